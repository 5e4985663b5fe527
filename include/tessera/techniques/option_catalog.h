// The technique options as data: every key a technique accepts in a scene file's "options" (or
// `tessera render --option KEY=VALUE`), its values, the faithful default, the correction and the
// ERRATA.md row it belongs to, and one line of meaning. `tessera options` prints it; the CLI
// checks --option against it before loading anything; a test holds it equal to the parsers.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

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
};

// The option tables of the built-in techniques (empty for an id without one): each registry row's
// TechniqueInfo::options (technique.h, which also answers techniqueOptions and findOption for
// every registered technique).
std::span<const OptionInfo> builtinOptionCatalog(std::string_view id);

// Why `value` is not a value of `option` ("'x' is not one of a, b"), or nullopt when it is.
std::optional<std::string> optionValueProblem(const OptionInfo& option, const nlohmann::json& value);

// "demo-gl | d3d", "false | true", "integer >= 1 | unbounded": the accepted values as one line.
std::string optionValuesText(const OptionInfo& option);

} // namespace tessera
