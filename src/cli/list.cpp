// `tessera list`: the techniques (id, MSAA, summary, source) and the bundled scenes (each scene
// file's first sentence of "description").
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <tessera/io/json_depth.h>
#include <tessera/techniques/technique.h>

#include "commands.h"
#include "scene_args.h"

namespace tessera::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kListUsage = R"(usage: tessera list

Lists the techniques (with their source and whether they are implemented) and the bundled
scenes (scene files in the scenes folder; TESSERA_SCENES overrides where that is).
)";

std::string firstSentence(const std::string& text) {
    const std::size_t end = text.find(". ");
    return end == std::string::npos ? text : text.substr(0, end + 1);
}

} // namespace

int listCommand(const std::vector<std::string_view>& args) {
    for (const std::string_view a : args) {
        if (a == "--help" || a == "-h") {
            std::fputs(kListUsage, stdout);
            return 0;
        }
        throw UsageError("list takes no arguments, got '" + std::string(a) + "'");
    }
    std::puts("techniques:");
    for (const tessera::TechniqueInfo& t : tessera::techniques())
        std::printf("  %-18s %-12s %s [%s]\n", std::string(t.id).c_str(), !t.build ? "planned" : t.msaa ? "ready, MSAA" : "ready",
                    std::string(t.summary).c_str(), std::string(t.source).c_str());
    const fs::path dir = bundledScenesDir();
    std::printf("bundled scenes (%s):\n", dir.string().c_str());
    std::printf("  %-22s %s\n", "builtin", "generated cubes and a blended pane (no files, no lights)");
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".json" && e.path().filename() != "scene.schema.json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
        std::string description;
        try {
            std::ifstream in(f, std::ios::binary);
            const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            tessera::checkJsonDepth(text, f.string());
            const nlohmann::json j = nlohmann::json::parse(text);
            if (j.contains("description") && j["description"].is_string()) description = firstSentence(j["description"].get<std::string>());
        } catch (const std::exception&) {
            description = "(not valid JSON)";
        }
        std::printf("  %-22s %s\n", f.stem().string().c_str(), description.c_str());
    }
    return 0;
}

} // namespace tessera::cli
