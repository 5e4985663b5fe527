// A guard against JSON nested deep enough to overflow the stack: recursive parsers, copies and
// checks (nlohmann's copy constructor, tinygltf's parse) recurse once per level, so the nesting
// depth is counted on the raw bytes, with an explicit loop and no recursion, before any of them runs.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace tessera {

// The deepest nesting of arrays and objects accepted in scene and glTF JSON, in levels (the root
// object is level 1). Real files stay far below it: glTF's deepest schema path is 6 levels.
constexpr std::size_t kMaxJsonDepth = 256;

// Byte offset of the first '[' or '{' that opens level maxDepth + 1, or nullopt when the text
// stays within maxDepth. Brackets inside strings (escapes honoured) do not count; malformed text
// is left to the parser.
std::optional<std::size_t> findJsonDepthExcess(std::string_view text, std::size_t maxDepth = kMaxJsonDepth);

// Throws InputError "FILE: JSON nested deeper than 256 levels (at byte N)" when the text exceeds
// kMaxJsonDepth.
void checkJsonDepth(std::string_view text, const std::string& file);

} // namespace tessera
