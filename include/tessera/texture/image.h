// A decoded image as a texture's source: 8-bit RGBA texels (images with fewer channels are
// expanded: grey g -> (g,g,g,1), grey+alpha -> (g,g,g,a), RGB -> (r,g,b,1)), row 0 at the top.
// Whether the bytes are sRGB-encoded is a property of the texture that uses the image.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tessera {

struct Image {
    std::uint32_t width = 0, height = 0;  // texels, 1..16384 each once loaded
    std::vector<std::uint8_t> rgba8;      // width * height * 4 bytes, row-major, row 0 at the top
    std::string source;                   // file path or "<gltf>#/images/N" for embedded data (for messages)
};

} // namespace tessera
