// The technique options as data: every key a technique accepts in a scene file's "options" (or
// `tessera render --option KEY=VALUE`), its values, the faithful default, the correction and the
// ERRATA.md row it belongs to, and one line of meaning. Each technique declares its table in its own
// header (kForwardOptions, ...) and reads it through OptionReader (technique_options.h), so a key's
// values and default are written once; the options shared by several techniques are declared here.
// `tessera options` prints the tables; the CLI checks --option against them before loading anything.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace tessera {

struct OptionInfo {
    enum class Kind : std::uint8_t {
        Word,          // one of `values` as a JSON string
        Bool,          // true or false
        Integer,       // one of `values` (integers), or any integer >= minInteger when minInteger >= 0
        IntegerOrWord, // an integer >= minInteger, or one of `values` as a JSON string
        Number         // a JSON number in [minNumber, maxNumber]
    };
    std::string_view key;
    Kind kind = Kind::Word;
    std::span<const std::string_view> values;  // the words or integers (as text) accepted
    std::int64_t minInteger = -1;               // Integer / IntegerOrWord: the lower bound, -1 none
    std::string_view faithful;                  // the default, as a user writes it
    std::string_view corrected;                 // the correcting value; empty when the option corrects nothing
    int erratum = 0;                            // ERRATA.md row; 0 when none
    std::string_view meaning;                   // one line
    double minNumber = 0.0, maxNumber = 0.0;    // Number: the closed range accepted
    std::int64_t maxInteger = std::numeric_limits<std::int64_t>::max();  // Integer / IntegerOrWord with minInteger >= 0: the upper bound
};

// Values and options that several techniques share (each technique's own are in its header).
namespace option_values {
inline constexpr std::array<std::string_view, 2> kBool{"false", "true"};
inline constexpr std::array<std::string_view, 2> kProjection{"demo-gl", "d3d"};
inline constexpr std::array<std::string_view, 2> kSampler{"demo", "gltf"};
inline constexpr std::array<std::string_view, 3> kTileSize{"16", "8", "32"};
inline constexpr std::array<std::string_view, 2> kGBuffer{"demo", "float"};
inline constexpr std::array<std::string_view, 2> kPosition{"reconstruct", "gbuffer"};
inline constexpr std::array<std::string_view, 3> kEdgesPrc{"coverage", "depthNormal", "all"};
inline constexpr std::array<std::string_view, 3> kEdgesIntel{"depthNormal", "coverage", "all"};
inline constexpr std::array<std::string_view, 0> kNone{};
} // namespace option_values

inline constexpr OptionInfo kProjectionOption{"projection", OptionInfo::Kind::Word, option_values::kProjection, -1,
                                              "demo-gl", "d3d", 1,
                                              "the demo's OpenGL-form perspective under D3D clipping (near plane at "
                                              "0.19998), or perspectiveRH_ZO"};
inline constexpr OptionInfo kSamplerOption{"sampler", OptionInfo::Kind::Word, option_values::kSampler, -1, "demo", "", 0,
                                           "the demo's trilinear wrap sampler for every texture, or each texture's glTF "
                                           "sampler"};
inline constexpr OptionInfo kAlphaTestOption{"alphaTest", OptionInfo::Kind::Bool, option_values::kBool, -1, "false", "true",
                                             2,
                                             "discard where alpha * Opacity < AlphaThreshold in the forward-shaded pass, "
                                             "which the demo's forward PS never does"};
inline constexpr OptionInfo kTileSizeOption{"tileSize", OptionInfo::Kind::Integer, option_values::kTileSize, -1, "16", "",
                                            0, "tile edge in px, one thread group per tile (BLOCK_SIZE)"};
// With --msaa N: which pixels the light passes shade per sample (techniques/msaa_deferred.h).
inline constexpr OptionInfo kEdgesPrcOption{"msaaEdges", OptionInfo::Kind::Word, option_values::kEdgesPrc, -1, "coverage",
                                            "", 0,
                                            "MSAA: per-sample shading where a triangle covered the pixel partly (Listing "
                                            "11.17), where depth or normal differ (Intel 2010), or everywhere"};
inline constexpr OptionInfo kEdgesIntelOption{"msaaEdges", OptionInfo::Kind::Word, option_values::kEdgesIntel, -1,
                                              "depthNormal", "", 0,
                                              "MSAA: per-sample shading where depth or normal differ (Intel 2010), where "
                                              "a triangle covered the pixel partly (PR&C Listing 11.17), or everywhere"};

// A table's options and one more (deferred-killzone: deferred's and its threshold).
template <std::size_t N>
constexpr std::array<OptionInfo, N + 1> withOption(const std::array<OptionInfo, N>& base, const OptionInfo& extra) {
    std::array<OptionInfo, N + 1> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = base[i];
    out[N] = extra;
    return out;
}

// Why `value` is not a value of `option` ("'x' is not one of a, b"), or nullopt when it is.
std::optional<std::string> optionValueProblem(const OptionInfo& option, const nlohmann::json& value);

// An option of a table left at its faithful value where an erratum's correction would change it:
// the option and the value in effect (its faithful default's first word).
struct FaithfulChoice {
    const OptionInfo* option = nullptr;
    std::string value;
};
// The options of `table` with an erratum and a correction that `options` (the run's JSON options)
// leaves at the faithful value, in table order. A default that follows another option (its first
// word equals the correction, as forward-plus-amd's projection) is left out. The render note and
// the report's "why" column both read this.
std::vector<FaithfulChoice> faithfulChoices(std::span<const OptionInfo> table, const nlohmann::json& options);

// "demo-gl | d3d", "false | true", "integer >= 1 | unbounded", "integer in 1..4096": the accepted values as one line.
std::string optionValuesText(const OptionInfo& option);

} // namespace tessera
