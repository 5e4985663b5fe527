// Technique option helpers (include/tessera/techniques/technique_options.h): one key each, with
// errors that name the file and the JSON pointer "/options/KEY".
#include <tessera/techniques/technique_options.h>

#include <cmath>
#include <string>

#include <tessera/errors/input_error.h>

namespace tessera {
namespace {

std::string keyPath(std::string_view key) {
    std::string path = "/options/";
    path += key;
    return path;
}

const nlohmann::json* find(const nlohmann::json& options, std::string_view key) {
    if (!options.is_object()) return nullptr;
    const auto it = options.find(std::string(key));
    return it == options.end() ? nullptr : &*it;
}

} // namespace

std::string optionEnum(const nlohmann::json& options, std::string_view key, std::initializer_list<std::string_view> allowed,
                       std::string_view fallback, const std::string& file) {
    const nlohmann::json* value = find(options, key);
    if (!value) return std::string(fallback);
    std::string list;
    for (const std::string_view a : allowed) {
        if (!list.empty()) list += ", ";
        list += a;
    }
    if (!value->is_string()) {
        std::string what = "expected a string (one of ";
        what += list;
        what += ')';
        throw inputError(file, keyPath(key), what);
    }
    const std::string text = value->get<std::string>();
    for (const std::string_view a : allowed)
        if (text == a) return text;
    std::string what = "'";
    what += text;
    what += "' is not one of ";
    what += list;
    throw inputError(file, keyPath(key), what);
}

bool optionBool(const nlohmann::json& options, std::string_view key, bool fallback, const std::string& file) {
    const nlohmann::json* value = find(options, key);
    if (!value) return fallback;
    if (!value->is_boolean()) throw inputError(file, keyPath(key), "expected true or false");
    return value->get<bool>();
}

double optionNumber(const nlohmann::json& options, std::string_view key, double fallback, double lo, double hi,
                    const std::string& file) {
    const nlohmann::json* value = find(options, key);
    if (!value) return fallback;
    // Built with += (GCC 12's -Wrestrict misfires on chains of std::string operator+ here).
    std::string range = "[";
    range += nlohmann::json(lo).dump();
    range += ", ";
    range += nlohmann::json(hi).dump();
    range += ']';
    if (!value->is_number()) throw inputError(file, keyPath(key), "expected a number in " + range);
    const double v = value->get<double>();
    if (!(v >= lo && v <= hi)) {
        std::string what = value->dump();
        what += " is outside ";
        what += range;
        throw inputError(file, keyPath(key), what);
    }
    return v;
}

std::int64_t optionInteger(const nlohmann::json& options, std::string_view key, std::int64_t fallback, std::int64_t lo,
                           std::int64_t hi, const std::string& file) {
    const nlohmann::json* value = find(options, key);
    if (!value) return fallback;
    std::string range = std::to_string(lo);
    range += "..";
    range += std::to_string(hi);
    if (!value->is_number_integer()) throw inputError(file, keyPath(key), "expected an integer in " + range);
    const bool outside = value->is_number_unsigned() ? value->get<std::uint64_t>() > std::uint64_t(hi)
                                                     : (value->get<std::int64_t>() < lo || value->get<std::int64_t>() > hi);
    if (outside) {
        std::string what = value->dump();
        what += " is outside ";
        what += range;
        throw inputError(file, keyPath(key), what);
    }
    return value->get<std::int64_t>();
}

} // namespace tessera
