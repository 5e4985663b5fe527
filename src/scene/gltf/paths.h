// Path helpers the glTF loader shares: the JSON pointers its messages name ("/accessors/3"), and
// uris with their %XX escapes decoded (to match the files tinygltf opens).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace tessera::gltf_detail {

// `base` + "/" + index: the JSON pointer of an array element.
std::string indexPath(std::string_view base, std::size_t index);

// A uri with its %XX escapes decoded (as tinygltf does before opening the file).
std::string percentDecoded(const std::string& uri);

} // namespace tessera::gltf_detail
