// `tessera list`: the techniques (id, MSAA, summary, source) and the bundled scenes (each scene
// file's size, technique and lights, then the first sentence of its "description").
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

// The description's first sentence: it ends at ". " before a capital letter, so that "GPU Pro 4
// ch. 5's" or "e.g. the" do not end it. Cut at a word after kMaxSummaryChars.
constexpr std::size_t kMaxSummaryChars = 160;  // characters of a scene's line in the listing
std::string firstSentence(const std::string& text) {
    std::string sentence = text;
    for (std::size_t at = text.find(". "); at != std::string::npos; at = text.find(". ", at + 1)) {
        const std::size_t next = at + 2;
        if (next < text.size() && text[next] >= 'A' && text[next] <= 'Z') {
            sentence = text.substr(0, at + 1);
            break;
        }
    }
    if (sentence.size() <= kMaxSummaryChars) return sentence;
    const std::size_t space = sentence.rfind(' ', kMaxSummaryChars);
    return sentence.substr(0, space == std::string::npos ? kMaxSummaryChars : space) + " ...";
}

// What sets a scene file apart at a glance: its size, technique and lights (explicit ones, and
// each generator's count and range), from the file's own keys.
std::string sceneFacts(const nlohmann::json& j) {
    std::string facts;
    const auto add = [&facts](const std::string& part) { facts += (facts.empty() ? "" : ", ") + part; };
    const auto number = [](const nlohmann::json& v) { return v.dump(); };  // as written in the file
    if (j.contains("resolution") && j["resolution"].is_array() && j["resolution"].size() == 2)
        add(number(j["resolution"][0]) + "x" + number(j["resolution"][1]));
    if (j.contains("technique") && j["technique"].is_string()) add(j["technique"].get<std::string>());
    if (j.contains("lights") && j["lights"].is_array())
        add(std::to_string(j["lights"].size()) + (j["lights"].size() == 1 ? " light" : " lights"));
    if (j.contains("generate") && j["generate"].is_array())
        for (const nlohmann::json& g : j["generate"]) {
            if (!g.is_object() || !g.contains("count")) continue;
            std::string part = number(g["count"]) + " generated lights";
            if (g.contains("range") && g["range"].is_array() && g["range"].size() == 2)
                part += " of range " + number(g["range"][0]) + ".." + number(g["range"][1]);
            add(part);
        }
    return facts;
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
            description = sceneFacts(j);
            if (j.contains("description") && j["description"].is_string())
                description += (description.empty() ? "" : ": ") + firstSentence(j["description"].get<std::string>());
        } catch (const std::exception&) {
            description = "(not valid JSON)";
        }
        std::printf("  %-22s %s\n", f.stem().string().c_str(), description.c_str());
    }
    return 0;
}

} // namespace tessera::cli
