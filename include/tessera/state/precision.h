// The precision modes (README.md, "Precision modes"): reference (double, no storage quantization), exact
// (binary32, the sources' formats, bit for bit; the default) and fast (measured approximations).
#pragma once

#include <optional>
#include <string_view>

namespace tessera {

enum class Precision { Reference, Exact, Fast };

constexpr std::string_view precisionName(Precision p) {
    return p == Precision::Reference ? "reference" : p == Precision::Exact ? "exact" : "fast";
}
constexpr std::optional<Precision> parsePrecision(std::string_view s) {
    if (s == "reference") return Precision::Reference;
    if (s == "exact") return Precision::Exact;
    if (s == "fast") return Precision::Fast;
    return std::nullopt;
}

} // namespace tessera
