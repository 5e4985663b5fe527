// The option catalogue's checks (techniques/option_catalog.h): whether a JSON value is a value of an
// option, and its values as one line of text. The tables are in each technique's header.
#include <tessera/techniques/option_catalog.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

namespace tessera {
namespace {

using Kind = OptionInfo::Kind;

bool listed(const OptionInfo& option, std::string_view text) {
    for (const std::string_view v : option.values)
        if (v == text) return true;
    return false;
}

} // namespace

std::vector<FaithfulChoice> faithfulChoices(std::span<const OptionInfo> table, const nlohmann::json& options) {
    std::vector<FaithfulChoice> out;
    for (const OptionInfo& option : table) {
        if (option.erratum == 0 || option.corrected.empty()) continue;
        const std::string faithful(option.faithful.substr(0, option.faithful.find(' ')));
        if (faithful == option.corrected) continue;
        std::string value = faithful;
        if (options.is_object())
            if (const auto it = options.find(std::string(option.key)); it != options.end())
                value = it->is_string() ? it->get<std::string>() : it->dump();
        if (value == faithful) out.push_back({&option, value});
    }
    return out;
}

std::string optionValuesText(const OptionInfo& option) {
    if (option.kind == Kind::Number)
        return "number in [" + nlohmann::json(option.minNumber).dump() + ", " + nlohmann::json(option.maxNumber).dump() + "]";
    std::string text;
    if (option.minInteger >= 0) {
        text = option.maxInteger == std::numeric_limits<std::int64_t>::max()
                   ? "integer >= " + std::to_string(option.minInteger)
                   : "integer in " + std::to_string(option.minInteger) + ".." + std::to_string(option.maxInteger);
    }
    for (const std::string_view v : option.values) {
        if (!text.empty()) text += " | ";
        text += v;
    }
    return text;
}

std::optional<std::string> optionValueProblem(const OptionInfo& option, const nlohmann::json& value) {
    const std::string expected = optionValuesText(option);
    const std::string given = value.dump();
    switch (option.kind) {
    case Kind::Bool:
        if (value.is_boolean()) return std::nullopt;
        break;
    case Kind::Number:
        if (value.is_number() && value.get<double>() >= option.minNumber && value.get<double>() <= option.maxNumber)
            return std::nullopt;
        return given + " is not a " + expected;
    case Kind::Word:
        if (value.is_string() && listed(option, value.get<std::string>())) return std::nullopt;
        break;
    case Kind::IntegerOrWord:
        if (value.is_string() && listed(option, value.get<std::string>())) return std::nullopt;
        [[fallthrough]];
    case Kind::Integer:
        if (value.is_number_integer()) {
            const std::int64_t n = value.is_number_unsigned() ? std::int64_t(std::min<std::uint64_t>(value.get<std::uint64_t>(), INT64_MAX))
                                                              : value.get<std::int64_t>();
            if (option.minInteger >= 0 && n >= option.minInteger && n <= option.maxInteger) return std::nullopt;
            if (option.kind == Kind::Integer && listed(option, std::to_string(n))) return std::nullopt;
        }
        break;
    }
    return given + " is not " + (option.values.size() + (option.minInteger >= 0 ? 1 : 0) > 1 ? "one of " : "") + expected;
}

} // namespace tessera
