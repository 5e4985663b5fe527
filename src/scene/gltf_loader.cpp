// glTF 2.0 loader: tinygltf parses the JSON and the buffers, OpenImageIO decodes the images (as
// tinygltf's image callback), and this file checks every index, accessor range and value it
// reads while converting the file into tessera's Scene. Bad input throws InputError
// "FILE: /json/pointer: what"; "§" numbers cite the glTF 2.0 specification.
#include <tessera/scene/gltf_loader.h>

#include <algorithm>
#include <cctype>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <iomanip>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>
#include <glm/gtc/quaternion.hpp>

#ifdef TESSERA_NO_OIIO
#include <stb/stb_image.h>
#else
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif
#include <tiny_gltf.h>
#include <tbb/parallel_for.h>

#include <tessera/errors/input_error.h>
#include <tessera/io/json_depth.h>

namespace tessera {
namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t MAX_ACCESSOR_ELEMENTS = std::uint64_t(1) << 28;
// The accessor data one file may decode, in bytes of 32-bit values: 256 MiB plus 256 bytes per
// byte of its buffers. Data decoded from a buffer is at most 4 bytes per byte, but an accessor
// without a bufferView (zeros plus sparse values) is as large as its count says, and every
// primitive that uses an accessor decodes it again: without a budget, a 400-byte file asked for
// 3 GiB. Real files stay far below (256x covers one vertex buffer shared by 64 primitives).
constexpr std::uint64_t DECODE_BUDGET_BASE = std::uint64_t(256) << 20;
constexpr std::uint64_t DECODE_BUDGET_PER_BUFFER_BYTE = 256;
constexpr int MAX_IMAGE_EXTENT = 16384;  // Image: 1..16384 texels per axis
constexpr double PI = 3.14159265358979323846;

// Extensions this loader implements; any other one in extensionsRequired is an error.
constexpr std::array<std::string_view, 3> SUPPORTED_EXTENSIONS = {
    "KHR_lights_punctual", "KHR_mesh_quantization", "KHR_materials_emissive_strength"};

std::string indexPath(std::string_view base, std::size_t index) {
    return std::string(base) + "/" + std::to_string(index);
}

const char* componentTypeName(int componentType) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return "DOUBLE";
    default: return "an unknown component type";
    }
}

const char* accessorTypeName(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "an unknown type";
    }
}

// Bytes per component (§3.6.2.2); 0 for types glTF does not allow (INT, DOUBLE).
std::size_t componentSize(int componentType) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
    }
}

std::size_t componentCount(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4:
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
    }
}

// One component as float. Normalized integers follow §3.11 ("Animations", the table of
// normalized-integer decoding, also used by KHR_mesh_quantization): signed f = max(c / (2^(b-1) - 1), -1),
// unsigned f = c / (2^b - 1). Non-normalized integers convert to their value.
float decodeComponent(const unsigned char* p, int componentType, bool normalized) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        std::int8_t c;
        std::memcpy(&c, p, 1);
        return normalized ? std::max(float(c) / 127.0f, -1.0f) : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
        std::uint8_t c;
        std::memcpy(&c, p, 1);
        return normalized ? float(c) / 255.0f : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t c;
        std::memcpy(&c, p, 2);
        return normalized ? std::max(float(c) / 32767.0f, -1.0f) : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t c;
        std::memcpy(&c, p, 2);
        return normalized ? float(c) / 65535.0f : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t c;
        std::memcpy(&c, p, 4);
        return float(c);
    }
    default: {  // FLOAT (the only other type an accessor can pass validation with)
        float c;
        std::memcpy(&c, p, 4);
        return c;
    }
    }
}

std::uint32_t decodeIndex(const unsigned char* p, int componentType) {
    if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return *p;
    if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        std::uint16_t c;
        std::memcpy(&c, p, 2);
        return c;
    }
    std::uint32_t c;
    std::memcpy(&c, p, 4);
    return c;
}

// A uri with its %XX escapes decoded (as tinygltf does before opening the file).
std::string percentDecoded(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// ---- Images through OpenImageIO ----------------------------------------------------------------

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
    std::vector<std::uint8_t> raw(texels * std::size_t(channels));
    if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, raw.data())) {
        return "cannot decode the image: " + input->geterror();
    }
    image.rgba8.resize(texels * 4);
    for (std::size_t i = 0; i < texels; ++i) {
        const std::uint8_t* in = &raw[i * std::size_t(channels)];
        std::uint8_t* out = &image.rgba8[i * 4];
        switch (channels) {
        case 1: out[0] = out[1] = out[2] = in[0]; out[3] = 255; break;
        case 2: out[0] = out[1] = out[2] = in[0]; out[3] = in[1]; break;
        case 3: out[0] = in[0]; out[1] = in[1]; out[2] = in[2]; out[3] = 255; break;
        default: std::memcpy(out, in, 4); break;
        }
    }
    return {};
#endif
}

struct ImageLoaderState {
    bool loadImages = true;
    std::vector<std::pair<int, std::string>> errors;  // (images index, message)
};

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

// ---- Tangents ----------------------------------------------------------------------------------

// A unit vector perpendicular to n (for vertices whose UVs give no tangent direction).
glm::vec3 anyPerpendicular(const glm::vec3& n) {
    const glm::vec3 axis = std::abs(n.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 t = axis - n * glm::dot(n, axis);
    const float length = glm::length(t);
    return length > 0.0f ? t / length : glm::vec3(1.0f, 0.0f, 0.0f);
}

// Appends a copy of vertex `v` (every attribute) and returns its index.
std::uint32_t duplicateVertex(MeshPrimitive& prim, std::uint32_t v) {
    const auto copyOf = [v](auto& attribute) {
        if (!attribute.empty()) attribute.push_back(attribute[v]);
    };
    copyOf(prim.positionsObject);
    copyOf(prim.normalsObject);
    copyOf(prim.texCoords0);
    copyOf(prim.texCoords1);
    copyOf(prim.colors0);
    return std::uint32_t(prim.positionsObject.size() - 1);
}

// MikkTSpace-like tangents (Mikkelsen 2008, "Simulation of Wrinkled Surfaces Revisited"): per
// triangle T = dP/du and B = dP/dv from the UV derivatives, projected into each corner's
// tangent plane, normalized and accumulated per vertex weighted by the corner angle; vertices
// shared by UV-preserving and UV-mirrored triangles are split in two, as MikkTSpace does; then
// T is Gram-Schmidt orthogonalized against N and w = sign(dot(cross(N, T), B)), so that
// bitangent = cross(normal, tangent.xyz) * w (§3.7.2.1). Differences from MikkTSpace: it
// also splits vertices whose accumulated frames diverge by angle thresholds, and gives
// UV-degenerate triangles their neighbours' tangents (here: such vertices get any unit
// vector perpendicular to N, w = +1).
// bitangentUp (GltfLoadOptions::generatedBitangentUp, ERRATA #33): B = -dP/dv instead, the
// direction of decreasing v, which is "up" in the image (glTF 2.0 §3.8, Texture Data: the UV origin is the image's top-left;
// §3.9.3: the normal texture's +Y is up), so w comes out negated.
void generateTangents(MeshPrimitive& prim, const std::vector<glm::vec2>& uvs, bool bitangentUp) {
    struct Accumulated {
        glm::vec3 tangent{0.0f}, bitangent{0.0f};
        bool used = false;
    };
    const std::size_t vertexCount = prim.positionsObject.size();
    const std::size_t triangleCount = prim.indices.size() / 3;
    std::vector<Accumulated> accumulated(vertexCount * 2);  // [vertex * 2 + mirrored]
    std::vector<std::uint8_t> mirrored(triangleCount, 0);

    for (std::size_t tri = 0; tri < triangleCount; ++tri) {
        const std::uint32_t* corner = &prim.indices[tri * 3];
        const glm::vec3 p[3] = {prim.positionsObject[corner[0]], prim.positionsObject[corner[1]],
                                prim.positionsObject[corner[2]]};
        const glm::vec2 uv[3] = {uvs[corner[0]], uvs[corner[1]], uvs[corner[2]]};
        const glm::vec3 edge1 = p[1] - p[0], edge2 = p[2] - p[0];
        const glm::vec2 duv1 = uv[1] - uv[0], duv2 = uv[2] - uv[0];
        const float signedUvArea2 = duv1.x * duv2.y - duv2.x * duv1.y;
        if (!(std::abs(signedUvArea2) > 0.0f)) continue;  // UV-degenerate: no direction
        const float orientation = signedUvArea2 > 0.0f ? 1.0f : -1.0f;
        mirrored[tri] = signedUvArea2 < 0.0f ? 1 : 0;
        // dP/du and dP/dv times the UV area (its magnitude drops out when normalized).
        const glm::vec3 tangentDir = (edge1 * duv2.y - edge2 * duv1.y) * orientation;
        const glm::vec3 bitangentDir = (edge2 * duv1.x - edge1 * duv2.x) * orientation;
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 toNext = p[(k + 1) % 3] - p[k], toPrev = p[(k + 2) % 3] - p[k];
            const float lengths = glm::length(toNext) * glm::length(toPrev);
            if (!(lengths > 0.0f)) continue;
            const float angle = std::acos(std::clamp(glm::dot(toNext, toPrev) / lengths, -1.0f, 1.0f));
            const glm::vec3& n = prim.normalsObject[corner[k]];
            glm::vec3 t = tangentDir - n * glm::dot(n, tangentDir);
            glm::vec3 b = bitangentDir - n * glm::dot(n, bitangentDir);
            const float tLength = glm::length(t), bLength = glm::length(b);
            if (tLength > 0.0f) t /= tLength;
            if (bLength > 0.0f) b /= bLength;
            Accumulated& slot = accumulated[std::size_t(corner[k]) * 2 + mirrored[tri]];
            slot.tangent += t * angle;
            slot.bitangent += b * angle;
            slot.used = true;
        }
    }

    // Split vertices used by both orientations: the mirrored triangles get a copy.
    std::vector<std::uint32_t> mirroredCopy(vertexCount, UINT32_MAX);
    for (std::size_t v = 0; v < vertexCount; ++v) {
        if (accumulated[v * 2].used && accumulated[v * 2 + 1].used) {
            mirroredCopy[v] = duplicateVertex(prim, std::uint32_t(v));
        }
    }
    for (std::size_t tri = 0; tri < triangleCount; ++tri) {
        if (!mirrored[tri]) continue;
        for (std::size_t k = 0; k < 3; ++k) {
            std::uint32_t& index = prim.indices[tri * 3 + k];
            if (index < vertexCount && mirroredCopy[index] != UINT32_MAX) index = mirroredCopy[index];
        }
    }

    prim.tangentsObject.assign(prim.positionsObject.size(), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    auto finish = [&](std::size_t vertex, const Accumulated& slot, bool mirroredSlot) {
        const glm::vec3& n = prim.normalsObject[vertex];
        glm::vec3 t = slot.tangent - n * glm::dot(n, slot.tangent);  // Gram-Schmidt against N
        const float length = glm::length(t);
        if (!(length > 1e-12f)) {
            prim.tangentsObject[vertex] = glm::vec4(anyPerpendicular(n), 1.0f);
            return;
        }
        t /= length;
        const float handedness = glm::dot(glm::cross(n, t), slot.bitangent);
        const float w = handedness < 0.0f ? -1.0f : handedness > 0.0f ? 1.0f : (mirroredSlot ? -1.0f : 1.0f);
        prim.tangentsObject[vertex] = glm::vec4(t, bitangentUp ? -w : w);
    };
    for (std::size_t v = 0; v < vertexCount; ++v) {
        const Accumulated& preserving = accumulated[v * 2];
        const Accumulated& flipped = accumulated[v * 2 + 1];
        if (mirroredCopy[v] != UINT32_MAX) {
            finish(v, preserving, false);
            finish(mirroredCopy[v], flipped, true);
        } else {
            finish(v, flipped.used ? flipped : preserving, flipped.used);
        }
    }
    prim.tangentsGenerated = true;
}

// ---- JSON shape ---------------------------------------------------------------------------------

// The JSON types of the properties this loader reads (glTF 2.0 JSON schema, §5), checked before
// tinygltf parses the file: tinygltf silently replaces a mistyped value by its default (an
// object for an array of primitives, "-1" for a texture index), which would load a wrong scene.
class JsonShapeChecker {
public:
    using Json = nlohmann::json;
    explicit JsonShapeChecker(const std::string& file) : mFile(file) {}

    void check(const Json& root) {
        if (!root.is_object()) fail("", "the JSON root is not an object");
        assetVersion(root);
        strings(root, "extensionsUsed", "");
        strings(root, "extensionsRequired", "");
        uint(root, "scene", "");
        extensionsEverywhere(root, "");
        objects(root, "accessors", "", [&](const Json& a, const std::string& at) {
            uints(a, at, {"bufferView", "byteOffset", "componentType", "count"});
            boolean(a, "normalized", at);
            string(a, "type", at);
            numbers(a, "min", at, 0);
            numbers(a, "max", at, 0);
            if (const Json* sparse = object(a, "sparse", at)) {
                const std::string sparseAt = at + "/sparse";
                uint(*sparse, "count", sparseAt);
                if (const Json* indices = object(*sparse, "indices", sparseAt)) {
                    uints(*indices, sparseAt + "/indices", {"bufferView", "byteOffset", "componentType"});
                }
                if (const Json* values = object(*sparse, "values", sparseAt)) {
                    uints(*values, sparseAt + "/values", {"bufferView", "byteOffset"});
                }
            }
        });
        objects(root, "bufferViews", "", [&](const Json& v, const std::string& at) {
            uints(v, at, {"buffer", "byteOffset", "byteLength", "byteStride", "target"});
        });
        objects(root, "buffers", "", [&](const Json& b, const std::string& at) {
            string(b, "uri", at);
            uint(b, "byteLength", at);
        });
        objects(root, "cameras", "", [&](const Json& c, const std::string& at) {
            string(c, "type", at);
            for (const char* kind : {"perspective", "orthographic"}) {
                if (const Json* projection = object(c, kind, at)) {
                    for (const char* key : {"aspectRatio", "yfov", "zfar", "znear", "xmag", "ymag"}) {
                        number(*projection, key, at + "/" + kind);
                    }
                }
            }
        });
        objects(root, "images", "", [&](const Json& i, const std::string& at) {
            string(i, "uri", at);
            string(i, "mimeType", at);
            uint(i, "bufferView", at);
        });
        objects(root, "materials", "", [&](const Json& m, const std::string& at) {
            if (const Json* pbr = object(m, "pbrMetallicRoughness", at)) {
                const std::string pbrAt = at + "/pbrMetallicRoughness";
                numbers(*pbr, "baseColorFactor", pbrAt, 4);
                number(*pbr, "metallicFactor", pbrAt);
                number(*pbr, "roughnessFactor", pbrAt);
                textureInfo(*pbr, "baseColorTexture", pbrAt);
                textureInfo(*pbr, "metallicRoughnessTexture", pbrAt);
            }
            textureInfo(m, "normalTexture", at, "scale");
            textureInfo(m, "occlusionTexture", at, "strength");
            textureInfo(m, "emissiveTexture", at);
            numbers(m, "emissiveFactor", at, 3);
            string(m, "alphaMode", at);
            number(m, "alphaCutoff", at);
            boolean(m, "doubleSided", at);
        });
        objects(root, "meshes", "", [&](const Json& mesh, const std::string& at) {
            if (!mesh.contains("primitives")) fail(at + "/primitives", "is missing");
            objects(mesh, "primitives", at, [&](const Json& p, const std::string& primitiveAt) {
                const Json* attributes = object(p, "attributes", primitiveAt);
                if (!attributes) fail(primitiveAt + "/attributes", "is missing");
                for (const auto& [semantic, value] : attributes->items()) {
                    uint(*attributes, semantic.c_str(), primitiveAt + "/attributes");
                }
                uints(p, primitiveAt, {"indices", "material", "mode"});
            });
            numbers(mesh, "weights", at, 0);
        });
        objects(root, "nodes", "", [&](const Json& n, const std::string& at) {
            uints(n, at, {"camera", "skin", "mesh"});
            if (const Json* children = member(n, "children")) {
                if (!children->is_array()) fail(at + "/children", "must be an array");
                for (std::size_t i = 0; i < children->size(); ++i) {
                    if (!isUint((*children)[i])) fail(indexPath(at + "/children", i), "must be a non-negative integer");
                }
            }
            numbers(n, "matrix", at, 16);
            numbers(n, "rotation", at, 4);
            numbers(n, "scale", at, 3);
            numbers(n, "translation", at, 3);
            if (const Json* extensions = member(n, "extensions")) {
                if (const Json* light = member(*extensions, "KHR_lights_punctual")) {
                    uint(*light, "light", at + "/extensions/KHR_lights_punctual");
                }
            }
        });
        objects(root, "samplers", "", [&](const Json& sampler, const std::string& at) {
            uints(sampler, at, {"magFilter", "minFilter", "wrapS", "wrapT"});
        });
        objects(root, "scenes", "", [&](const Json& scene, const std::string& at) {
            if (const Json* nodes = member(scene, "nodes")) {
                if (!nodes->is_array()) fail(at + "/nodes", "must be an array");
                for (std::size_t i = 0; i < nodes->size(); ++i) {
                    if (!isUint((*nodes)[i])) fail(indexPath(at + "/nodes", i), "must be a non-negative integer");
                }
            }
        });
        objects(root, "textures", "", [&](const Json& t, const std::string& at) { uints(t, at, {"sampler", "source"}); });
        if (const Json* extensions = member(root, "extensions")) {
            if (const Json* lights = member(*extensions, "KHR_lights_punctual")) {
                const std::string at = "/extensions/KHR_lights_punctual";
                objects(*lights, "lights", at, [&](const Json& l, const std::string& lightAt) {
                    string(l, "type", lightAt);
                    numbers(l, "color", lightAt, 3);
                    number(l, "intensity", lightAt);
                    number(l, "range", lightAt);
                    if (const Json* spot = object(l, "spot", lightAt)) {
                        number(*spot, "innerConeAngle", lightAt + "/spot");
                        number(*spot, "outerConeAngle", lightAt + "/spot");
                    }
                });
            }
        }
    }

private:
    [[noreturn]] void fail(const std::string& keyPath, const std::string& what) const {
        throw inputError(mFile, keyPath, what);
    }
    // "<major>.<minor>" (§3.2: the pattern ^[0-9]+\.[0-9]+$); nullopt when the value is not one.
    static std::optional<std::pair<unsigned, unsigned>> version(const Json& value) {
        if (!value.is_string()) return std::nullopt;
        const std::string& text = value.get_ref<const std::string&>();
        const std::size_t dot = text.find('.');
        constexpr std::size_t kMaxVersionDigits = 6;  // per part; keeps the parts within unsigned
        auto digits = [&](std::size_t begin, std::size_t end) {
            return end > begin && end - begin <= kMaxVersionDigits &&
                   std::all_of(text.begin() + std::ptrdiff_t(begin), text.begin() + std::ptrdiff_t(end),
                               [](char c) { return c >= '0' && c <= '9'; });
        };
        if (dot == std::string::npos || !digits(0, dot) || !digits(dot + 1, text.size())) return std::nullopt;
        return std::pair<unsigned, unsigned>(unsigned(std::stoul(text.substr(0, dot))), unsigned(std::stoul(text.substr(dot + 1))));
    }
    // §3.2 Asset: this loader reads glTF 2.x (minor versions are backwards compatible), and a
    // file whose minVersion is above 2.0 needs features it does not know. A missing asset or
    // version is left to tinygltf, which requires both.
    void assetVersion(const Json& root) const {
        const Json* asset = object(root, "asset", "");
        if (!asset) return;
        if (const Json* v = member(*asset, "version")) {
            const auto parsed = version(*v);
            if (!parsed) fail("/asset/version", shown(*v) + " is not a version \"<major>.<minor>\"");
            if (parsed->first != 2)
                fail("/asset/version", "glTF " + v->get<std::string>() + " is not supported (this loader reads glTF 2.x)");
        }
        if (const Json* v = member(*asset, "minVersion")) {
            const auto parsed = version(*v);
            if (!parsed) fail("/asset/minVersion", shown(*v) + " is not a version \"<major>.<minor>\"");
            if (*parsed > std::pair<unsigned, unsigned>(2, 0))
                fail("/asset/minVersion", "the file needs glTF " + v->get<std::string>() + " or later; this loader reads glTF 2.0");
        }
    }
    static const Json* member(const Json& parent, const char* key) {
        const auto it = parent.find(key);
        return it == parent.end() ? nullptr : &*it;
    }
    static std::string shown(const Json& value) {
        std::string text = value.dump();
        return text.size() > 40 ? text.substr(0, 37) + "..." : text;
    }
    static bool isUint(const Json& v) {
        if (v.is_number_unsigned()) return true;
        if (v.is_number_integer()) return v.get<std::int64_t>() >= 0;
        if (v.is_number_float()) {
            const double d = v.get<double>();
            return d >= 0.0 && d == std::floor(d) && d < 9.0e15;
        }
        return false;
    }
    void uint(const Json& parent, const char* key, const std::string& at) const {
        if (const Json* v = member(parent, key); v && !isUint(*v)) {
            fail(at + "/" + key, shown(*v) + " is not a non-negative integer");
        }
    }
    void uints(const Json& parent, const std::string& at, std::initializer_list<const char*> keys) const {
        for (const char* key : keys) uint(parent, key, at);
    }
    void number(const Json& parent, const char* key, const std::string& at) const {
        if (const Json* v = member(parent, key); v && !v->is_number()) fail(at + "/" + key, shown(*v) + " is not a number");
    }
    void string(const Json& parent, const char* key, const std::string& at) const {
        if (const Json* v = member(parent, key); v && !v->is_string()) fail(at + "/" + key, shown(*v) + " is not a string");
    }
    void boolean(const Json& parent, const char* key, const std::string& at) const {
        if (const Json* v = member(parent, key); v && !v->is_boolean()) {
            fail(at + "/" + key, shown(*v) + " is not true or false");
        }
    }
    void strings(const Json& parent, const char* key, const std::string& at) const {
        const Json* v = member(parent, key);
        if (!v) return;
        if (!v->is_array()) fail(at + "/" + key, "must be an array of strings");
        for (std::size_t i = 0; i < v->size(); ++i) {
            if (!(*v)[i].is_string()) fail(indexPath(at + "/" + key, i), shown((*v)[i]) + " is not a string");
        }
    }
    void numbers(const Json& parent, const char* key, const std::string& at, std::size_t size) const {
        const Json* v = member(parent, key);
        if (!v) return;
        if (!v->is_array() || (size != 0 && v->size() != size)) {
            fail(at + "/" + key, "must be an array of " + (size ? std::to_string(size) + " " : std::string()) + "numbers");
        }
        for (std::size_t i = 0; i < v->size(); ++i) {
            if (!(*v)[i].is_number()) fail(indexPath(at + "/" + key, i), shown((*v)[i]) + " is not a number");
        }
    }
    const Json* object(const Json& parent, const char* key, const std::string& at) const {
        const Json* v = member(parent, key);
        if (v && !v->is_object()) fail(at + "/" + key, "must be an object, not " + shown(*v));
        return v;
    }
    // A textureInfo (§5.23) with its extra number ("scale", "strength") where it has one.
    void textureInfo(const Json& parent, const char* key, const std::string& at, const char* extra = nullptr) const {
        const Json* info = object(parent, key, at);
        if (!info) return;
        uints(*info, at + "/" + key, {"index", "texCoord"});
        if (extra) number(*info, extra, at + "/" + key);
        if (!info->contains("index")) fail(at + "/" + key + "/index", "is missing");
    }
    template <class Visit>
    void objects(const Json& parent, const char* key, const std::string& at, Visit&& visit) const {
        const Json* v = member(parent, key);
        if (!v) return;
        if (!v->is_array()) fail(at + "/" + key, "must be an array, not " + shown(*v));
        for (std::size_t i = 0; i < v->size(); ++i) {
            const std::string elementAt = indexPath(at + "/" + key, i);
            if (!(*v)[i].is_object()) fail(elementAt, "must be an object, not " + shown((*v)[i]));
            visit((*v)[i], elementAt);
        }
    }
    // Every "extensions" is an object of objects and every "name" a string (not inside "extras").
    void extensionsEverywhere(const Json& value, const std::string& at) const {
        if (value.is_array()) {
            for (std::size_t i = 0; i < value.size(); ++i) extensionsEverywhere(value[i], indexPath(at, i));
            return;
        }
        if (!value.is_object()) return;
        for (const auto& [key, child] : value.items()) {
            const std::string childAt = at + "/" + key;
            if (key == "extras") continue;
            if (key == "name" && !child.is_string()) fail(childAt, shown(child) + " is not a string");
            if (key == "extensions") {
                if (!child.is_object()) fail(childAt, "must be an object, not " + shown(child));
                for (const auto& [name, extension] : child.items()) {
                    if (!extension.is_object()) fail(childAt + "/" + name, "must be an object, not " + shown(extension));
                }
            }
            extensionsEverywhere(child, childAt);
        }
    }

    const std::string& mFile;
};

// ---- The reader --------------------------------------------------------------------------------

struct AccessorLayout {
    const unsigned char* first = nullptr;  // element 0; null: no bufferView (all zeros, §3.6.2.3)
    std::size_t stride = 0, count = 0, components = 0, componentBytes = 0;
    int componentType = 0;
    bool normalized = false;
};

class GltfReader {
public:
    GltfReader(std::string file, fs::path folder, tinygltf::Model& model, const GltfLoadOptions& options,
               const Scene& target)
        : mFile(std::move(file)), mFolder(std::move(folder)), mModel(model), mOptions(options),
          mMeshBase(int(target.meshes.size())), mMaterialBase(int(target.materials.size())),
          mImageBase(int(target.images.size())), mTextureBase(int(target.textures.size())) {
        mDecodeBudget = DECODE_BUDGET_BASE;
        for (const tinygltf::Buffer& buffer : mModel.buffers) mDecodeBudget += DECODE_BUDGET_PER_BUFFER_BYTE * buffer.data.size();
    }

    void read() {
        checkExtensions();
        readImages();
        readTextures();
        readMaterials();
        readMeshes();
        checkLights();
        readNodes();
        reportLights();
    }

    Scene mOut;  // what the file adds (appended to the target scene once everything passed)
    std::vector<std::string> mWarnings;

private:
    [[noreturn]] void fail(const std::string& keyPath, const std::string& what) const {
        throw inputError(mFile, keyPath, what);
    }
    void warn(const std::string& what) { mWarnings.push_back(mFile + ": " + what); }

    bool extensionUsed(std::string_view name) const {
        return std::find(mModel.extensionsUsed.begin(), mModel.extensionsUsed.end(), name) !=
               mModel.extensionsUsed.end();
    }

    void checkExtensions() {
        auto supported = [](const std::string& name) {
            return std::find(SUPPORTED_EXTENSIONS.begin(), SUPPORTED_EXTENSIONS.end(), name) !=
                   SUPPORTED_EXTENSIONS.end();
        };
        for (std::size_t i = 0; i < mModel.extensionsRequired.size(); ++i) {
            const std::string& name = mModel.extensionsRequired[i];
            if (!supported(name)) fail(indexPath("/extensionsRequired", i), "extension '" + name + "' is required but not supported");
        }
        for (const std::string& name : mModel.extensionsUsed) {
            if (!supported(name)) warn("extension '" + name + "' is not supported and is ignored");
        }
        mQuantization = extensionUsed("KHR_mesh_quantization");
    }

    // Checks index `index` into an array of `size` elements referenced at `keyPath`.
    void checkIndex(int index, std::size_t size, const std::string& keyPath, std::string_view what) const {
        if (index < 0 || std::size_t(index) >= size) {
            fail(keyPath, std::string(what) + " " + std::to_string(index) + " does not exist (the file has " +
                              std::to_string(size) + ")");
        }
    }

    // The bytes of bufferView `index`, checked against its buffer.
    const unsigned char* bufferViewData(int index, const std::string& referencedAt) const {
        checkIndex(index, mModel.bufferViews.size(), referencedAt, "bufferView");
        const tinygltf::BufferView& view = mModel.bufferViews[std::size_t(index)];
        const std::string path = indexPath("/bufferViews", std::size_t(index));
        checkIndex(view.buffer, mModel.buffers.size(), path + "/buffer", "buffer");
        const std::vector<unsigned char>& data = mModel.buffers[std::size_t(view.buffer)].data;
        if (view.byteLength == 0) fail(path + "/byteLength", "0 is below the minimum 1");
        if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
            fail(path, "byteOffset " + std::to_string(view.byteOffset) + " + byteLength " +
                           std::to_string(view.byteLength) + " exceeds buffer " + std::to_string(view.buffer) +
                           "'s " + std::to_string(data.size()) + " bytes");
        }
        return data.data() + view.byteOffset;
    }

    AccessorLayout layoutOf(int index, const std::string& referencedAt) const {
        checkIndex(index, mModel.accessors.size(), referencedAt, "accessor");
        const tinygltf::Accessor& accessor = mModel.accessors[std::size_t(index)];
        const std::string path = indexPath("/accessors", std::size_t(index));
        AccessorLayout layout;
        layout.componentType = accessor.componentType;
        layout.normalized = accessor.normalized;
        layout.count = accessor.count;
        layout.components = componentCount(accessor.type);
        layout.componentBytes = componentSize(accessor.componentType);
        if (layout.componentBytes == 0) {
            fail(path + "/componentType", std::to_string(accessor.componentType) + " (" +
                                              componentTypeName(accessor.componentType) +
                                              ") is not a glTF 2.0 component type");
        }
        if (layout.components == 0) fail(path + "/type", "unknown accessor type");
        if (accessor.count == 0) fail(path + "/count", "0 is below the minimum 1");
        if (accessor.count > MAX_ACCESSOR_ELEMENTS) {
            fail(path + "/count", std::to_string(accessor.count) + " elements exceeds the limit of 2^28");
        }
        const std::size_t elementBytes = layout.components * layout.componentBytes;
        layout.stride = elementBytes;
        if (accessor.bufferView != -1) {
            const std::string viewPath = indexPath("/bufferViews", std::size_t(std::max(accessor.bufferView, 0)));
            const unsigned char* view = bufferViewData(accessor.bufferView, path + "/bufferView");
            const tinygltf::BufferView& bufferView = mModel.bufferViews[std::size_t(accessor.bufferView)];
            if (bufferView.byteStride != 0) {
                // §3.6.2.4: byteStride is a multiple of the component size and holds one element.
                if (bufferView.byteStride < elementBytes || bufferView.byteStride % layout.componentBytes != 0) {
                    fail(viewPath + "/byteStride", std::to_string(bufferView.byteStride) + " does not fit accessor " +
                                                       std::to_string(index) + "'s " + std::to_string(elementBytes) +
                                                       "-byte elements");
                }
                layout.stride = bufferView.byteStride;
            }
            const std::uint64_t needed = std::uint64_t(layout.stride) * (accessor.count - 1) + elementBytes;
            if (accessor.byteOffset > bufferView.byteLength || needed > bufferView.byteLength - accessor.byteOffset) {
                fail(path, std::to_string(accessor.count) + " elements of " + std::to_string(elementBytes) +
                               " bytes (stride " + std::to_string(layout.stride) + ") from byteOffset " +
                               std::to_string(accessor.byteOffset) + " exceed bufferView " +
                               std::to_string(accessor.bufferView) + "'s " + std::to_string(bufferView.byteLength) +
                               " bytes");
            }
            layout.first = view + accessor.byteOffset;
        } else if (!accessor.sparse.isSparse) {
            fail(path, "the accessor has neither a bufferView nor sparse values");
        }
        return layout;
    }

    // Applies a sparse accessor's substitutions (§3.6.2.3) by calling store(element, bytes).
    template <class Store>
    void applySparse(int index, const AccessorLayout& layout, Store&& store) const {
        const tinygltf::Accessor& accessor = mModel.accessors[std::size_t(index)];
        if (!accessor.sparse.isSparse) return;
        const std::string path = indexPath("/accessors", std::size_t(index)) + "/sparse";
        const auto& sparse = accessor.sparse;
        if (sparse.count < 1 || std::size_t(sparse.count) > accessor.count) {
            fail(path + "/count", std::to_string(sparse.count) + " is outside 1.." + std::to_string(accessor.count));
        }
        const std::size_t indexBytes = sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                                       : sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                                       : sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                                                                 : 0;
        if (indexBytes == 0) fail(path + "/indices/componentType", "must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
        const std::size_t elementBytes = layout.components * layout.componentBytes;
        auto range = [&](int viewIndex, int byteOffset, std::size_t bytes, const std::string& at) {
            const unsigned char* data = bufferViewData(viewIndex, at + "/bufferView");
            const std::size_t length = mModel.bufferViews[std::size_t(viewIndex)].byteLength;
            if (byteOffset < 0 || std::size_t(byteOffset) > length || bytes > length - std::size_t(byteOffset)) {
                fail(at, std::to_string(bytes) + " bytes from byteOffset " + std::to_string(byteOffset) +
                             " exceed bufferView " + std::to_string(viewIndex) + "'s " + std::to_string(length) +
                             " bytes");
            }
            return data + byteOffset;
        };
        const std::size_t n = std::size_t(sparse.count);
        const unsigned char* indices =
            range(sparse.indices.bufferView, sparse.indices.byteOffset, n * indexBytes, path + "/indices");
        const unsigned char* values =
            range(sparse.values.bufferView, sparse.values.byteOffset, n * elementBytes, path + "/values");
        for (std::size_t k = 0; k < n; ++k) {
            const std::uint32_t element = decodeIndex(indices + k * indexBytes, sparse.indices.componentType);
            if (element >= accessor.count) {
                fail(path + "/indices", "index " + std::to_string(element) + " is not below the count " +
                                            std::to_string(accessor.count));
            }
            store(std::size_t(element), values + k * elementBytes);
        }
    }

    // Reads a float-decoded attribute: components floats per element.
    // Counts `values` 32-bit values against the file's decode budget before they are allocated.
    void chargeDecode(std::size_t values, int index) const {
        const std::uint64_t bytes = std::uint64_t(values) * 4;
        if (bytes > mDecodeBudget - mDecoded) {
            fail(indexPath("/accessors", std::size_t(index)) + "/count",
                 "decoding " + std::to_string(values) + " values would take the file's decoded accessor data past " +
                     std::to_string(mDecodeBudget >> 20) + " MiB (256 MiB + 256 bytes per buffer byte; " +
                     std::to_string(mDecoded >> 20) + " MiB decoded so far)");
        }
        mDecoded += bytes;
    }

    std::vector<float> readFloats(int index, const std::string& referencedAt) const {
        const AccessorLayout layout = layoutOf(index, referencedAt);
        chargeDecode(layout.count * layout.components, index);
        std::vector<float> out(layout.count * layout.components, 0.0f);
        auto decodeElement = [&](std::size_t element, const unsigned char* bytes) {
            for (std::size_t c = 0; c < layout.components; ++c) {
                out[element * layout.components + c] =
                    decodeComponent(bytes + c * layout.componentBytes, layout.componentType, layout.normalized);
            }
        };
        if (layout.first) {
            for (std::size_t i = 0; i < layout.count; ++i) decodeElement(i, layout.first + i * layout.stride);
        }
        applySparse(index, layout, decodeElement);
        return out;
    }

    std::vector<std::uint32_t> readIndices(int index, const std::string& referencedAt) const {
        checkIndex(index, mModel.accessors.size(), referencedAt, "accessor");
        const std::string path = indexPath("/accessors", std::size_t(index));
        const tinygltf::Accessor& accessor = mModel.accessors[std::size_t(index)];
        if (accessor.type != TINYGLTF_TYPE_SCALAR ||
            (accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
             accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
             accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
            fail(path, std::string("indices must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, not ") +
                           accessorTypeName(accessor.type) + " of " + componentTypeName(accessor.componentType) +
                           " (used by " + referencedAt + ")");
        }
        const AccessorLayout layout = layoutOf(index, referencedAt);
        chargeDecode(layout.count, index);
        std::vector<std::uint32_t> out(layout.count, 0);
        auto decodeElement = [&](std::size_t element, const unsigned char* bytes) {
            out[element] = decodeIndex(bytes, layout.componentType);
        };
        if (layout.first) {
            for (std::size_t i = 0; i < layout.count; ++i) decodeElement(i, layout.first + i * layout.stride);
        }
        applySparse(index, layout, decodeElement);
        return out;
    }

    // §3.7.2.1 attribute formats, widened by KHR_mesh_quantization when the file uses it.
    bool attributeFormatAllowed(const std::string& semantic, int type, int componentType, bool normalized) const {
        const bool isFloat = componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
        const bool isSigned8or16 =
            componentType == TINYGLTF_COMPONENT_TYPE_BYTE || componentType == TINYGLTF_COMPONENT_TYPE_SHORT;
        const bool isUnsigned8or16 = componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                     componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
        if (semantic == "POSITION") {
            return type == TINYGLTF_TYPE_VEC3 && (isFloat || (mQuantization && (isSigned8or16 || isUnsigned8or16)));
        }
        if (semantic == "NORMAL") {
            return type == TINYGLTF_TYPE_VEC3 && (isFloat || (mQuantization && isSigned8or16 && normalized));
        }
        if (semantic == "TANGENT") {
            return type == TINYGLTF_TYPE_VEC4 && (isFloat || (mQuantization && isSigned8or16 && normalized));
        }
        if (semantic == "COLOR_0") {
            return (type == TINYGLTF_TYPE_VEC3 || type == TINYGLTF_TYPE_VEC4) &&
                   (isFloat || (isUnsigned8or16 && normalized) || (mQuantization && isSigned8or16 && normalized));
        }
        // TEXCOORD_n
        return type == TINYGLTF_TYPE_VEC2 &&
               (isFloat || (isUnsigned8or16 && normalized) || (mQuantization && (isSigned8or16 || isUnsigned8or16)));
    }

    std::vector<float> readAttribute(const tinygltf::Primitive& primitive, const std::string& semantic,
                                     const std::string& primitivePath, std::size_t expectedCount) const {
        const int index = primitive.attributes.at(semantic);
        const std::string referencedAt = primitivePath + "/attributes/" + semantic;
        checkIndex(index, mModel.accessors.size(), referencedAt, "accessor");
        const tinygltf::Accessor& accessor = mModel.accessors[std::size_t(index)];
        if (!attributeFormatAllowed(semantic, accessor.type, accessor.componentType, accessor.normalized)) {
            static const std::vector<std::pair<std::string, std::string>> EXPECTED = {
                {"POSITION", "VEC3 of FLOAT"}, {"NORMAL", "VEC3 of FLOAT"}, {"TANGENT", "VEC4 of FLOAT"},
                {"COLOR_0", "VEC3/VEC4 of FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT"}};
            std::string expected = "VEC2 of FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT";
            for (const auto& [name, format] : EXPECTED) {
                if (name == semantic) expected = format;
            }
            fail(indexPath("/accessors", std::size_t(index)),
                 semantic + " must be " + expected + (mQuantization ? " (or a KHR_mesh_quantization format)" : "") +
                     ", not " + (accessor.normalized ? "normalized " : "") + accessorTypeName(accessor.type) + " of " +
                     componentTypeName(accessor.componentType) + " (used by " + referencedAt + ")");
        }
        if (expectedCount != 0 && accessor.count != expectedCount) {
            fail(referencedAt, "accessor " + std::to_string(index) + " has " + std::to_string(accessor.count) +
                                   " elements but POSITION has " + std::to_string(expectedCount));
        }
        return readFloats(index, referencedAt);
    }

    // ---- images, textures, materials

    // Checks every image record in file order, then decodes them all in parallel (each image is
    // independent, so the bytes do not depend on scheduling); the first failing image in file
    // order is the one reported.
    void readImages() {
        struct Pending {
            const unsigned char* bytes = nullptr;
            std::size_t size = 0;
            std::string uri;
        };
        std::vector<Image> images(mModel.images.size());
        std::vector<Pending> pending(mModel.images.size());
        for (std::size_t i = 0; i < mModel.images.size(); ++i) {
            tinygltf::Image& gltfImage = mModel.images[i];
            const std::string path = indexPath("/images", i);
            Image& image = images[i];
            const bool external = !gltfImage.uri.empty() && gltfImage.bufferView < 0;
            image.source = external ? (mFolder / percentDecoded(gltfImage.uri)).string() : mFile + "#" + path;
            if (gltfImage.bufferView >= 0) {
                pending[i].bytes = bufferViewData(gltfImage.bufferView, path + "/bufferView");
                pending[i].size = mModel.bufferViews[std::size_t(gltfImage.bufferView)].byteLength;
            } else if (gltfImage.width < 1) {
                // tinygltf only warns when an external image cannot be read.
                fail(path + "/uri", "cannot read the image file '" + image.source + "'");
            } else {
                image.width = std::uint32_t(gltfImage.width);
                image.height = std::uint32_t(gltfImage.height);
                pending[i] = {gltfImage.image.data(), gltfImage.image.size(), gltfImage.uri};
                if (!mOptions.loadImages) pending[i].bytes = nullptr;  // header already read
            }
        }
        std::vector<std::string> problems(images.size());
        tbb::parallel_for(std::size_t(0), images.size(), [&](std::size_t i) {
            if (pending[i].bytes == nullptr) return;
            problems[i] = decodeImage(pending[i].bytes, pending[i].size, mModel.images[i].mimeType, pending[i].uri,
                                      !mOptions.loadImages, images[i]);
        });
        for (std::size_t i = 0; i < images.size(); ++i) {
            if (!problems[i].empty()) fail(indexPath("/images", i), problems[i]);
            mModel.images[i].image.clear();
            mModel.images[i].image.shrink_to_fit();
            mOut.images.push_back(std::move(images[i]));
        }
    }

    static SamplerState samplerFrom(const tinygltf::Sampler& sampler, const std::string& path, const GltfReader& self) {
        // §5.26 (sampler): absent filters are implementation-defined; tessera uses the common
        // choice linear + linear-mip-linear. Wrap modes default to REPEAT.
        SamplerState state;
        state.minFilter = state.magFilter = state.mipFilter = Filter::Linear;
        switch (sampler.magFilter) {
        case -1:
        case 9729: state.magFilter = Filter::Linear; break;   // LINEAR
        case 9728: state.magFilter = Filter::Point; break;    // NEAREST
        default: self.fail(path + "/magFilter", std::to_string(sampler.magFilter) + " is not 9728 or 9729");
        }
        switch (sampler.minFilter) {
        case -1: break;
        // NEAREST / LINEAR without mipmaps: sample the top level only (maxLod = 0, as in GL).
        case 9728: state.minFilter = Filter::Point; state.mipFilter = Filter::Point; state.maxLod = 0.0f; break;
        case 9729: state.minFilter = Filter::Linear; state.mipFilter = Filter::Point; state.maxLod = 0.0f; break;
        case 9984: state.minFilter = Filter::Point; state.mipFilter = Filter::Point; break;   // NEAREST_MIPMAP_NEAREST
        case 9985: state.minFilter = Filter::Linear; state.mipFilter = Filter::Point; break;  // LINEAR_MIPMAP_NEAREST
        case 9986: state.minFilter = Filter::Point; state.mipFilter = Filter::Linear; break;  // NEAREST_MIPMAP_LINEAR
        case 9987: state.minFilter = Filter::Linear; state.mipFilter = Filter::Linear; break; // LINEAR_MIPMAP_LINEAR
        default: self.fail(path + "/minFilter", std::to_string(sampler.minFilter) + " is not a glTF minFilter");
        }
        auto wrap = [&](int mode, const char* key) {
            switch (mode) {
            case 33071: return AddressMode::Clamp;   // CLAMP_TO_EDGE
            case 33648: return AddressMode::Mirror;  // MIRRORED_REPEAT
            case 10497: return AddressMode::Wrap;    // REPEAT
            default: self.fail(path + "/" + key, std::to_string(mode) + " is not 33071, 33648 or 10497");
            }
        };
        state.addressU = wrap(sampler.wrapS, "wrapS");
        state.addressV = wrap(sampler.wrapT, "wrapT");
        return state;
    }

    void readTextures() {
        std::vector<SamplerState> samplers;
        for (std::size_t i = 0; i < mModel.samplers.size(); ++i) {
            samplers.push_back(samplerFrom(mModel.samplers[i], indexPath("/samplers", i), *this));
        }
        const SamplerState defaultSampler = samplerFrom(tinygltf::Sampler{}, "/samplers", *this);
        for (std::size_t i = 0; i < mModel.textures.size(); ++i) {
            const tinygltf::Texture& texture = mModel.textures[i];
            const std::string path = indexPath("/textures", i);
            TextureBinding binding;
            if (texture.source == -1) {
                warn(path + ": no source image (an image-format extension?); the texture samples nothing");
            } else {
                checkIndex(texture.source, mModel.images.size(), path + "/source", "image");
                binding.image = mImageBase + texture.source;
            }
            if (texture.sampler == -1) {
                binding.sampler = defaultSampler;
            } else {
                checkIndex(texture.sampler, samplers.size(), path + "/sampler", "sampler");
                binding.sampler = samplers[std::size_t(texture.sampler)];
            }
            mOut.textures.push_back(binding);
        }
    }

    TextureRef textureRef(int index, int texCoord, double scale, const std::string& path) {
        TextureRef ref;
        if (index == -1) return ref;
        checkIndex(index, mModel.textures.size(), path + "/index", "texture");
        ref.texture = mTextureBase + index;
        if (texCoord < 0) fail(path + "/texCoord", std::to_string(texCoord) + " is negative");
        if (texCoord > 1) {
            warn(path + "/texCoord: TEXCOORD_" + std::to_string(texCoord) + " is not supported; TEXCOORD_0 is used");
            texCoord = 0;
        }
        ref.texCoord = texCoord;
        ref.scale = float(scale);
        return ref;
    }

    template <std::size_t N>
    glm::vec<int(N), float> vectorOf(const std::vector<double>& values, glm::vec<int(N), float> fallback,
                                     const std::string& path) const {
        if (values.empty()) return fallback;
        if (values.size() != N) fail(path, "needs " + std::to_string(N) + " numbers, has " + std::to_string(values.size()));
        glm::vec<int(N), float> out;
        for (std::size_t i = 0; i < N; ++i) {
            if (!std::isfinite(values[i])) fail(path, "holds a non-finite value");
            out[int(i)] = float(values[i]);
        }
        return out;
    }

    void readMaterials() {
        for (std::size_t i = 0; i < mModel.materials.size(); ++i) {
            const tinygltf::Material& m = mModel.materials[i];
            const std::string path = indexPath("/materials", i);
            const auto& pbr = m.pbrMetallicRoughness;
            const std::string pbrPath = path + "/pbrMetallicRoughness";
            Material material;
            material.name = m.name;
            material.baseColorFactor = vectorOf<4>(pbr.baseColorFactor, glm::vec4(1.0f), pbrPath + "/baseColorFactor");
            material.baseColorTexture = textureRef(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, 1.0,
                                                   pbrPath + "/baseColorTexture");
            material.metallicFactor = float(pbr.metallicFactor);
            material.roughnessFactor = float(pbr.roughnessFactor);
            material.metallicRoughnessTexture =
                textureRef(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, 1.0,
                           pbrPath + "/metallicRoughnessTexture");
            material.normalTexture = textureRef(m.normalTexture.index, m.normalTexture.texCoord, m.normalTexture.scale,
                                                path + "/normalTexture");
            material.occlusionTexture = textureRef(m.occlusionTexture.index, m.occlusionTexture.texCoord,
                                                   m.occlusionTexture.strength, path + "/occlusionTexture");
            material.emissiveTexture =
                textureRef(m.emissiveTexture.index, m.emissiveTexture.texCoord, 1.0, path + "/emissiveTexture");
            material.emissiveFactor = vectorOf<3>(m.emissiveFactor, glm::vec3(0.0f), path + "/emissiveFactor");
            const auto strength = m.extensions.find("KHR_materials_emissive_strength");
            if (strength != m.extensions.end() && strength->second.Has("emissiveStrength")) {
                material.emissiveFactor *= float(strength->second.Get("emissiveStrength").GetNumberAsDouble());
            }
            if (m.alphaMode == "OPAQUE") material.alphaMode = AlphaMode::Opaque;
            else if (m.alphaMode == "MASK") material.alphaMode = AlphaMode::Mask;
            else if (m.alphaMode == "BLEND") material.alphaMode = AlphaMode::Blend;
            else fail(path + "/alphaMode", "'" + m.alphaMode + "' is not OPAQUE, MASK or BLEND");
            if (!(m.alphaCutoff >= 0.0)) fail(path + "/alphaCutoff", std::to_string(m.alphaCutoff) + " is negative");
            material.alphaCutoff = float(m.alphaCutoff);
            material.doubleSided = m.doubleSided;
            mOut.materials.push_back(std::move(material));
        }
    }

    // ---- meshes

    void readMeshes() {
        std::vector<std::string> skipped;
        bool morphWarned = false;
        for (std::size_t m = 0; m < mModel.meshes.size(); ++m) {
            const tinygltf::Mesh& gltfMesh = mModel.meshes[m];
            Mesh mesh;
            mesh.name = gltfMesh.name;
            for (std::size_t p = 0; p < gltfMesh.primitives.size(); ++p) {
                const std::string path = indexPath(indexPath("/meshes", m) + "/primitives", p);
                const tinygltf::Primitive& primitive = gltfMesh.primitives[p];
                if (!primitive.targets.empty() && !morphWarned) {
                    warn(path + "/targets: morph targets are ignored (the base shape is drawn)");
                    morphWarned = true;
                }
                std::optional<MeshPrimitive> prim = readPrimitive(primitive, path);
                if (prim) mesh.primitives.push_back(std::move(*prim));
                else skipped.push_back(path);
            }
            mOut.meshes.push_back(std::move(mesh));
        }
        if (!skipped.empty()) {
            std::string list;
            for (std::size_t i = 0; i < skipped.size() && i < 8; ++i) list += (i ? ", " : "") + skipped[i];
            if (skipped.size() > 8) list += ", ...";
            warn(std::to_string(skipped.size()) + " primitive(s) without triangles (points, lines, or fewer than 3 "
                 "vertices) skipped: " + list);
        }
    }

    // The triangle list of a primitive (§3.7.2.1 "Topology types"); empty for points and lines.
    std::vector<std::uint32_t> triangleList(std::vector<std::uint32_t> vertices, int mode, const std::string& path) const {
        std::vector<std::uint32_t> triangles;
        const std::size_t n = vertices.size();
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            if (n % 3 != 0) {
                fail(path, std::to_string(n) + " vertices (after indexing) are not a multiple of 3 for TRIANGLES");
            }
            return vertices;
        }
        if (n < 3) return triangles;
        triangles.reserve((n - 2) * 3);
        for (std::size_t i = 0; i + 2 < n; ++i) {
            if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                // p_i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}}: odd triangles swap to keep the winding.
                triangles.insert(triangles.end(), {vertices[i], vertices[i + 1 + i % 2], vertices[i + 2 - i % 2]});
            } else {
                // TRIANGLE_FAN: p_i = {v_{i+1}, v_{i+2}, v_0}
                triangles.insert(triangles.end(), {vertices[i + 1], vertices[i + 2], vertices[0]});
            }
        }
        return triangles;
    }

    std::optional<MeshPrimitive> readPrimitive(const tinygltf::Primitive& primitive, const std::string& path) {
        const int mode = primitive.mode == -1 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
        if (mode < TINYGLTF_MODE_POINTS || mode > TINYGLTF_MODE_TRIANGLE_FAN) {
            fail(path + "/mode", std::to_string(mode) + " is not a glTF primitive mode (0..6)");
        }
        if (mode < TINYGLTF_MODE_TRIANGLES) return std::nullopt;
        if (primitive.material != -1) checkIndex(primitive.material, mModel.materials.size(), path + "/material", "material");
        if (primitive.attributes.count("POSITION") == 0) fail(path + "/attributes", "POSITION is missing");

        MeshPrimitive prim;
        prim.material = primitive.material == -1 ? -1 : mMaterialBase + primitive.material;
        const int positionAccessor = primitive.attributes.at("POSITION");
        const std::vector<float> positions = readAttribute(primitive, "POSITION", path, 0);
        const std::size_t vertexCount = positions.size() / 3;
        for (std::size_t i = 0; i < positions.size(); ++i) {
            if (!std::isfinite(positions[i])) {
                fail(indexPath("/accessors", std::size_t(positionAccessor)),
                     "POSITION holds a non-finite value (element " + std::to_string(i / 3) + ")");
            }
        }
        prim.positionsObject.resize(vertexCount);
        for (std::size_t v = 0; v < vertexCount; ++v) {
            prim.positionsObject[v] = {positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2]};
        }
        auto has = [&](const char* semantic) { return primitive.attributes.count(semantic) != 0; };
        if (has("NORMAL")) {
            const std::vector<float> normals = readAttribute(primitive, "NORMAL", path, vertexCount);
            prim.normalsObject.resize(vertexCount);
            for (std::size_t v = 0; v < vertexCount; ++v) {
                prim.normalsObject[v] = {normals[v * 3], normals[v * 3 + 1], normals[v * 3 + 2]};
            }
        }
        // §3.7.2.1: without normals, flat normals are used and any TANGENT is ignored.
        if (has("TANGENT") && has("NORMAL")) {
            const std::vector<float> tangents = readAttribute(primitive, "TANGENT", path, vertexCount);
            prim.tangentsObject.resize(vertexCount);
            for (std::size_t v = 0; v < vertexCount; ++v) {
                const float w = tangents[v * 4 + 3] < 0.0f ? -1.0f : 1.0f;  // the bitangent sign as given
                prim.tangentsObject[v] = {tangents[v * 4], tangents[v * 4 + 1], tangents[v * 4 + 2], w};
            }
        }
        auto readUv = [&](const char* semantic, std::vector<glm::vec2>& out) {
            if (!has(semantic)) return;
            const std::vector<float> uv = readAttribute(primitive, semantic, path, vertexCount);
            out.resize(vertexCount);
            for (std::size_t v = 0; v < vertexCount; ++v) out[v] = {uv[v * 2], uv[v * 2 + 1]};
        };
        readUv("TEXCOORD_0", prim.texCoords0);
        readUv("TEXCOORD_1", prim.texCoords1);
        if (has("COLOR_0")) {
            const std::vector<float> colors = readAttribute(primitive, "COLOR_0", path, vertexCount);
            const std::size_t components = colors.size() / vertexCount;
            prim.colors0.resize(vertexCount);
            for (std::size_t v = 0; v < vertexCount; ++v) {
                const float* c = &colors[v * components];
                prim.colors0[v] = {c[0], c[1], c[2], components == 4 ? c[3] : 1.0f};
            }
        }

        std::vector<std::uint32_t> vertices;
        if (primitive.indices != -1) {
            const std::string indicesPath = path + "/indices";
            vertices = readIndices(primitive.indices, indicesPath);
            for (std::size_t i = 0; i < vertices.size(); ++i) {
                if (vertices[i] >= vertexCount) {
                    fail(indexPath("/accessors", std::size_t(primitive.indices)),
                         "index " + std::to_string(vertices[i]) + " (element " + std::to_string(i) +
                             ") is not below the vertex count " + std::to_string(vertexCount) + " of " + path);
                }
            }
        } else {
            vertices.resize(vertexCount);
            for (std::size_t v = 0; v < vertexCount; ++v) vertices[v] = std::uint32_t(v);
        }
        prim.indices = triangleList(std::move(vertices), mode, path);
        if (prim.indices.empty()) return std::nullopt;

        if (prim.normalsObject.empty()) makeFlatNormals(prim);

        // Tangents: generated whenever TANGENT is absent and the UV set they follow exists (the
        // normal texture's texCoord when the material has one, else TEXCOORD_0).
        if (prim.tangentsObject.empty()) {
            int uvSet = 0;
            if (primitive.material != -1) {
                const TextureRef& normalMap = mOut.materials[std::size_t(primitive.material)].normalTexture;
                if (normalMap.present()) uvSet = normalMap.texCoord;
            }
            const std::vector<glm::vec2>& uvs = uvSet == 1 ? prim.texCoords1 : prim.texCoords0;
            if (!uvs.empty()) {
                const std::vector<glm::vec2> uvCopy = uvs;  // generateTangents may append vertices
                generateTangents(prim, uvCopy, mOptions.generatedBitangentUp);
            }
        }
        return prim;
    }

    // Flat normals (§3.7.2.1): every triangle gets its own three vertices and the face normal
    // normalize(cross(p1 - p0, p2 - p0)) (counter-clockwise front faces, §3.7.2.1).
    static void makeFlatNormals(MeshPrimitive& prim) {
        MeshPrimitive flat;
        const std::size_t corners = prim.indices.size();
        auto unweld = [&](const auto& from, auto& to) {
            if (from.empty()) return;
            to.resize(corners);
            for (std::size_t c = 0; c < corners; ++c) to[c] = from[prim.indices[c]];
        };
        unweld(prim.positionsObject, flat.positionsObject);
        unweld(prim.texCoords0, flat.texCoords0);
        unweld(prim.texCoords1, flat.texCoords1);
        unweld(prim.colors0, flat.colors0);
        flat.normalsObject.resize(corners);
        flat.indices.resize(corners);
        for (std::size_t c = 0; c < corners; c += 3) {
            const glm::vec3 n = glm::cross(flat.positionsObject[c + 1] - flat.positionsObject[c],
                                           flat.positionsObject[c + 2] - flat.positionsObject[c]);
            const float length = glm::length(n);
            const glm::vec3 unit = length > 0.0f && std::isfinite(length) ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);
            for (std::size_t k = 0; k < 3; ++k) {
                flat.normalsObject[c + k] = unit;
                flat.indices[c + k] = std::uint32_t(c + k);
            }
        }
        prim.positionsObject = std::move(flat.positionsObject);
        prim.normalsObject = std::move(flat.normalsObject);
        prim.texCoords0 = std::move(flat.texCoords0);
        prim.texCoords1 = std::move(flat.texCoords1);
        prim.colors0 = std::move(flat.colors0);
        prim.indices = std::move(flat.indices);
        prim.tangentsObject.clear();
    }

    // ---- nodes, cameras, lights

    // §3.5.3: matrix, or T * R * S from translation, rotation (unit quaternion xyzw) and scale.
    glm::mat4 localFromNode(const tinygltf::Node& node, const std::string& path) const {
        auto finite = [&](const std::vector<double>& values, const char* key) {
            for (double v : values) {
                if (!std::isfinite(v)) fail(path + "/" + key, "holds a non-finite value");
            }
        };
        if (!node.matrix.empty()) {
            if (node.matrix.size() != 16) fail(path + "/matrix", "needs 16 numbers");
            finite(node.matrix, "matrix");
            glm::mat4 m;
            for (int column = 0; column < 4; ++column) {
                for (int row = 0; row < 4; ++row) m[column][row] = float(node.matrix[std::size_t(column * 4 + row)]);
            }
            return m;
        }
        glm::vec3 translation(0.0f), scale(1.0f);
        glm::quat rotation(1.0f, 0.0f, 0.0f, 0.0f);
        if (!node.translation.empty()) {
            if (node.translation.size() != 3) fail(path + "/translation", "needs 3 numbers");
            finite(node.translation, "translation");
            translation = {float(node.translation[0]), float(node.translation[1]), float(node.translation[2])};
        }
        if (!node.rotation.empty()) {
            if (node.rotation.size() != 4) fail(path + "/rotation", "needs 4 numbers (x, y, z, w)");
            finite(node.rotation, "rotation");
            rotation = glm::quat(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]),
                                 float(node.rotation[2]));
            const float length = glm::length(rotation);
            if (!(length > 0.0f)) fail(path + "/rotation", "is a zero quaternion");
            rotation = rotation / length;
        }
        if (!node.scale.empty()) {
            if (node.scale.size() != 3) fail(path + "/scale", "needs 3 numbers");
            finite(node.scale, "scale");
            scale = {float(node.scale[0]), float(node.scale[1]), float(node.scale[2])};
        }
        return glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(rotation) *
               glm::scale(glm::mat4(1.0f), scale);
    }

    Camera cameraFrom(int index, const glm::mat4& worldFromNode, const std::string& nodeName) const {
        const tinygltf::Camera& c = mModel.cameras[std::size_t(index)];
        const std::string path = indexPath("/cameras", std::size_t(index));
        Camera camera;
        camera.name = c.name.empty() ? nodeName : c.name;
        camera.positionWorld = glm::vec3(worldFromNode[3]);
        // Orientation: the node's rotation with scale removed (Gram-Schmidt of the basis).
        glm::vec3 x = glm::vec3(worldFromNode[0]), y = glm::vec3(worldFromNode[1]);
        if (!(glm::length(x) > 0.0f) || !(glm::length(y) > 0.0f)) fail(path, "the camera's node has a zero scale");
        x = glm::normalize(x);
        y = glm::normalize(y - x * glm::dot(x, y));
        camera.orientationWorld = glm::normalize(glm::quat_cast(glm::mat3(x, y, glm::cross(x, y))));
        if (c.type == "perspective") {
            const auto& p = c.perspective;
            camera.projection = ProjectionKind::Perspective;
            if (!(p.yfov > 0.0 && p.yfov < PI)) {
                fail(path + "/perspective/yfov", std::to_string(p.yfov) + " is outside (0, pi)");
            }
            if (!(p.znear > 0.0)) fail(path + "/perspective/znear", std::to_string(p.znear) + " is not positive");
            if (p.zfar != 0.0 && !(p.zfar > p.znear)) {
                fail(path + "/perspective/zfar", std::to_string(p.zfar) + " is not greater than znear");
            }
            if (!(p.aspectRatio >= 0.0)) fail(path + "/perspective/aspectRatio", "is negative");
            camera.fovYDeg = float(p.yfov * 180.0 / PI);
            camera.nearZ = float(p.znear);
            camera.farZ = p.zfar == 0.0 ? std::numeric_limits<float>::infinity() : float(p.zfar);  // absent: infinite
            camera.aspect = float(p.aspectRatio);
        } else if (c.type == "orthographic") {
            const auto& o = c.orthographic;
            camera.projection = ProjectionKind::Orthographic;
            if (o.xmag == 0.0 || !std::isfinite(o.xmag)) fail(path + "/orthographic/xmag", "must be finite and non-zero");
            if (o.ymag == 0.0 || !std::isfinite(o.ymag)) fail(path + "/orthographic/ymag", "must be finite and non-zero");
            if (!(o.znear >= 0.0)) fail(path + "/orthographic/znear", "is negative");
            if (!(o.zfar > o.znear) || !std::isfinite(o.zfar)) {
                fail(path + "/orthographic/zfar", std::to_string(o.zfar) + " is not a finite value greater than znear");
            }
            camera.xMag = float(o.xmag);
            camera.yMag = float(o.ymag);
            camera.nearZ = float(o.znear);
            camera.farZ = float(o.zfar);
        } else {
            fail(path + "/type", "'" + c.type + "' is not perspective or orthographic");
        }
        return camera;
    }

    // KHR_lights_punctual README ("Light Shared Properties", "Range Property", "Spot Properties")
    // and its schema light.schema.json, for EVERY light the file defines, referenced by a node or
    // not (an unplaced light with a bad range is still a bad file, and was passed in silence):
    //   type      "directional", "point" or "spot" (required)
    //   color     3 numbers, each in [0, 1] (schema minimum 0, maximum 1); default [1, 1, 1]
    //   intensity a finite number >= 0 (candela for point and spot, lux for directional); default 1
    //   range     > 0 when given (schema exclusiveMinimum 0); absent: infinite (tinygltf: 0)
    //   spot      0 <= innerConeAngle < outerConeAngle <= pi/2 (radians, half angles)
    // Errors name the light's JSON pointer, /extensions/KHR_lights_punctual/lights/<i>/<key>.
    static constexpr double kHalfPi = PI / 2;  // outerConeAngle's bound, radians
    void checkLights() const {
        for (std::size_t i = 0; i < mModel.lights.size(); ++i) {
            const tinygltf::Light& l = mModel.lights[i];
            const std::string path = indexPath("/extensions/KHR_lights_punctual/lights", i);
            if (l.type != "point" && l.type != "spot" && l.type != "directional")
                fail(path + "/type", "'" + l.type + "' is not point, spot or directional");
            if (!l.color.empty()) {
                if (l.color.size() != 3) fail(path + "/color", "needs 3 numbers, has " + std::to_string(l.color.size()));
                for (std::size_t c = 0; c < 3; ++c)
                    if (!(l.color[c] >= 0.0 && l.color[c] <= 1.0))
                        fail(indexPath(path + "/color", c), formatDouble(l.color[c]) + " is outside [0, 1] (a linear RGB colour)");
            }
            if (!(l.intensity >= 0.0) || !std::isfinite(l.intensity))
                fail(path + "/intensity", formatDouble(l.intensity) + " is not a finite number >= 0");
            if (l.range < 0.0 || !std::isfinite(l.range))
                fail(path + "/range", formatDouble(l.range) + " is not positive (absent means infinite)");
            if (l.type == "spot") {
                const double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
                // The bound pi/2 as written in a file may round either side of the double pi/2:
                // 1e-6 rad of slack (spotHalfAngleDeg is a float of degrees anyway).
                if (!(outer > 0.0 && outer <= kHalfPi + 1e-6))
                    fail(path + "/spot/outerConeAngle", formatDouble(outer) + " is outside (0, pi/2]");
                if (!(inner >= 0.0 && inner < outer))
                    fail(path + "/spot/innerConeAngle", formatDouble(inner) + " is outside [0, outerConeAngle = " +
                                                            formatDouble(outer) + ")");
            }
        }
    }

    // The lights the file defines against those its scene's nodes place (a light may be placed
    // by several nodes, or by none: then it lights nothing, and the file's author should know).
    void reportLights() {
        if (mModel.lights.empty()) return;
        const std::size_t defined = mModel.lights.size(), placed = mPlacedLights.size();
        if (placed == defined) return;
        warn("defines " + std::to_string(defined) + (defined == 1 ? " light, " : " lights, ") + std::to_string(placed) +
             (placed == 1 ? " placed by a node; " : " placed by nodes; ") + std::to_string(defined - placed) +
             " unreferenced (KHR_lights_punctual: a light shines only where a node of the scene places it)");
    }

    static std::string formatDouble(double v) {
        std::ostringstream out;
        out << std::setprecision(17) << v;
        return out.str();
    }

    Light lightFrom(int index, const glm::mat4& worldFromNode, const std::string& nodeName) {
        const tinygltf::Light& l = mModel.lights[std::size_t(index)];
        const std::string path = indexPath("/extensions/KHR_lights_punctual/lights", std::size_t(index));
        mPlacedLights.insert(index);
        Light light;
        light.name = l.name.empty() ? nodeName : l.name;
        if (l.type == "point") light.type = LightType::Point;
        else if (l.type == "spot") light.type = LightType::Spot;
        else light.type = LightType::Directional;  // checkLights: one of the three
        light.color = vectorOf<3>(l.color, glm::vec3(1.0f), path + "/color");
        light.intensity = float(l.intensity);
        // tinygltf reads an absent range as 0; KHR_lights_punctual: absent = infinite.
        light.range = l.range == 0.0 ? std::numeric_limits<float>::infinity() : float(l.range);
        if (light.type == LightType::Spot) {
            light.spotHalfAngleDeg = float(l.spot.outerConeAngle * 180.0 / PI);
            light.spotInnerHalfAngleDeg = float(l.spot.innerConeAngle * 180.0 / PI);
        }
        light.positionWorld = glm::vec3(worldFromNode[3]);
        const glm::vec3 direction = glm::mat3(worldFromNode) * glm::vec3(0.0f, 0.0f, -1.0f);  // the node's -Z
        const float length = glm::length(direction);
        if (light.type != LightType::Point && !(length > 0.0f)) fail(path, "the light's node has a zero scale");
        light.directionWorld = length > 0.0f ? direction / length : glm::vec3(0.0f, 0.0f, -1.0f);
        return light;
    }

    void readNodes() {
        const std::size_t nodeCount = mModel.nodes.size();
        // §3.5.1: the nodes form disjoint strict trees: one parent at most, no cycles.
        std::vector<int> parent(nodeCount, -1);
        for (std::size_t n = 0; n < nodeCount; ++n) {
            const auto& children = mModel.nodes[n].children;
            for (std::size_t k = 0; k < children.size(); ++k) {
                const std::string childPath = indexPath(indexPath("/nodes", n) + "/children", k);
                checkIndex(children[k], nodeCount, childPath, "node");
                int& childParent = parent[std::size_t(children[k])];
                if (childParent != -1) {
                    fail(childPath, "node " + std::to_string(children[k]) + " already has parent " +
                                        std::to_string(childParent) + " (nodes must form strict trees)");
                }
                childParent = int(n);
            }
        }
        for (std::size_t n = 0; n < nodeCount; ++n) {  // walk up: more steps than nodes means a cycle
            std::size_t steps = 0;
            for (int at = parent[n]; at != -1; at = parent[std::size_t(at)]) {
                if (std::size_t(at) == n || ++steps > nodeCount) {
                    fail(indexPath("/nodes", n), "the node is its own ancestor (a cycle in children)");
                }
            }
        }
        std::vector<int> roots;
        std::string rootsPath;
        if (!mModel.scenes.empty()) {
            int sceneIndex = mOptions.sceneIndex >= 0 ? mOptions.sceneIndex : std::max(mModel.defaultScene, 0);
            if (mOptions.sceneIndex >= 0) checkIndex(sceneIndex, mModel.scenes.size(), "/scenes", "scene");
            else checkIndex(sceneIndex, mModel.scenes.size(), "/scene", "scene");
            roots = mModel.scenes[std::size_t(sceneIndex)].nodes;
            rootsPath = indexPath("/scenes", std::size_t(sceneIndex)) + "/nodes";
        } else {
            if (mOptions.sceneIndex >= 0) checkIndex(mOptions.sceneIndex, 0, "/scenes", "scene");
            for (std::size_t n = 0; n < nodeCount; ++n) {  // no scenes: every root node
                if (parent[n] == -1) roots.push_back(int(n));
            }
            rootsPath = "/nodes";
        }
        std::vector<std::uint8_t> visited(nodeCount, 0);
        for (std::size_t r = 0; r < roots.size(); ++r) {
            const std::string rootPath = indexPath(rootsPath, r);
            checkIndex(roots[r], nodeCount, rootPath, "node");
            if (parent[std::size_t(roots[r])] != -1) {
                fail(rootPath, "node " + std::to_string(roots[r]) + " is a child of node " +
                                   std::to_string(parent[std::size_t(roots[r])]) + ", not a root");
            }
            if (visited[std::size_t(roots[r])]) fail(rootPath, "node " + std::to_string(roots[r]) + " is listed twice");
            // Depth-first, children in order, with an explicit stack (deep hierarchies are fine).
            std::vector<std::pair<int, glm::mat4>> stack{{roots[r], mOptions.worldFromFile}};
            while (!stack.empty()) {
                const auto [index, worldFromParent] = stack.back();
                stack.pop_back();
                visited[std::size_t(index)] = 1;
                visitNode(index, worldFromParent, stack);
            }
        }
    }

    void visitNode(int index, const glm::mat4& worldFromParent, std::vector<std::pair<int, glm::mat4>>& stack) {
        const tinygltf::Node& node = mModel.nodes[std::size_t(index)];
        const std::string path = indexPath("/nodes", std::size_t(index));
        const glm::mat4 worldFromNode = worldFromParent * localFromNode(node, path);
        if (node.mesh != -1) {
            checkIndex(node.mesh, mModel.meshes.size(), path + "/mesh", "mesh");
            mOut.instances.push_back({mMeshBase + node.mesh, worldFromNode, node.name, mOptions.lightGroups});
        }
        if (node.skin != -1 && !mSkinWarned) {
            warn(path + "/skin: skins are ignored (meshes are drawn in their bind pose)");
            mSkinWarned = true;
        }
        if (node.camera != -1) {
            checkIndex(node.camera, mModel.cameras.size(), path + "/camera", "camera");
            mOut.cameras.push_back(cameraFrom(node.camera, worldFromNode, node.name));
        }
        const auto lightExtension = node.extensions.find("KHR_lights_punctual");
        if (lightExtension != node.extensions.end() && lightExtension->second.Has("light")) {
            const tinygltf::Value& value = lightExtension->second.Get("light");
            const std::string lightPath = path + "/extensions/KHR_lights_punctual/light";
            if (!value.IsNumber()) fail(lightPath, "is not a number");
            const int light = value.GetNumberAsInt();
            checkIndex(light, mModel.lights.size(), lightPath, "light");
            mOut.lights.push_back(lightFrom(light, worldFromNode, node.name));
        }
        for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) {
            stack.emplace_back(*child, worldFromNode);  // reversed: popped in file order
        }
    }

    std::string mFile;
    fs::path mFolder;
    tinygltf::Model& mModel;
    const GltfLoadOptions& mOptions;
    int mMeshBase, mMaterialBase, mImageBase, mTextureBase;
    bool mQuantization = false;
    std::uint64_t mDecodeBudget = 0;     // bytes (DECODE_BUDGET_BASE + per buffer byte)
    mutable std::uint64_t mDecoded = 0;  // bytes charged so far
    bool mSkinWarned = false;
    std::set<int> mPlacedLights;  // indices of the lights a node of the scene places
};

// The JSON text of a .gltf, or of a .glb's first chunk (§4.4.3: 12-byte header, then chunk
// length, type "JSON" and the text). Empty when the chunk is not there.
std::string gltfJsonText(std::string_view bytes, bool binary) {
    if (!binary) return std::string(bytes);
    if (bytes.size() < 20 || bytes.substr(16, 4) != "JSON") return {};
    std::uint32_t length;
    std::memcpy(&length, bytes.data() + 12, 4);
    if (length > bytes.size() - 20) return {};
    return std::string(bytes.substr(20, length));
}

// A .glb whose BIN chunk (§4.4.3.3: length, type "BIN", data) runs past the header's total
// length: tinygltf 2.7.0 checks the chunk's data length against the length without its 8-byte
// chunk header, and then copies up to 8 bytes past the end of the data. Empty when the chunk
// fits (other malformed layouts are left to tinygltf, which refuses them).
std::string glbBinChunkOverrun(std::string_view bytes) {
    if (bytes.size() < 20) return {};
    std::uint32_t length, jsonLength;
    std::memcpy(&length, bytes.data() + 8, 4);
    std::memcpy(&jsonLength, bytes.data() + 12, 4);
    const std::uint64_t binAt = 20 + std::uint64_t(jsonLength);  // the BIN chunk header
    if (length > bytes.size() || binAt + 8 > length) return {};
    std::uint32_t binLength;
    std::memcpy(&binLength, bytes.data() + binAt, 4);
    if (binAt + 8 + binLength <= length) return {};
    return "the BIN chunk's " + std::to_string(binLength) + " bytes at byte " + std::to_string(binAt + 8) +
           " run past the GLB's length of " + std::to_string(length) + " bytes";
}

// tinygltf's error text on one line; for a missing external buffer ("File not found : X"),
// the JSON path of the buffer whose uri names it.
std::pair<std::string, std::string> describeParseError(std::string err, const std::string& jsonText, const fs::path& baseDir) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    std::string keyPath, what = err;
    const std::string notFound = "File not found : ";
    const std::size_t at = err.find(notFound);
    if (at != std::string::npos) {
        const std::size_t begin = at + notFound.size();
        const std::string missing = err.substr(begin, err.find('\n', begin) - begin);
        const nlohmann::json doc = nlohmann::json::parse(jsonText, nullptr, false);
        if (doc.is_object() && doc.contains("buffers") && doc["buffers"].is_array()) {
            for (std::size_t i = 0; i < doc["buffers"].size(); ++i) {
                const nlohmann::json& buffer = doc["buffers"][i];
                if (buffer.is_object() && buffer.contains("uri") && buffer["uri"].is_string() &&
                    percentDecoded(buffer["uri"].get<std::string>()) == missing) {
                    keyPath = indexPath("/buffers", i) + "/uri";
                    what = "cannot read the buffer file '" + (baseDir / missing).string() + "'";
                    break;
                }
            }
        }
    }
    std::replace(what.begin(), what.end(), '\n', ';');
    return {keyPath, what.empty() ? std::string("tinygltf reported an error without a message") : what};
}

// Both entry points: the bytes of a .gltf or .glb, `fileName` for messages, `baseDir` for
// external uris.
void loadGltfBytes(std::string_view bytes, const std::string& fileName, const fs::path& baseDir, Scene& scene,
                   const GltfLoadOptions& options) {
    if (bytes.size() > std::numeric_limits<unsigned int>::max())
        throw inputError(fileName, "", "the file is larger than 4 GiB");  // tinygltf takes an unsigned int size
    const bool binary = bytes.size() >= 4 && bytes.substr(0, 4) == "glTF";  // GLB header (§4.4.2)

    // JSON syntax and types first (tinygltf would default mistyped values silently).
    const std::string jsonText = gltfJsonText(bytes, binary);
    {
        // Before any parse: tinygltf's JSON parse recurses once per nesting level.
        checkJsonDepth(jsonText, fileName);
        if (!jsonText.empty() || !binary) {
            nlohmann::json document;
            try {
                document = nlohmann::json::parse(jsonText);
            } catch (const nlohmann::json::exception& e) {
                // parse_error, and out_of_range 406 for a number beyond double ("1e999").
                throw inputError(fileName, "", std::string("invalid JSON: ") + e.what());
            }
            JsonShapeChecker(fileName).check(document);
        }
    }

    if (binary) {
        if (const std::string problem = glbBinChunkOverrun(bytes); !problem.empty()) throw inputError(fileName, "", problem);
    }
    tinygltf::TinyGLTF parser;
    ImageLoaderState imageState;
    imageState.loadImages = options.loadImages;
    parser.SetImageLoader(&loadImageData, &imageState);
    tinygltf::Model model;
    std::string err, warnText;
    const auto size = static_cast<unsigned int>(bytes.size());
    const bool parsed =
        binary ? parser.LoadBinaryFromMemory(&model, &err, &warnText, reinterpret_cast<const unsigned char*>(bytes.data()),
                                             size, baseDir.string())
               : parser.LoadASCIIFromString(&model, &err, &warnText, bytes.data(), size, baseDir.string());
    if (!imageState.errors.empty()) {
        const auto& [index, what] = imageState.errors.front();
        throw inputError(fileName, "/images/" + std::to_string(index), what);
    }
    if (!parsed) {
        const auto [keyPath, what] = describeParseError(err, jsonText, baseDir);
        throw inputError(fileName, keyPath, what);
    }

    GltfReader reader(fileName, baseDir, model, options, scene);
    std::string line;
    for (char c : warnText + "\n") {
        if (c != '\n') { line += c; continue; }
        // tinygltf warns about unreadable external images; readImages() turns those into errors.
        if (!line.empty() && line.rfind("File not found", 0) != 0 && line.rfind("Failed to load external 'uri' for image", 0) != 0) {
            reader.mWarnings.push_back(fileName + ": " + line);
        }
        line.clear();
    }
    reader.read();

    // Everything passed: append (the target scene is untouched when the file is rejected).
    auto append = [](auto& to, auto& from) {
        to.insert(to.end(), std::make_move_iterator(from.begin()), std::make_move_iterator(from.end()));
    };
    append(scene.meshes, reader.mOut.meshes);
    append(scene.instances, reader.mOut.instances);
    append(scene.materials, reader.mOut.materials);
    append(scene.images, reader.mOut.images);
    append(scene.textures, reader.mOut.textures);
    append(scene.cameras, reader.mOut.cameras);
    append(scene.lights, reader.mOut.lights);
    for (const std::string& warning : reader.mWarnings) {
        if (options.warnings) options.warnings->push_back(warning);
        else std::fprintf(stderr, "tessera: warning: %s\n", warning.c_str());
    }
}

} // namespace

void loadGltf(const fs::path& file, Scene& scene, const GltfLoadOptions& options) {
    const std::string fileName = file.string();
    std::ifstream in(file, std::ios::binary);
    std::error_code ec;
    if (!in || !fs::is_regular_file(file, ec)) throw inputError(fileName, "", "cannot open the file");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw inputError(fileName, "", "read error");
    loadGltfBytes(bytes, fileName, file.parent_path(), scene, options);
}

void loadGltfFromMemory(std::string_view bytes, const std::string& name, const fs::path& baseDir, Scene& scene,
                        const GltfLoadOptions& options) {
    loadGltfBytes(bytes, name, baseDir, scene, options);
}

} // namespace tessera
