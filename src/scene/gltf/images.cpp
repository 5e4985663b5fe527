// glTF images: the format from magic bytes / mimeType / uri, a PNG's chunk walk before decoding,
// decoding to RGBA8 through OpenImageIO (or stb_image), and tinygltf's image callback.
// "§" numbers cite the glTF 2.0 specification.
#include "images.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#ifdef TESSERA_NO_OIIO
#include <stb/stb_image.h>
#else
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif
#include <tiny_gltf.h>

namespace tessera::gltf_detail {
namespace {

namespace fs = std::filesystem;

constexpr int MAX_IMAGE_EXTENT = 16384;  // Image: 1..16384 texels per axis

// The file extension OIIO should decode the bytes as: from the magic bytes first, then the
// mime type, then the uri's extension. Empty when none of them names a known format.
std::string imageExtension(const unsigned char* bytes, std::size_t size, const std::string& mimeType,
                           const std::string& uri) {
    auto startsWith = [&](std::string_view magic) {
        return size >= magic.size() && std::memcmp(bytes, magic.data(), magic.size()) == 0;
    };
    if (startsWith("\x89PNG")) return ".png";
    if (startsWith("\xFF\xD8\xFF")) return ".jpg";
    if (startsWith("GIF8")) return ".gif";
    if (startsWith("BM")) return ".bmp";
    if (startsWith("DDS ")) return ".dds";
    if (size >= 12 && startsWith("RIFF") && std::memcmp(bytes + 8, "WEBP", 4) == 0) return ".webp";
    if (mimeType == "image/png") return ".png";
    if (mimeType == "image/jpeg") return ".jpg";
    if (mimeType == "image/webp") return ".webp";
    if (mimeType == "image/bmp") return ".bmp";
    if (mimeType == "image/gif") return ".gif";
    std::string extension = fs::path(uri).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](char c) { return char(std::tolower(static_cast<unsigned char>(c))); });
    return extension;
}

// A PNG's chunk sequence (PNG 1.2 §5.3: 4-byte big-endian length, type, data, CRC) walked up to
// IEND without decoding anything, before OpenImageIO sees the data:
// - data that ends inside a chunk is refused: OpenImageIO 2.4's PNG reader leaks its error
//   message when libpng asks for bytes past the end (its read callback formats the error, then
//   libpng's longjmp skips the string's destructor);
// - an image whose IDAT bytes cannot hold its IHDR size is refused: the decoder allocates the
//   whole image from the header before inflating, so a 100-byte PNG claiming 16384 x 16384
//   texels cost 1 GiB. Deflate expands at most 1032:1 (RFC 1951: a 258-byte match per 2 bits),
//   so a real PNG never fails this test.
// Returns an empty string when the data passes.
std::string pngProblem(const unsigned char* bytes, std::size_t size) {
    auto be32 = [&](std::size_t at) {
        return (std::uint32_t(bytes[at]) << 24) | (std::uint32_t(bytes[at + 1]) << 16) | (std::uint32_t(bytes[at + 2]) << 8) |
               std::uint32_t(bytes[at + 3]);
    };
    std::uint64_t pixelBits = 0, idatBytes = 0;  // from IHDR: width x height x bits per texel
    std::size_t at = 8;  // after the signature
    while (true) {
        if (size - at < 12) return "the PNG data ends inside a chunk header (at byte " + std::to_string(at) + " of " + std::to_string(size) + ")";
        const std::uint32_t length = be32(at);
        if (length > size - at - 12)
            return "the PNG data ends inside a chunk (a " + std::to_string(length) + "-byte chunk at byte " +
                   std::to_string(at) + " of " + std::to_string(size) + ")";
        const unsigned char* type = bytes + at + 4;
        if (std::memcmp(type, "IHDR", 4) == 0 && length >= 13) {
            const unsigned char* ihdr = bytes + at + 8;
            const std::uint64_t width = be32(at + 8), height = be32(at + 12), bitDepth = ihdr[8];
            const std::uint64_t channels = ihdr[9] == 2 ? 3 : ihdr[9] == 4 ? 2 : ihdr[9] == 6 ? 4 : 1;  // grey, palette: 1
            // Sizes outside 1..16384 are left to the size check after OpenImageIO reads the header.
            if (width <= std::uint64_t(MAX_IMAGE_EXTENT) && height <= std::uint64_t(MAX_IMAGE_EXTENT))
                pixelBits = width * height * channels * bitDepth;
        }
        if (std::memcmp(type, "IDAT", 4) == 0) idatBytes += length;
        if (std::memcmp(type, "IEND", 4) == 0) break;
        at += 12 + std::size_t(length);
    }
    constexpr std::uint64_t kMaxDeflateRatio = 1032;
    if (pixelBits / 8 > kMaxDeflateRatio * idatBytes + 1024)
        return "the PNG's " + std::to_string(idatBytes) + " bytes of image data cannot hold the " + std::to_string(pixelBits / 8) +
               " bytes its header announces (deflate expands at most 1032:1)";
    return {};
}

} // namespace


// Decodes an image held in memory into RGBA8 (grey, grey+alpha and RGB expanded as Image
// documents; 16-bit and float channels converted by OIIO to UINT8). headerOnly: only the size.
// Returns an empty string on success, else what went wrong.
std::string decodeImage(const unsigned char* bytes, std::size_t size, const std::string& mimeType,
                        const std::string& uri, bool headerOnly, Image& image) {
    if (size == 0) return "the image data is empty";
    const std::string extension = imageExtension(bytes, size, mimeType, uri);
    if (extension.empty()) return "unknown image format (mimeType '" + mimeType + "')";
    if (extension == ".png") {
        if (size < 8 || std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) != 0) return "the data is not a PNG (no PNG signature)";
        if (std::string problem = pngProblem(bytes, size); !problem.empty()) return problem;
    }
#ifdef TESSERA_NO_OIIO
    // Benchmark builds without OpenImageIO (TESSERA_WITH_OIIO=OFF): stb_image, which expands
    // grey / grey+alpha / RGB to RGBA the same way. PNG texels are identical; JPEG may differ.
    if (size > std::size_t(std::numeric_limits<int>::max())) return "the image data is larger than 2 GiB";
    int width = 0, height = 0, channelsInFile = 0;
    if (!stbi_info_from_memory(bytes, int(size), &width, &height, &channelsInFile))
        return "cannot decode the image as " + extension.substr(1) + ": " + stbi_failure_reason();
    if (width < 1 || height < 1 || width > MAX_IMAGE_EXTENT || height > MAX_IMAGE_EXTENT)
        return std::to_string(width) + " x " + std::to_string(height) + " texels is outside 1..16384 per axis";
    image.width = std::uint32_t(width);
    image.height = std::uint32_t(height);
    if (headerOnly) return {};
    stbi_uc* texels = stbi_load_from_memory(bytes, int(size), &width, &height, &channelsInFile, 4);
    if (!texels) return std::string("cannot decode the image: ") + stbi_failure_reason();
    image.rgba8.assign(texels, texels + std::size_t(image.width) * image.height * 4);
    stbi_image_free(texels);
    return {};
#else
    OIIO::Filesystem::IOMemReader reader(bytes, size);
    void* proxy = &reader;
    OIIO::ImageSpec config;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    config.attribute("oiio:UnassociatedAlpha", 1);  // glTF colour is not premultiplied (§3.9.4)
    auto input = OIIO::ImageInput::open("image" + extension, &config);
    if (!input) {
        std::string why = OIIO::geterror();
        while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
        return "cannot decode the image as " + extension.substr(1) + ": " + why;
    }
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width < 1 || spec.height < 1 || spec.width > MAX_IMAGE_EXTENT || spec.height > MAX_IMAGE_EXTENT ||
        spec.depth != 1) {
        return std::to_string(spec.width) + " x " + std::to_string(spec.height) +
               " texels is outside 1..16384 per axis";
    }
    if (spec.nchannels < 1) return "the image has no channels";
    image.width = std::uint32_t(spec.width);
    image.height = std::uint32_t(spec.height);
    if (headerOnly) return {};
    const int channels = std::min(spec.nchannels, 4);
    const std::size_t texels = std::size_t(image.width) * image.height;
    // An 8-bit file with at most 4 channels (every PNG and JPEG texture in practice) is read in its
    // native layout: asking OpenImageIO 2.4 for a type, even the file's own, sends
    // ImageInput::read_scanlines through a staging buffer of the whole image, allocated and freed per
    // image (under AddressSanitizer a fresh mapping each time: a third of loading Sponza). The bytes
    // are the same: UINT8 to UINT8 is a copy.
    const bool native8 = spec.format == OIIO::TypeDesc::UINT8 && spec.channelformats.empty() && spec.nchannels == channels;
    const OIIO::TypeDesc type = native8 ? OIIO::TypeDesc(OIIO::TypeDesc::UNKNOWN) : OIIO::TypeDesc(OIIO::TypeDesc::UINT8);
    // One buffer: the file's c channels land at the front of rgba8 and are widened to RGBA in place,
    // from the last texel back. Texel i is copied out before it is written, and the texels below it
    // lie below byte c * i <= 4 * i, which no write of texel i or above reaches.
    image.rgba8.resize(texels * 4);
    if (!input->read_image(0, 0, 0, channels, type, image.rgba8.data())) {
        image.rgba8.clear();
        return "cannot decode the image: " + input->geterror();
    }
    if (channels < 4) {
        for (std::size_t i = texels; i-- > 0;) {
            std::uint8_t in[3];
            std::memcpy(in, &image.rgba8[i * std::size_t(channels)], std::size_t(channels));
            std::uint8_t* out = &image.rgba8[i * 4];
            switch (channels) {
            case 1: out[0] = out[1] = out[2] = in[0]; out[3] = 255; break;
            case 2: out[0] = out[1] = out[2] = in[0]; out[3] = in[1]; break;
            default: out[0] = in[0]; out[1] = in[1]; out[2] = in[2]; out[3] = 255; break;
            }
        }
    }
    return {};
#endif
}

// tinygltf's LoadImageDataFunction. Images in bufferViews are left alone here: tinygltf hands
// them over without checking the bufferView against its buffer, so they are decoded later,
// after that check. With loadImages == false only the header is read (for the size).
bool loadImageData(tinygltf::Image* image, const int imageIndex, std::string* err, std::string* /*warn*/,
                   int /*reqWidth*/, int /*reqHeight*/, const unsigned char* bytes, int size, void* userData) {
    auto& state = *static_cast<ImageLoaderState*>(userData);
    if (image->bufferView >= 0) return true;
    // Only the header here (size and format checks); the encoded bytes are kept and decoded
    // later by readImages, all images in parallel.
    Image header;
    const std::string problem =
        decodeImage(bytes, size > 0 ? std::size_t(size) : 0, image->mimeType, image->uri, true, header);
    if (!problem.empty()) {
        state.errors.emplace_back(imageIndex, problem);
        if (err) *err += problem + "\n";
        return false;
    }
    image->width = int(header.width);
    image->height = int(header.height);
    image->component = 4;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    if (state.loadImages) image->image.assign(bytes, bytes + size);  // still encoded (PNG, JPEG)
    return true;
}

} // namespace tessera::gltf_detail
