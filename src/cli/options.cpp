// `tessera options [TECHNIQUE] [--json]`: the registry's option catalogue (techniques/technique.h,
// option_catalog.h) as text, each option's values, faithful default, correction and ERRATA.md row;
// or, with --json, the whole registry for scripts (bench/sweep.py takes its techniques and knobs
// from it instead of lists of its own).
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include <tessera/techniques/option_catalog.h>
#include <tessera/techniques/technique.h>

#include "commands.h"
#include "render_args.h"

namespace tessera::cli {
namespace {

constexpr const char* kOptionsUsage = R"(usage: tessera options [TECHNIQUE] [--json]

Lists the options each technique accepts (in a scene file's "options" object, or with
`tessera render --option KEY=VALUE`): the values, the default (faithful to the source), the
correcting value where the option corrects an erratum, the ERRATA.md row, and what it changes.
--json prints the technique registry instead: per technique its id, source, whether it is
ready, renders MSAA, is the comparison baseline or an inspection view, its pass captions and
its options (key, kind, values, minimum, range, faithful, corrected, erratum, meaning).
)";

} // namespace

int optionsCommand(const std::vector<std::string_view>& args) {
    std::string only;
    bool json = false;
    for (const std::string_view a : args) {
        if (a == "--help" || a == "-h") {
            std::fputs(kOptionsUsage, stdout);
            return 0;
        }
        if (a == "--json") {
            json = true;
            continue;
        }
        if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + std::string(a) + "' (see tessera options --help)");
        if (!only.empty()) throw UsageError("options takes one TECHNIQUE at most");
        only = std::string(a);
        if (!tessera::findTechnique(only)) {
            std::string ids;
            for (const tessera::TechniqueInfo& t : tessera::techniques()) ids += (ids.empty() ? "" : ", ") + std::string(t.id);
            throw UsageError("options: unknown technique '" + only + "' (one of " + ids + ")");
        }
    }
    if (json) {
        std::printf("%s\n", tessera::techniqueRegistryJson(only).dump(2).c_str());
        return 0;
    }
    bool first = true;
    for (const tessera::TechniqueInfo& t : tessera::techniques()) {
        if (!only.empty() && t.id != only) continue;
        if (!first) std::puts("");
        first = false;
        const auto list = tessera::techniqueOptions(t.id);
        std::printf("%s%s\n", std::string(t.id).c_str(),
                    !t.build ? " (planned)" : list.empty() ? ": no options" : "");
        for (const tessera::OptionInfo& option : list) {
            std::printf("  %-17s %s\n", std::string(option.key).c_str(), tessera::optionValuesText(option).c_str());
            std::printf("  %-17s default %s", "", std::string(option.faithful).c_str());
            if (!option.corrected.empty()) std::printf("; correction %s", std::string(option.corrected).c_str());
            if (option.erratum != 0) std::printf("; ERRATA.md #%d", option.erratum);
            std::printf("\n  %-17s %s\n", "", std::string(option.meaning).c_str());
        }
    }
    return 0;
}

} // namespace tessera::cli
