// The JSON nesting-depth pre-scan: one pass over the bytes counting '[' / '{' against ']' / '}'
// outside strings (a backslash skips the next byte inside a string), no recursion.
#include <tessera/io/json_depth.h>

#include <tessera/errors/input_error.h>

namespace tessera {

std::optional<std::size_t> findJsonDepthExcess(std::string_view text, std::size_t maxDepth) {
    std::size_t depth = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') ++i;  // the escaped byte (", \, /, b, f, n, r, t or the u of \uXXXX)
            else if (c == '"') inString = false;
            continue;
        }
        if (c == '"') inString = true;
        else if (c == '[' || c == '{') {
            if (++depth > maxDepth) return i;
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return std::nullopt;
}

void checkJsonDepth(std::string_view text, const std::string& file) {
    if (const auto at = findJsonDepthExcess(text))
        throw inputError(file, "", "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels (at byte " +
                                       std::to_string(*at) + "); refusing to parse it");
}

} // namespace tessera
