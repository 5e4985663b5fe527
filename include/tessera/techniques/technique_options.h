// Reading a technique's "options" (the scene file's JSON object) through its option table
// (techniques/option_catalog.h): each read returns the value given or the table's faithful default,
// checked by the table's own rule (optionValueProblem), so a key's values and default are written
// once, in the table. A bad value is an InputError naming the file and "/options/KEY"; unknown keys
// are rejected earlier, by buildTechnique. Reading a key the table lacks, or comparing with a word it
// does not list, is a programming error (std::logic_error), which every technique's tests reach.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include <tessera/techniques/option_catalog.h>

namespace tessera {

class OptionReader {
public:
    // `options` (a JSON object, or null for none) read against `table`; `file` names the scene file
    // in errors. The reader keeps references: both must outlive it.
    OptionReader(const nlohmann::json& options, std::span<const OptionInfo> table, std::string file);

    // Whether the options give `key` (its value is checked either way when read).
    bool given(std::string_view key) const;
    // A Word option (or an IntegerOrWord given as a word): the word given, else the default.
    std::string word(std::string_view key) const;
    // Whether the option's word (given or default) is `value`, which must be one of its words
    // (false for an IntegerOrWord given as an integer).
    bool is(std::string_view key, std::string_view value) const;
    // A Bool option.
    bool flag(std::string_view key) const;
    // A Number option.
    double number(std::string_view key) const;
    // An Integer option, or an IntegerOrWord given as an integer (unsigned values past INT64_MAX
    // read as INT64_MAX).
    std::int64_t integer(std::string_view key) const;

private:
    const OptionInfo& info(std::string_view key) const;
    // The value given, checked against the table; nullptr when absent.
    const nlohmann::json* checked(const OptionInfo& option) const;
    // The table's default as JSON (std::logic_error when it is not one of the option's values).
    nlohmann::json fallback(const OptionInfo& option) const;
    nlohmann::json read(std::string_view key) const;

    const nlohmann::json& options_;
    std::span<const OptionInfo> table_;
    std::string file_;
};

} // namespace tessera
