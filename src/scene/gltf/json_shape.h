// The JSON types of the glTF properties the loader reads, checked before tinygltf parses the
// file (tinygltf silently replaces a mistyped value by its default).
#pragma once

#include <string>

#include <nlohmann/json_fwd.hpp>

namespace tessera::gltf_detail {

// Throws InputError "file: /json/pointer: what" at the first property whose JSON type is wrong
// (json_shape.cpp lists them), or for an asset version this loader does not read.
void checkJsonShape(const nlohmann::json& root, const std::string& file);

} // namespace tessera::gltf_detail
