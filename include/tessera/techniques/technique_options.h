// Reading a technique's "options" (the scene file's JSON object) with clear errors: each helper
// returns the value of one key or its default, and throws InputError naming "/options/KEY" for
// a value of the wrong type or outside the allowed set. Unknown keys are rejected earlier, by
// buildTechnique, against TechniqueInfo::options.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace tessera {

// options[key] as one of `allowed` (a JSON string); `fallback` when the key is absent.
std::string optionEnum(const nlohmann::json& options, std::string_view key, std::initializer_list<std::string_view> allowed,
                       std::string_view fallback, const std::string& file);

// options[key] as a JSON boolean; `fallback` when the key is absent.
bool optionBool(const nlohmann::json& options, std::string_view key, bool fallback, const std::string& file);

// options[key] as a JSON number in [lo, hi]; `fallback` when the key is absent.
double optionNumber(const nlohmann::json& options, std::string_view key, double fallback, double lo, double hi,
                    const std::string& file);

// options[key] as a JSON integer in [lo, hi]; `fallback` when the key is absent.
std::int64_t optionInteger(const nlohmann::json& options, std::string_view key, std::int64_t fallback, std::int64_t lo,
                           std::int64_t hi, const std::string& file);

} // namespace tessera
