// OptionReader (include/tessera/techniques/technique_options.h): one key at a time, checked by the
// option table's rule, with errors that name the file and the JSON pointer "/options/KEY".
#include <tessera/techniques/technique_options.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include <tessera/errors/input_error.h>

namespace tessera {

OptionReader::OptionReader(const nlohmann::json& options, std::span<const OptionInfo> table, std::string file)
    : options_(options), table_(table), file_(std::move(file)) {}

const OptionInfo& OptionReader::info(std::string_view key) const {
    for (const OptionInfo& o : table_)
        if (o.key == key) return o;
    throw std::logic_error("OptionReader: '" + std::string(key) + "' is not in the technique's option table");
}

bool OptionReader::given(std::string_view key) const {
    (void)info(key);
    return options_.is_object() && options_.contains(std::string(key));
}

const nlohmann::json* OptionReader::checked(const OptionInfo& option) const {
    if (!options_.is_object()) return nullptr;
    const auto it = options_.find(std::string(option.key));
    if (it == options_.end()) return nullptr;
    if (const auto problem = optionValueProblem(option, *it)) {
        std::string path = "/options/";
        path += option.key;
        throw inputError(file_, path, *problem);
    }
    return &*it;
}

nlohmann::json OptionReader::fallback(const OptionInfo& option) const {
    const std::string text(option.faithful);
    nlohmann::json value;
    switch (option.kind) {
    case OptionInfo::Kind::Bool: value = text == "true"; break;
    case OptionInfo::Kind::Number: value = std::stod(text); break;
    case OptionInfo::Kind::Integer:
    case OptionInfo::Kind::IntegerOrWord:
        value = text.find_first_not_of("0123456789") == std::string::npos && !text.empty() ? nlohmann::json(std::stoll(text))
                                                                                           : nlohmann::json(text);
        break;
    case OptionInfo::Kind::Word: value = text; break;
    }
    if (optionValueProblem(option, value))
        throw std::logic_error("OptionReader: '" + std::string(option.key) + "' has no fixed default (" + text +
                               "); the technique must test given() and choose");
    return value;
}

nlohmann::json OptionReader::read(std::string_view key) const {
    const OptionInfo& option = info(key);
    if (const nlohmann::json* value = checked(option)) return *value;
    return fallback(option);
}

std::string OptionReader::word(std::string_view key) const {
    const nlohmann::json value = read(key);
    if (!value.is_string()) throw std::logic_error("OptionReader: '" + std::string(key) + "' read as a word");
    return value.get<std::string>();
}

bool OptionReader::is(std::string_view key, std::string_view value) const {
    const OptionInfo& option = info(key);
    if (std::find(option.values.begin(), option.values.end(), value) == option.values.end())
        throw std::logic_error("OptionReader: '" + std::string(value) + "' is not a value of '" + std::string(key) + "'");
    const nlohmann::json given = read(key);  // an IntegerOrWord given as an integer is no word
    return given.is_string() && given.get<std::string>() == value;
}

bool OptionReader::flag(std::string_view key) const {
    const nlohmann::json value = read(key);
    if (!value.is_boolean()) throw std::logic_error("OptionReader: '" + std::string(key) + "' read as a flag");
    return value.get<bool>();
}

double OptionReader::number(std::string_view key) const {
    const nlohmann::json value = read(key);
    if (!value.is_number()) throw std::logic_error("OptionReader: '" + std::string(key) + "' read as a number");
    return value.get<double>();
}

std::int64_t OptionReader::integer(std::string_view key) const {
    const nlohmann::json value = read(key);
    if (value.is_number_unsigned())
        return std::int64_t(std::min<std::uint64_t>(value.get<std::uint64_t>(), std::uint64_t(std::numeric_limits<std::int64_t>::max())));
    if (!value.is_number_integer()) throw std::logic_error("OptionReader: '" + std::string(key) + "' read as an integer");
    return value.get<std::int64_t>();
}

} // namespace tessera
