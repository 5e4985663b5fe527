// glTF images through OpenImageIO (stb_image where TESSERA_WITH_OIIO=OFF): decoding to RGBA8
// with size and PNG structure checks before the decoder sees the bytes, and the image callback
// tinygltf calls while it parses (header only; the reader decodes every image later).
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <tessera/texture/image.h>

namespace tinygltf {
struct Image;  // tiny_gltf.h
}

namespace tessera::gltf_detail {

// Decodes an image held in memory into RGBA8; headerOnly: only the size. Returns an empty string
// on success, else what went wrong (images.cpp).
std::string decodeImage(const unsigned char* bytes, std::size_t size, const std::string& mimeType,
                        const std::string& uri, bool headerOnly, Image& image);

struct ImageLoaderState {
    bool loadImages = true;
    std::vector<std::pair<int, std::string>> errors;  // (images index, message)
};

// tinygltf's LoadImageDataFunction; userData is an ImageLoaderState (images.cpp).
bool loadImageData(tinygltf::Image* image, const int imageIndex, std::string* err, std::string* warn,
                   int reqWidth, int reqHeight, const unsigned char* bytes, int size, void* userData);

} // namespace tessera::gltf_detail
