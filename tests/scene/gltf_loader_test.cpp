// glTF loader tests: counts on the bundled Khronos models, hand-written glTF files (written by
// the test as JSON with base64 data URIs) whose decoded values are derived by hand, and every
// kind of bad input, which must raise InputError naming the file and the JSON path.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <tessera/errors/input_error.h>
#include <tessera/scene/gltf_loader.h>
#include <tessera/scene/scene.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::scene_gltf_loader_test {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace tessera;

namespace {

const fs::path KHRONOS = fs::path(TESSERA_SOURCE_DIR) / "scenes" / "khronos";
const fs::path ASSIMP_GLTF2 = "/usr/share/assimp/models/glTF2";  // Debian package assimp-testmodels
constexpr double PI = 3.14159265358979323846;

constexpr int BYTE = 5120, UBYTE = 5121, SHORT = 5122, USHORT = 5123, UINT = 5125, FLOAT = 5126;

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::path(TESSERA_TEST_OUTPUT_DIR) / "gltf-out";
    fs::create_directories(dir);
    return dir / name;
}

std::string base64(const std::vector<std::uint8_t>& bytes) {
    static const char* ALPHABET = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t n = std::uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? bytes[i + 1] << 8 : 0) |
                                (i + 2 < bytes.size() ? bytes[i + 2] : 0);
        out += ALPHABET[n >> 18 & 63];
        out += ALPHABET[n >> 12 & 63];
        out += i + 1 < bytes.size() ? ALPHABET[n >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? ALPHABET[n & 63] : '=';
    }
    return out;
}

// A glTF file under construction: one buffer (embedded as a data URI when written).
struct GltfFile {
    json doc = {{"asset", {{"version", "2.0"}}}, {"bufferViews", json::array()}, {"accessors", json::array()}};
    std::vector<std::uint8_t> bin;

    template <class T>
    int view(const std::vector<T>& values, int byteStride = 0) {
        while (bin.size() % 4) bin.push_back(0);
        const std::size_t offset = bin.size();
        bin.resize(offset + values.size() * sizeof(T));
        std::memcpy(bin.data() + offset, values.data(), values.size() * sizeof(T));
        json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}};
        if (byteStride) v["byteStride"] = byteStride;
        doc["bufferViews"].push_back(v);
        return int(doc["bufferViews"].size() - 1);
    }
    int accessor(int bufferView, int componentType, std::size_t count, const char* type, bool normalized = false,
                 std::size_t byteOffset = 0) {
        json a = {{"bufferView", bufferView}, {"componentType", componentType}, {"count", count}, {"type", type}};
        if (normalized) a["normalized"] = true;
        if (byteOffset) a["byteOffset"] = byteOffset;
        doc["accessors"].push_back(a);
        return int(doc["accessors"].size() - 1);
    }
    template <class T>
    int data(const std::vector<T>& values, int componentType, const char* type, std::size_t components,
             bool normalized = false) {
        return accessor(view(values), componentType, values.size() / components, type, normalized);
    }
    // One mesh with one primitive, one node, one scene.
    void singleMesh(json primitive) {
        doc["meshes"] = json::array({{{"primitives", json::array({primitive})}}});
        doc["nodes"] = json::array({{{"mesh", 0}}});
        doc["scenes"] = json::array({{{"nodes", {0}}}});
        doc["scene"] = 0;
    }
    fs::path write(const std::string& name) const {
        json out = doc;
        if (!bin.empty()) {
            out["buffers"] = json::array(
                {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
        }
        const fs::path path = scratch(name);
        std::ofstream(path) << out.dump(1);
        return path;
    }
};

// A unit quad in z = 0 (normal +z), counter-clockwise seen from +z: 0 (0,0) 1 (1,0) 2 (1,1) 3 (0,1).
const std::vector<float> QUAD_POSITIONS = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
const std::vector<float> QUAD_NORMALS = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
const std::vector<std::uint16_t> QUAD_INDICES = {0, 1, 2, 0, 2, 3};

GltfFile quadFile(const std::vector<float>& uvs = {}) {
    GltfFile f;
    json primitive = {{"attributes", {{"POSITION", f.data(QUAD_POSITIONS, FLOAT, "VEC3", 3)},
                                      {"NORMAL", f.data(QUAD_NORMALS, FLOAT, "VEC3", 3)}}},
                      {"indices", f.data(QUAD_INDICES, USHORT, "SCALAR", 1)}};
    if (!uvs.empty()) primitive["attributes"]["TEXCOORD_0"] = f.data(uvs, FLOAT, "VEC2", 2);
    f.singleMesh(primitive);
    return f;
}

Scene load(const fs::path& file, std::vector<std::string>* warnings = nullptr, bool loadImages = true,
           bool generatedBitangentUp = true) {
    Scene scene;
    GltfLoadOptions options;
    options.loadImages = loadImages;
    options.generatedBitangentUp = generatedBitangentUp;
    std::vector<std::string> sink;
    options.warnings = warnings ? warnings : &sink;
    loadGltf(file, scene, options);
    return scene;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Loading must throw InputError whose message names the file and contains every `needles` part;
// the scene must be left untouched.
void expectInputError(const fs::path& file, std::initializer_list<std::string> needles, bool loadImages = true) {
    Scene scene;
    scene.materials.emplace_back();
    GltfLoadOptions options;
    options.loadImages = loadImages;
    std::vector<std::string> warnings;
    options.warnings = &warnings;
    std::string message;
    try {
        loadGltf(file, scene, options);
    } catch (const InputError& e) {
        message = e.what();
    }
    INFO("file: " << file.string() << "\nmessage: " << message);
    REQUIRE_MESSAGE(!message.empty(), "no InputError");
    CHECK(contains(message, file.string()));
    for (const std::string& needle : needles) CHECK_MESSAGE(contains(message, needle), "missing: " << needle);
    CHECK(scene.meshes.empty());
    CHECK(scene.materials.size() == 1);
}

// ---- tiny PNG writer (stored deflate blocks), for image decoding cases

std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0) {
    crc = ~crc;
    for (std::size_t i = 0; i < size; ++i) {
        crc ^= data[i];
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

void putBigEndian(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(std::uint8_t(v >> shift));
}

void pngChunk(std::vector<std::uint8_t>& png, const char* type, const std::vector<std::uint8_t>& payload) {
    putBigEndian(png, std::uint32_t(payload.size()));
    std::vector<std::uint8_t> typed(type, type + 4);
    typed.insert(typed.end(), payload.begin(), payload.end());
    png.insert(png.end(), typed.begin(), typed.end());
    putBigEndian(png, crc32(typed.data(), typed.size()));
}

// colorType: 0 grey, 2 RGB, 4 grey+alpha, 6 RGBA. `rows`: filter byte 0 + samples per row
// (big-endian for 16 bits). withData = false writes the header only (IHDR + IEND).
std::vector<std::uint8_t> makePng(std::uint32_t width, std::uint32_t height, int colorType, int bitDepth,
                                  const std::vector<std::uint8_t>& rows, bool withData = true) {
    std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    std::vector<std::uint8_t> header;
    putBigEndian(header, width);
    putBigEndian(header, height);
    header.insert(header.end(), {std::uint8_t(bitDepth), std::uint8_t(colorType), 0, 0, 0});
    pngChunk(png, "IHDR", header);
    if (withData) {
        std::vector<std::uint8_t> zlib = {0x78, 0x01, 0x01};  // zlib header, final stored block
        const auto length = std::uint16_t(rows.size());
        zlib.insert(zlib.end(), {std::uint8_t(length), std::uint8_t(length >> 8), std::uint8_t(~length),
                                 std::uint8_t(~length >> 8)});
        zlib.insert(zlib.end(), rows.begin(), rows.end());
        std::uint32_t a = 1, b = 0;  // Adler-32
        for (std::uint8_t byte : rows) {
            a = (a + byte) % 65521;
            b = (b + a) % 65521;
        }
        putBigEndian(zlib, b << 16 | a);
        pngChunk(png, "IDAT", zlib);
    }
    pngChunk(png, "IEND", {});
    return png;
}

// A quad file with one textured material whose image is `png` (embedded as a data URI).
fs::path texturedQuad(const std::string& name, const std::vector<std::uint8_t>& png) {
    GltfFile f = quadFile({0, 0, 1, 0, 1, 1, 0, 1});
    f.doc["images"] = json::array({{{"uri", "data:image/png;base64," + base64(png)}}});
    f.doc["textures"] = json::array({{{"source", 0}}});
    f.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    f.doc["meshes"][0]["primitives"][0]["material"] = 0;
    return f.write(name);
}

glm::vec3 transformPoint(const glm::mat4& m, const glm::vec3& p) { return glm::vec3(m * glm::vec4(p, 1.0f)); }

void checkNear(const glm::vec3& actual, const glm::vec3& expected, float tolerance = 1e-5f) {
    INFO("actual (" << actual.x << ", " << actual.y << ", " << actual.z << ") expected (" << expected.x << ", "
                    << expected.y << ", " << expected.z << ")");
    CHECK(glm::length(actual - expected) <= tolerance);
}

} // namespace

// ---- Khronos sample models ---------------------------------------------------------------------

TEST_CASE("gltf: Khronos Box: 1 mesh, 12 triangles, normals, no UVs so no tangents") {
    const Scene scene = load(KHRONOS / "Box" / "glTF" / "Box.gltf");
    REQUIRE(scene.meshes.size() == 1);
    REQUIRE(scene.meshes[0].primitives.size() == 1);
    const MeshPrimitive& prim = scene.meshes[0].primitives[0];
    CHECK(prim.triangleCount() == 12);
    CHECK(prim.positionsObject.size() == 24);
    CHECK(prim.normalsObject.size() == 24);
    CHECK(prim.texCoords0.empty());
    CHECK(prim.tangentsObject.empty());
    CHECK_FALSE(prim.tangentsGenerated);
    CHECK(prim.material == 0);
    CHECK(scene.instances.size() == 1);
    CHECK(scene.triangleCount() == 12);
    CHECK(scene.materials.size() == 1);
    CHECK(scene.images.empty());
    // The unit cube under the root's Y-up -> Z-up matrix is still [-0.5, 0.5]^3.
    const Bounds bounds = scene.bounds();
    checkNear(bounds.minWorld, glm::vec3(-0.5f));
    checkNear(bounds.maxWorld, glm::vec3(0.5f));
    CHECK(scene.memoryBytes() == 24 * (12 + 12) + 36 * 4);
}

TEST_CASE("gltf: Khronos BoxTextured: a palette PNG decoded to RGBA8, its sampler, generated tangents") {
    const Scene scene = load(KHRONOS / "BoxTextured" / "glTF" / "BoxTextured.gltf");
    REQUIRE(scene.images.size() == 1);
    const Image& image = scene.images[0];
    CHECK(image.width == 256);
    CHECK(image.height == 256);
    CHECK(image.rgba8.size() == 256u * 256u * 4u);
    CHECK(contains(image.source, "CesiumLogoFlat.png"));
    REQUIRE(scene.textures.size() == 1);
    const SamplerState& sampler = scene.textures[0].sampler;  // mag 9729, min 9986, wrap 10497
    CHECK(sampler.magFilter == Filter::Linear);
    CHECK(sampler.minFilter == Filter::Point);
    CHECK(sampler.mipFilter == Filter::Linear);
    CHECK(sampler.addressU == AddressMode::Wrap);
    CHECK(sampler.addressV == AddressMode::Wrap);
    REQUIRE(scene.materials.size() == 1);
    CHECK(scene.materials[0].baseColorTexture.texture == 0);
    const MeshPrimitive& prim = scene.meshes.at(0).primitives.at(0);
    CHECK(prim.triangleCount() == 12);
    CHECK(prim.tangentsGenerated);
    REQUIRE(prim.tangentsObject.size() == prim.positionsObject.size());
    for (std::size_t v = 0; v < prim.tangentsObject.size(); ++v) {
        const glm::vec3 t(prim.tangentsObject[v]);
        CHECK(std::abs(glm::length(t) - 1.0f) < 1e-5f);
        CHECK(std::abs(glm::dot(t, prim.normalsObject[v])) < 1e-5f);
        CHECK(std::abs(prim.tangentsObject[v].w) == 1.0f);
    }

    // Without images: the record and its size remain, the pixels are not decoded.
    const Scene header = load(KHRONOS / "BoxTextured" / "glTF" / "BoxTextured.gltf", nullptr, false);
    REQUIRE(header.images.size() == 1);
    CHECK(header.images[0].width == 256);
    CHECK(header.images[0].height == 256);
    CHECK(header.images[0].rgba8.empty());
}

TEST_CASE("gltf: Khronos AlphaBlendModeTest: alpha modes, cutoffs (default 0.5), doubleSided, TANGENT kept") {
    const Scene scene = load(KHRONOS / "AlphaBlendModeTest" / "glTF" / "AlphaBlendModeTest.gltf");
    CHECK(scene.meshes.size() == 9);
    CHECK(scene.instances.size() == 9);
    CHECK(scene.images.size() == 4);
    CHECK(scene.textures.size() == 4);
    CHECK(scene.triangleCount() == 61);
    REQUIRE(scene.materials.size() == 6);
    struct Expected {
        const char* name;
        AlphaMode mode;
        float cutoff;
        bool doubleSided;
    };
    const Expected expected[] = {{"MatBed", AlphaMode::Opaque, 0.5f, false},
                                 {"MatBlend", AlphaMode::Blend, 0.5f, true},
                                 {"MatCutoff25", AlphaMode::Mask, 0.25f, true},
                                 {"MatCutoff75", AlphaMode::Mask, 0.75f, true},
                                 {"MatCutoffDefault", AlphaMode::Mask, 0.5f, true},
                                 {"MatOpaque", AlphaMode::Opaque, 0.5f, true}};
    for (std::size_t i = 0; i < 6; ++i) {
        CAPTURE(i);
        CHECK(scene.materials[i].name == expected[i].name);
        CHECK(scene.materials[i].alphaMode == expected[i].mode);
        CHECK(scene.materials[i].alphaCutoff == expected[i].cutoff);
        CHECK(scene.materials[i].doubleSided == expected[i].doubleSided);
    }
    for (const Image& image : scene.images) CHECK(image.rgba8.size() == std::size_t(image.width) * image.height * 4);
    // The file supplies TANGENT: kept as given, not regenerated.
    for (const Mesh& mesh : scene.meshes) {
        for (const MeshPrimitive& prim : mesh.primitives) {
            CHECK_FALSE(prim.tangentsGenerated);
            CHECK(prim.tangentsObject.size() == prim.positionsObject.size());
        }
    }
    // The sampler is {}: glTF defaults (repeat, linear, linear-mip-linear).
    CHECK(scene.textures[0].sampler.addressU == AddressMode::Wrap);
    CHECK(scene.textures[0].sampler.minFilter == Filter::Linear);
    CHECK(scene.textures[0].sampler.mipFilter == Filter::Linear);
}

TEST_CASE("gltf: Khronos MetalRoughSpheresNoTextures: 102 meshes, 123 primitives, 98 materials") {
    const Scene scene = load(KHRONOS / "MetalRoughSpheresNoTextures" / "glTF" / "MetalRoughSpheresNoTextures.gltf");
    CHECK(scene.meshes.size() == 102);
    std::size_t primitives = 0;
    for (const Mesh& mesh : scene.meshes) primitives += mesh.primitives.size();
    CHECK(primitives == 123);
    CHECK(scene.materials.size() == 98);
    CHECK(scene.instances.size() == 102);
    CHECK(scene.triangleCount() == 1040409);
    CHECK(scene.materials[0].name == "mat_0");
    CHECK(scene.materials[0].metallicFactor == 0.0f);
    CHECK(scene.materials[0].baseColorFactor.x == doctest::Approx(0.6038269996643066));
    CHECK(scene.images.empty());
}

TEST_CASE("gltf: binary glTF (.glb) with its image in a bufferView") {
    const Scene scene = load(ASSIMP_GLTF2 / "BoxTextured-glTF-Binary" / "BoxTextured.glb");
    CHECK(scene.triangleCount() == 12);
    REQUIRE(scene.images.size() == 1);
    CHECK(scene.images[0].width > 0);
    CHECK(scene.images[0].rgba8.size() == std::size_t(scene.images[0].width) * scene.images[0].height * 4);
    CHECK(contains(scene.images[0].source, "BoxTextured.glb#/images/0"));
}

TEST_CASE("gltf: appending a second file offsets mesh, material and texture indices") {
    Scene scene;
    GltfLoadOptions options;
    std::vector<std::string> warnings;
    options.warnings = &warnings;
    loadGltf(KHRONOS / "Box" / "glTF" / "Box.gltf", scene, options);
    loadGltf(KHRONOS / "BoxTextured" / "glTF" / "BoxTextured.gltf", scene, options);
    REQUIRE(scene.meshes.size() == 2);
    CHECK(scene.instances[1].mesh == 1);
    CHECK(scene.meshes[1].primitives[0].material == 1);
    CHECK(scene.materials[1].baseColorTexture.texture == 0);
    CHECK(scene.textures[0].image == 0);
    CHECK(scene.triangleCount() == 24);
    CHECK(warnings.empty());
}

// ---- hand-written files: decoding ---------------------------------------------------------------

TEST_CASE("gltf: u8, u16 and u32 indices decode to the same triangles, non-indexed primitives too") {
    const std::vector<std::uint32_t> expected = {0, 1, 2, 0, 2, 3};
    for (int width : {UBYTE, USHORT, UINT, 0}) {
        CAPTURE(width);
        GltfFile f;
        json primitive = {{"attributes", {{"POSITION", f.data(QUAD_POSITIONS, FLOAT, "VEC3", 3)}}}};
        if (width == UBYTE) primitive["indices"] = f.data(std::vector<std::uint8_t>{0, 1, 2, 0, 2, 3}, UBYTE, "SCALAR", 1);
        if (width == USHORT) primitive["indices"] = f.data(QUAD_INDICES, USHORT, "SCALAR", 1);
        if (width == UINT) primitive["indices"] = f.data(std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}, UINT, "SCALAR", 1);
        if (width == 0) {  // non-indexed: the six corners spelled out
            std::vector<float> corners;
            for (std::uint32_t i : expected) corners.insert(corners.end(), &QUAD_POSITIONS[i * 3], &QUAD_POSITIONS[i * 3 + 3]);
            primitive["attributes"]["POSITION"] = f.data(corners, FLOAT, "VEC3", 3);
        }
        primitive["attributes"]["NORMAL"] = f.data(std::vector<float>(width == 0 ? 18 : 12, 0.0f), FLOAT, "VEC3", 3);
        f.singleMesh(primitive);
        const Scene scene = load(f.write("indices.gltf"));
        const MeshPrimitive& prim = scene.meshes.at(0).primitives.at(0);
        CHECK(prim.triangleCount() == 2);
        if (width != 0) CHECK(prim.indices == expected);
        else CHECK(prim.indices == std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5});
    }
}

TEST_CASE("gltf: KHR_mesh_quantization: normalized SHORT/BYTE/UBYTE and integer positions (glTF 2.0 §3.11)") {
    GltfFile f;
    f.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    f.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    // SHORT normalized: max(c / 32767, -1): -32768 -> -1, 32767 -> 1, 16384 -> 16384/32767.
    const int positions = f.data(std::vector<std::int16_t>{-32768, 32767, 16384, 0, 0, 0, 0, 1, 0, 0}, SHORT,
                                 "VEC3", 3, true);
    f.doc["accessors"][positions]["count"] = 3;
    // BYTE normalized: max(c / 127, -1): -128 -> -1, 127 -> 1, 64 -> 64/127 (padded to 4 bytes per element).
    const int normalsView = f.view(std::vector<std::int8_t>{-128, 0, 0, 0, 127, 0, 0, 0, 64, 0, 0, 0}, 4);
    const int normals = f.accessor(normalsView, BYTE, 3, "VEC3", true);
    // UBYTE normalized texcoords: c / 255.
    const int uvs = f.data(std::vector<std::uint8_t>{0, 255, 51, 102, 255, 0}, UBYTE, "VEC2", 2, true);
    f.singleMesh({{"attributes", {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}}}});
    const Scene scene = load(f.write("quantized.gltf"));
    const MeshPrimitive& prim = scene.meshes.at(0).primitives.at(0);
    CHECK(prim.positionsObject[0] == glm::vec3(-1.0f, 1.0f, 16384.0f / 32767.0f));
    CHECK(prim.positionsObject[1] == glm::vec3(0.0f));
    CHECK(prim.positionsObject[2] == glm::vec3(0.0f, 1.0f / 32767.0f, 0.0f));
    CHECK(prim.normalsObject[0] == glm::vec3(-1.0f, 0.0f, 0.0f));
    CHECK(prim.normalsObject[1] == glm::vec3(1.0f, 0.0f, 0.0f));
    CHECK(prim.normalsObject[2] == glm::vec3(64.0f / 127.0f, 0.0f, 0.0f));
    CHECK(prim.texCoords0[0] == glm::vec2(0.0f, 1.0f));
    CHECK(prim.texCoords0[1] == glm::vec2(51.0f / 255.0f, 102.0f / 255.0f));

    // Non-normalized USHORT positions are their integer values.
    GltfFile g;
    g.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    const int integers = g.data(std::vector<std::uint16_t>{0, 0, 0, 1000, 0, 0, 0, 65535, 7, 0}, USHORT, "VEC3", 3);
    g.doc["accessors"][integers]["count"] = 3;
    g.singleMesh({{"attributes", {{"POSITION", integers}}}});
    const Scene integerScene = load(g.write("quantized-int.gltf"));
    const MeshPrimitive& flat = integerScene.meshes.at(0).primitives.at(0);
    CHECK(flat.positionsObject[1] == glm::vec3(1000.0f, 0.0f, 0.0f));
    CHECK(flat.positionsObject[2] == glm::vec3(0.0f, 65535.0f, 7.0f));

    // The same file without the extension declared: a format error on the accessor.
    g.doc.erase("extensionsUsed");
    expectInputError(g.write("quantized-undeclared.gltf"), {"/accessors/0", "POSITION must be VEC3 of FLOAT"});
}

TEST_CASE("gltf: interleaved attributes through byteStride, COLOR_0 VEC3 and TEXCOORD_1") {
    GltfFile f;
    // position xyz, uv0 uv, colour rgb: 8 floats = 32 bytes per vertex.
    std::vector<float> interleaved;
    for (int v = 0; v < 4; ++v) {
        interleaved.insert(interleaved.end(), &QUAD_POSITIONS[v * 3], &QUAD_POSITIONS[v * 3 + 3]);
        interleaved.insert(interleaved.end(), {float(v), float(10 + v), 0.25f * float(v), 0.5f, 1.0f});
    }
    const int view = f.view(interleaved, 32);
    const int positions = f.accessor(view, FLOAT, 4, "VEC3");
    const int uv1 = f.accessor(view, FLOAT, 4, "VEC2", false, 12);
    const int colors = f.accessor(view, FLOAT, 4, "VEC3", false, 20);
    f.singleMesh({{"attributes", {{"POSITION", positions}, {"TEXCOORD_1", uv1}, {"COLOR_0", colors}}},
                  {"indices", f.data(QUAD_INDICES, USHORT, "SCALAR", 1)}});
    const Scene scene = load(f.write("interleaved.gltf"));
    const MeshPrimitive& prim = scene.meshes.at(0).primitives.at(0);
    // No NORMAL: flat normals, unwelded to 6 vertices in index order 0 1 2 0 2 3.
    REQUIRE(prim.positionsObject.size() == 6);
    CHECK(prim.positionsObject[4] == glm::vec3(1.0f, 1.0f, 0.0f));
    CHECK(prim.texCoords1[4] == glm::vec2(2.0f, 12.0f));
    CHECK(prim.colors0[5] == glm::vec4(0.75f, 0.5f, 1.0f, 1.0f));
    for (const glm::vec3& n : prim.normalsObject) CHECK(n == glm::vec3(0.0f, 0.0f, 1.0f));
    CHECK(prim.texCoords0.empty());
    CHECK(prim.tangentsObject.empty());  // no TEXCOORD_0 to follow
}

TEST_CASE("gltf: sparse accessors substitute values, with and without a base bufferView") {
    GltfFile f;
    const int positions = f.data(QUAD_POSITIONS, FLOAT, "VEC3", 3);
    const int sparseIndices = f.view(std::vector<std::uint16_t>{1, 3});
    const int sparseValues = f.view(std::vector<float>{5, 5, 5, 7, 7, 7});
    const json sparse = {{"count", 2},
                         {"indices", {{"bufferView", sparseIndices}, {"componentType", USHORT}}},
                         {"values", {{"bufferView", sparseValues}}}};
    f.doc["accessors"][positions]["sparse"] = sparse;
    const int zeros = f.accessor(0, FLOAT, 4, "VEC3");
    f.doc["accessors"][zeros].erase("bufferView");
    f.doc["accessors"][zeros]["sparse"] = sparse;
    const int normals = f.data(QUAD_NORMALS, FLOAT, "VEC3", 3);
    const int indices = f.data(QUAD_INDICES, USHORT, "SCALAR", 1);
    f.doc["meshes"] = json::array({{{"primitives",
                                     {{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}}, {"indices", indices}},
                                      {{"attributes", {{"POSITION", zeros}, {"NORMAL", normals}}}, {"indices", indices}}}}}});
    f.doc["nodes"] = json::array({{{"mesh", 0}}});
    const Scene scene = load(f.write("sparse.gltf"));
    const MeshPrimitive& a = scene.meshes.at(0).primitives.at(0);
    CHECK(a.positionsObject[0] == glm::vec3(0.0f));
    CHECK(a.positionsObject[1] == glm::vec3(5.0f));
    CHECK(a.positionsObject[2] == glm::vec3(1.0f, 1.0f, 0.0f));
    CHECK(a.positionsObject[3] == glm::vec3(7.0f));
    const MeshPrimitive& b = scene.meshes.at(0).primitives.at(1);
    CHECK(b.positionsObject[0] == glm::vec3(0.0f));
    CHECK(b.positionsObject[1] == glm::vec3(5.0f));
    CHECK(b.positionsObject[2] == glm::vec3(0.0f));
    // No "scenes": the root nodes are instantiated.
    CHECK(scene.instances.size() == 1);
}

TEST_CASE("gltf: TRIANGLE_STRIP and TRIANGLE_FAN become lists (§3.7.2.1), points and lines are skipped with a warning") {
    GltfFile f;
    const int positions = f.data(QUAD_POSITIONS, FLOAT, "VEC3", 3);
    const int normals = f.data(QUAD_NORMALS, FLOAT, "VEC3", 3);
    const json attributes = {{"POSITION", positions}, {"NORMAL", normals}};
    f.doc["meshes"] = json::array({{{"primitives", {{{"attributes", attributes}, {"mode", 5}},
                                                    {{"attributes", attributes}, {"mode", 6}},
                                                    {{"attributes", attributes}, {"mode", 0}},
                                                    {{"attributes", attributes}, {"mode", 3}}}}}});
    f.doc["nodes"] = json::array({{{"mesh", 0}}});
    f.doc["scenes"] = json::array({{{"nodes", {0}}}});
    std::vector<std::string> warnings;
    const Scene scene = load(f.write("modes.gltf"), &warnings);
    REQUIRE(scene.meshes.at(0).primitives.size() == 2);
    // Strip 0 1 2 3: p0 = {0, 1, 2}, p1 = {v1, v3, v2}.
    CHECK(scene.meshes[0].primitives[0].indices == std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2});
    // Fan 0 1 2 3: p_i = {v_{i+1}, v_{i+2}, v_0}.
    CHECK(scene.meshes[0].primitives[1].indices == std::vector<std::uint32_t>{1, 2, 0, 2, 3, 0});
    REQUIRE(warnings.size() == 1);
    CHECK(contains(warnings[0], "2 primitive(s)"));
    CHECK(contains(warnings[0], "/meshes/0/primitives/2"));
    CHECK(contains(warnings[0], "modes.gltf"));
}

TEST_CASE("gltf: node hierarchy: parent TRS x child matrix, the same mesh instanced from two nodes") {
    GltfFile f;
    const int positions = f.data(std::vector<float>{1, 0, 0, 0, 0, 0, 0, 0, 1}, FLOAT, "VEC3", 3);
    f.doc["meshes"] = json::array({{{"primitives", {{{"attributes", {{"POSITION", positions}}}}}}}});
    const double h = std::sqrt(0.5);
    f.doc["nodes"] = json::array({
        {{"name", "parent"}, {"translation", {10, 0, 0}}, {"rotation", {0, 0, h, h}}, {"scale", {2, 2, 2}}, {"children", {1}}},
        {{"name", "child"}, {"mesh", 0}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1}}},
        {{"name", "second"}, {"mesh", 0}, {"translation", {0, 0, 5}}},
    });
    f.doc["scenes"] = json::array({{{"nodes", {0, 2}}}});
    const Scene scene = load(f.write("hierarchy.gltf"));
    REQUIRE(scene.instances.size() == 2);
    CHECK(scene.instances[0].nodeName == "child");
    CHECK(scene.instances[0].mesh == scene.instances[1].mesh);
    // (1,0,0): child +(0,1,0) -> (1,1,0); scale 2 -> (2,2,0); 90 deg about +Z -> (-2,2,0); +(10,0,0) -> (8,2,0).
    checkNear(transformPoint(scene.instances[0].worldFromObject, {1.0f, 0.0f, 0.0f}), {8.0f, 2.0f, 0.0f});
    checkNear(transformPoint(scene.instances[1].worldFromObject, {1.0f, 0.0f, 0.0f}), {1.0f, 0.0f, 5.0f});
    CHECK(scene.triangleCount() == 2);
    const Bounds bounds = scene.bounds();
    // Instance 0: (8,2,0) (8,0,0) (8,0,2); instance 1: (1,0,5) (0,0,5) (0,0,6).
    checkNear(bounds.minWorld, {0.0f, 0.0f, 0.0f});
    checkNear(bounds.maxWorld, {8.0f, 2.0f, 6.0f});
    // worldFromFile sits above the roots.
    Scene moved;
    GltfLoadOptions options;
    options.worldFromFile = glm::mat4(1.0f);
    options.worldFromFile[3] = glm::vec4(0.0f, 100.0f, 0.0f, 1.0f);
    loadGltf(scratch("hierarchy.gltf"), moved, options);
    checkNear(transformPoint(moved.instances[0].worldFromObject, {1.0f, 0.0f, 0.0f}), {8.0f, 102.0f, 0.0f});
}

TEST_CASE("gltf: cameras: perspective (infinite far), orthographic, pose from the node, viewFromWorld") {
    GltfFile f;
    const double h = std::sqrt(0.5);
    f.doc["cameras"] = json::array({
        {{"type", "perspective"}, {"name", "persp"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}, {"aspectRatio", 1.5}}}},
        {{"type", "orthographic"}, {"orthographic", {{"xmag", 2.0}, {"ymag", 1.0}, {"znear", 0.0}, {"zfar", 10.0}}}},
    });
    f.doc["nodes"] = json::array({
        {{"camera", 0}, {"translation", {1, 2, 3}}, {"rotation", {0, h, 0, h}}},  // 90 deg about +Y
        {{"camera", 1}, {"name", "orthoNode"}, {"translation", {0, 0, 4}}},
    });
    f.doc["scenes"] = json::array({{{"nodes", {0, 1}}}});
    const Scene scene = load(f.write("cameras.gltf"));
    REQUIRE(scene.cameras.size() == 2);
    const Camera& persp = scene.cameras[0];
    CHECK(persp.name == "persp");
    CHECK(persp.projection == ProjectionKind::Perspective);
    CHECK(persp.fovYDeg == doctest::Approx(0.8 * 180.0 / PI));
    CHECK(persp.nearZ == doctest::Approx(0.1));
    CHECK(std::isinf(persp.farZ));
    CHECK(persp.aspect == doctest::Approx(1.5));
    checkNear(persp.positionWorld, {1.0f, 2.0f, 3.0f});
    // Rotated 90 deg about +Y, the camera's -Z looks down world -X.
    const glm::mat4 view = persp.viewFromWorld();
    checkNear(transformPoint(view, {1.0f, 2.0f, 3.0f}), {0.0f, 0.0f, 0.0f});
    checkNear(transformPoint(view, {0.0f, 2.0f, 3.0f}), {0.0f, 0.0f, -1.0f});
    checkNear(transformPoint(view, {1.0f, 3.0f, 3.0f}), {0.0f, 1.0f, 0.0f});
    const Camera& ortho = scene.cameras[1];
    CHECK(ortho.name == "orthoNode");
    CHECK(ortho.projection == ProjectionKind::Orthographic);
    CHECK(ortho.xMag == 2.0f);
    CHECK(ortho.yMag == 1.0f);
    CHECK(ortho.farZ == 10.0f);
    checkNear(transformPoint(ortho.viewFromWorld(), {0.0f, 0.0f, 0.0f}), {0.0f, 0.0f, -4.0f});
}

TEST_CASE("gltf: KHR_lights_punctual: spot angles in degrees, infinite range, direction = the node's -Z") {
    GltfFile f;
    const double h = std::sqrt(0.5);
    f.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    f.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({
        {{"type", "spot"}, {"name", "spotA"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 20.0},
         {"spot", {{"innerConeAngle", 0.3}, {"outerConeAngle", 0.6}}}},
        {{"type", "point"}, {"range", 5.0}},
        {{"type", "directional"}, {"intensity", 3.0}},
        {{"type", "spot"}, {"spot", json::object()}},  // defaults: outer pi/4, inner 0
    });
    auto lightNode = [](int light) { return json{{"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}}; };
    json spotNode = lightNode(0);
    spotNode["translation"] = {1, 2, 3};
    spotNode["rotation"] = {h, 0, 0, h};  // 90 deg about +X: -Z -> +Y
    json pointNode = lightNode(1);
    pointNode["translation"] = {4, 5, 6};
    json sunNode = lightNode(2);
    sunNode["rotation"] = {0, h, 0, h};  // 90 deg about +Y: -Z -> -X
    json defaultSpot = lightNode(3);
    defaultSpot["name"] = "defaultSpotNode";
    f.doc["nodes"] = json::array({spotNode, pointNode, sunNode, defaultSpot});
    f.doc["scenes"] = json::array({{{"nodes", {0, 1, 2, 3}}}});
    const Scene scene = load(f.write("lights.gltf"));
    REQUIRE(scene.lights.size() == 4);
    const Light& spot = scene.lights[0];
    CHECK(spot.type == LightType::Spot);
    CHECK(spot.name == "spotA");
    CHECK(spot.spotHalfAngleDeg == doctest::Approx(0.6 * 180.0 / PI));
    CHECK(spot.spotInnerHalfAngleDeg == doctest::Approx(0.3 * 180.0 / PI));
    CHECK(std::isinf(spot.range));
    CHECK(spot.intensity == 20.0f);
    CHECK(spot.color == glm::vec3(1.0f, 0.5f, 0.25f));
    checkNear(spot.positionWorld, {1.0f, 2.0f, 3.0f});
    checkNear(spot.directionWorld, {0.0f, 1.0f, 0.0f});
    const Light& point = scene.lights[1];
    CHECK(point.type == LightType::Point);
    CHECK(point.range == 5.0f);
    checkNear(point.positionWorld, {4.0f, 5.0f, 6.0f});
    const Light& sun = scene.lights[2];
    CHECK(sun.type == LightType::Directional);
    CHECK(sun.intensity == 3.0f);
    checkNear(sun.directionWorld, {-1.0f, 0.0f, 0.0f});
    CHECK(scene.lights[3].spotHalfAngleDeg == doctest::Approx(45.0));
    CHECK(scene.lights[3].spotInnerHalfAngleDeg == 0.0f);
    CHECK(scene.lights[3].name == "defaultSpotNode");
}

TEST_CASE("gltf: materials: factors, texture references with texCoord/scale/strength, samplers") {
    GltfFile f = quadFile({0, 0, 1, 0, 1, 1, 0, 1});
    const std::vector<std::uint8_t> png = makePng(1, 1, 6, 8, {0, 1, 2, 3, 4});
    f.doc["images"] = json::array({{{"uri", "data:image/png;base64," + base64(png)}, {"name", "one"}}});
    f.doc["samplers"] = json::array({{{"magFilter", 9728}, {"minFilter", 9985}, {"wrapS", 33071}, {"wrapT", 33648}},
                                     {{"minFilter", 9728}}});
    f.doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}, {{"source", 0}}, {{"source", 0}, {"sampler", 1}}});
    f.doc["materials"] = json::array({{
        {"name", "full"},
        {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1.0, 0.75}}, {"metallicFactor", 0.1},
                                  {"roughnessFactor", 0.2}, {"baseColorTexture", {{"index", 1}}},
                                  {"metallicRoughnessTexture", {{"index", 2}}}}},
        {"normalTexture", {{"index", 0}, {"texCoord", 1}, {"scale", 0.5}}},
        {"occlusionTexture", {{"index", 1}, {"strength", 0.25}}},
        {"emissiveTexture", {{"index", 2}}},
        {"emissiveFactor", {1.0, 0.5, 0.0}},
        {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}},
    }});
    f.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_texture_transform"};
    f.doc["meshes"][0]["primitives"][0]["material"] = 0;
    std::vector<std::string> warnings;
    const Scene scene = load(f.write("materials.gltf"), &warnings);
    REQUIRE(scene.materials.size() == 1);
    const Material& m = scene.materials[0];
    CHECK(m.name == "full");
    CHECK(m.baseColorFactor == glm::vec4(0.5f, 0.25f, 1.0f, 0.75f));
    CHECK(m.metallicFactor == doctest::Approx(0.1));
    CHECK(m.roughnessFactor == doctest::Approx(0.2));
    CHECK(m.baseColorTexture.texture == 1);
    CHECK(m.metallicRoughnessTexture.texture == 2);
    CHECK(m.normalTexture.texture == 0);
    CHECK(m.normalTexture.texCoord == 1);
    CHECK(m.normalTexture.scale == 0.5f);
    CHECK(m.occlusionTexture.scale == 0.25f);
    CHECK(m.emissiveTexture.texture == 2);
    CHECK(m.emissiveFactor == glm::vec3(4.0f, 2.0f, 0.0f));
    CHECK(m.alphaMode == AlphaMode::Opaque);
    CHECK(m.alphaCutoff == 0.5f);
    CHECK_FALSE(m.doubleSided);
    REQUIRE(scene.textures.size() == 3);
    const SamplerState& s0 = scene.textures[0].sampler;
    CHECK(s0.magFilter == Filter::Point);
    CHECK(s0.minFilter == Filter::Linear);  // LINEAR_MIPMAP_NEAREST
    CHECK(s0.mipFilter == Filter::Point);
    CHECK(s0.addressU == AddressMode::Clamp);
    CHECK(s0.addressV == AddressMode::Mirror);
    const SamplerState& s1 = scene.textures[1].sampler;  // no sampler: glTF defaults
    CHECK(s1.magFilter == Filter::Linear);
    CHECK(s1.minFilter == Filter::Linear);
    CHECK(s1.mipFilter == Filter::Linear);
    CHECK(s1.addressU == AddressMode::Wrap);
    CHECK(s1.addressV == AddressMode::Wrap);
    const SamplerState& s2 = scene.textures[2].sampler;  // NEAREST without mips: level 0 only
    CHECK(s2.minFilter == Filter::Point);
    CHECK(s2.maxLod == 0.0f);
    CHECK(scene.images.at(0).rgba8 == std::vector<std::uint8_t>{1, 2, 3, 4});
    CHECK(contains(scene.images[0].source, "materials.gltf#/images/0"));
    // Unsupported but optional extensions warn.
    REQUIRE(warnings.size() == 1);
    CHECK(contains(warnings[0], "KHR_texture_transform"));
    // The normal map reads TEXCOORD_1, which this quad lacks: no tangents.
    CHECK(scene.meshes[0].primitives[0].tangentsObject.empty());
}

TEST_CASE("gltf: images: grey+alpha and 16-bit RGB expand/convert to RGBA8, alpha not premultiplied") {
    // Grey+alpha 2x1: (100, a 50), (200, a 255).
    const Scene greyAlpha = load(texturedQuad("grey-alpha.gltf", makePng(2, 1, 4, 8, {0, 100, 50, 200, 255})));
    CHECK(greyAlpha.images.at(0).rgba8 == std::vector<std::uint8_t>{100, 100, 100, 50, 200, 200, 200, 255});
    // Grey 1x1.
    const Scene grey = load(texturedQuad("grey.gltf", makePng(1, 1, 0, 8, {0, 77})));
    CHECK(grey.images.at(0).rgba8 == std::vector<std::uint8_t>{77, 77, 77, 255});
    // 16-bit RGB 1x1 (big-endian): 0xFFFF -> 255, 0x8080 = 128 * 257 -> 128, 0 -> 0.
    const Scene wide = load(texturedQuad("rgb16.gltf", makePng(1, 1, 2, 16, {0, 0xFF, 0xFF, 0x80, 0x80, 0, 0})));
    CHECK(wide.images.at(0).rgba8 == std::vector<std::uint8_t>{255, 128, 0, 255});
    CHECK(wide.images[0].width == 1);
}

// ---- tangents -----------------------------------------------------------------------------------

TEST_CASE("gltf: generated tangents: unit, orthogonal to N, w from the UV orientation (upright quad: +1)") {
    struct Case {
        const char* name;
        std::vector<float> uvs;
        glm::vec3 tangent;
        float w;  // the default generator's (bitangent up the image)
    };
    // Quad corners (0,0) (1,0) (1,1) (0,1), N = +z; bitangent = cross(N, T) * w must equal
    // -dP/dv, up the image (glTF 2.0 §3.8: v runs down the image; §3.9.3: a normal texture's +Y
    // is up); the old generator (generatedBitangentUp off, ERRATA #33) takes +dP/dv: w negated.
    const Case cases[] = {
        {"uv = (x, y)", {0, 0, 1, 0, 1, 1, 0, 1}, {1, 0, 0}, -1.0f},           // T = dP/du = +x, B = -y = -cross(z, x)
        {"uv = (1 - x, y)", {1, 0, 0, 0, 0, 1, 1, 1}, {-1, 0, 0}, 1.0f},       // T = -x, cross(z, -x) = -y = B
        {"uv = (x, 1 - y): upright", {0, 1, 1, 1, 1, 0, 0, 0}, {1, 0, 0}, 1.0f},  // T = +x, B = +y = cross(z, x)
        {"uv = (2y, 3x)", {0, 0, 0, 3, 2, 3, 2, 0}, {0, 1, 0}, 1.0f},          // T = +y, B = -x = cross(z, y)
    };
    for (const bool up : {true, false}) {
        for (const Case& c : cases) {
            CAPTURE(c.name);
            CAPTURE(up);
            const Scene scene = load(quadFile(c.uvs).write("tangents.gltf"), nullptr, true, up);
            const MeshPrimitive& prim = scene.meshes.at(0).primitives.at(0);
            CHECK(prim.tangentsGenerated);
            REQUIRE(prim.tangentsObject.size() == 4);
            for (std::size_t v = 0; v < 4; ++v) {
                const glm::vec3 t(prim.tangentsObject[v]);
                CHECK(std::abs(glm::length(t) - 1.0f) < 1e-6f);
                CHECK(std::abs(glm::dot(t, prim.normalsObject[v])) < 1e-6f);
                checkNear(t, c.tangent);
                CHECK(prim.tangentsObject[v].w == (up ? c.w : -c.w));
            }
        }
    }
}

TEST_CASE("gltf: generated tangents: a vertex shared by preserving and mirrored triangles is split") {
    // Two quads side by side, x in [0, 2]; u = x on the left, mirrored (u = 2 - x) on the right,
    // so the vertices at x = 1 belong to both orientations.
    GltfFile f;
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
    const std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::vector<float> uvs = {0, 0, 1, 0, 0, 0, 0, 1, 1, 1, 0, 1};
    const std::vector<std::uint16_t> indices = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
    f.singleMesh({{"attributes", {{"POSITION", f.data(positions, FLOAT, "VEC3", 3)},
                                  {"NORMAL", f.data(normals, FLOAT, "VEC3", 3)},
                                  {"TEXCOORD_0", f.data(uvs, FLOAT, "VEC2", 2)}}},
                  {"indices", f.data(indices, USHORT, "SCALAR", 1)}});
    const Scene scene = load(f.write("tangent-split.gltf"));
    const MeshPrimitive& prim = scene.meshes.at(0).primitives.at(0);
    CHECK(prim.positionsObject.size() == 8);  // vertices 1 and 4 duplicated
    REQUIRE(prim.tangentsObject.size() == 8);
    for (std::size_t tri = 0; tri < 4; ++tri) {
        const bool right = tri >= 2;
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t v = prim.indices[tri * 3 + k];
            CAPTURE(tri);
            CAPTURE(v);
            checkNear(glm::vec3(prim.tangentsObject[v]), right ? glm::vec3(-1, 0, 0) : glm::vec3(1, 0, 0));
            // Left: T = +x, B = -dP/dv = -y = -cross(z, x): w = -1; mirrored right: T = -x, w = +1.
            CHECK(prim.tangentsObject[v].w == (right ? 1.0f : -1.0f));
        }
    }
    // Positions of the right-hand triangles are unchanged by the split.
    CHECK(prim.positionsObject[prim.indices[6]] == glm::vec3(1, 0, 0));
    CHECK(prim.positionsObject[prim.indices[11]] == glm::vec3(1, 1, 0));
}

TEST_CASE("gltf: TANGENT present: kept with its w, without NORMAL, flat normals and TANGENT ignored (§3.7.2.1)") {
    GltfFile f = quadFile({0, 0, 1, 0, 1, 1, 0, 1});
    const int tangents = f.data(std::vector<float>{0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, -1}, FLOAT, "VEC4", 4);
    f.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = tangents;
    const Scene given = load(f.write("given-tangents.gltf"));
    const MeshPrimitive& prim = given.meshes.at(0).primitives.at(0);
    CHECK_FALSE(prim.tangentsGenerated);
    for (const glm::vec4& t : prim.tangentsObject) CHECK(t == glm::vec4(0, 1, 0, -1));

    f.doc["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
    const Scene flat = load(f.write("flat-normals.gltf"));
    const MeshPrimitive& flatPrim = flat.meshes.at(0).primitives.at(0);
    CHECK(flatPrim.positionsObject.size() == 6);
    for (const glm::vec3& n : flatPrim.normalsObject) CHECK(n == glm::vec3(0, 0, 1));
    CHECK(flatPrim.tangentsGenerated);
    for (const glm::vec4& t : flatPrim.tangentsObject) CHECK(t == glm::vec4(1, 0, 0, -1));  // uv = (x, y): B = -y
}

// ---- bad input ----------------------------------------------------------------------------------

TEST_CASE("gltf bad input: missing file, invalid JSON, missing .bin, unsupported required extension") {
    expectInputError(scratch("does-not-exist.gltf"), {"cannot open"});
    const fs::path broken = scratch("broken.gltf");
    std::ofstream(broken) << "{ \"asset\": { \"version\": \"2.0\" }, \"nodes\": [ ";
    expectInputError(broken, {"invalid JSON", "parse error"});
    const fs::path garbage = scratch("garbage.glb");
    std::ofstream(garbage) << "glTF\x02\0\0\0 not really a binary glTF";
    expectInputError(garbage, {});

    GltfFile f = quadFile();
    f.doc["buffers"] = json::array({{{"byteLength", f.bin.size()}, {"uri", "missing.bin"}}});
    const fs::path missingBin = scratch("missing-bin.gltf");
    std::ofstream(missingBin) << f.doc.dump();
    expectInputError(missingBin, {"/buffers/0/uri", "missing.bin"});
    expectInputError(ASSIMP_GLTF2 / "MissingBin" / "BoxTextured.gltf", {"/buffers/0/uri"});

    GltfFile g = quadFile();
    g.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    g.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    expectInputError(g.write("required-extension.gltf"), {"/extensionsRequired/0", "KHR_draco_mesh_compression"});
}

TEST_CASE("gltf bad input: accessors out of their bufferView, bufferViews out of their buffer, absurd counts") {
    {
        GltfFile f = quadFile();
        f.doc["accessors"][0]["count"] = 5;  // 4 positions stored
        expectInputError(f.write("accessor-oob.gltf"), {"/accessors/0:", "exceed bufferView 0"});
    }
    {
        GltfFile f = quadFile();
        f.doc["accessors"][1]["byteOffset"] = 4;
        expectInputError(f.write("accessor-offset-oob.gltf"), {"/accessors/1:", "byteOffset 4"});
    }
    {
        GltfFile f = quadFile();
        f.doc["bufferViews"][0]["byteLength"] = 4096;
        expectInputError(f.write("view-oob.gltf"), {"/bufferViews/0:", "exceeds buffer 0"});
    }
    {
        GltfFile f = quadFile();
        f.doc["accessors"][0]["count"] = (1u << 28) + 1u;
        expectInputError(f.write("huge-count.gltf"), {"/accessors/0/count", "2^28"});
    }
    {
        GltfFile f = quadFile();
        f.doc["accessors"][0]["count"] = 0;
        expectInputError(f.write("zero-count.gltf"), {"/accessors/0/count"});
    }
    {
        GltfFile f = quadFile();
        f.doc["bufferViews"][0]["byteStride"] = 8;  // VEC3 FLOAT needs 12
        expectInputError(f.write("small-stride.gltf"), {"/bufferViews/0/byteStride"});
    }
    {
        GltfFile f = quadFile();
        f.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99;
        expectInputError(f.write("no-accessor.gltf"), {"/meshes/0/primitives/0/attributes/POSITION", "accessor 99"});
    }
    {
        GltfFile f = quadFile();
        f.doc["accessors"][1]["count"] = 3;  // NORMAL shorter than POSITION
        expectInputError(f.write("count-mismatch.gltf"), {"/meshes/0/primitives/0/attributes/NORMAL"});
    }
    {
        GltfFile f = quadFile();
        const int sparseIndices = f.view(std::vector<std::uint16_t>{9});
        const int sparseValues = f.view(std::vector<float>{5, 5, 5});
        f.doc["accessors"][0]["sparse"] = {{"count", 1},
                                           {"indices", {{"bufferView", sparseIndices}, {"componentType", USHORT}}},
                                           {"values", {{"bufferView", sparseValues}}}};
        expectInputError(f.write("sparse-oob.gltf"), {"/accessors/0/sparse/indices", "index 9"});
    }
}

TEST_CASE("gltf bad input: indices out of range, wrong accessor types, non-finite positions, bad topology") {
    {
        GltfFile f = quadFile();
        f.doc["meshes"][0]["primitives"][0]["indices"] = f.data(std::vector<std::uint16_t>{0, 1, 4}, USHORT, "SCALAR", 1);
        expectInputError(f.write("index-oob.gltf"), {"/accessors/3:", "index 4", "vertex count 4", "/meshes/0/primitives/0"});
    }
    expectInputError(ASSIMP_GLTF2 / "IndexOutOfRange" / "IndexOutOfRange.gltf", {"/accessors/", "not below the vertex count"});
    expectInputError(ASSIMP_GLTF2 / "IndexOutOfRange" / "AllIndicesOutOfRange.gltf", {"not below the vertex count"});
    {
        GltfFile f = quadFile();
        f.doc["accessors"][0]["type"] = "VEC2";
        expectInputError(f.write("position-vec2.gltf"), {"/accessors/0:", "POSITION must be VEC3 of FLOAT", "VEC2"});
    }
    {
        GltfFile f = quadFile();
        f.doc["accessors"][2]["componentType"] = FLOAT;
        expectInputError(f.write("float-indices.gltf"), {"/accessors/2:", "indices must be SCALAR"});
    }
    {
        GltfFile f = quadFile();
        f.doc["accessors"][0]["componentType"] = 5124;  // INT is not a glTF component type
        expectInputError(f.write("int-positions.gltf"), {"/accessors/0"});
    }
    {
        GltfFile f;
        const float inf = std::numeric_limits<float>::infinity();
        const int positions = f.data(std::vector<float>{0, 0, 0, 1, 0, 0, 0, std::nanf(""), 0}, FLOAT, "VEC3", 3);
        f.singleMesh({{"attributes", {{"POSITION", positions}}}});
        expectInputError(f.write("nan.gltf"), {"/accessors/0: POSITION holds a non-finite value"});
        GltfFile g;
        g.singleMesh({{"attributes", {{"POSITION", g.data(std::vector<float>{0, 0, 0, inf, 0, 0, 0, 1, 0}, FLOAT, "VEC3", 3)}}}});
        expectInputError(g.write("inf.gltf"), {"/accessors/0: POSITION holds a non-finite value"});
    }
    expectInputError(ASSIMP_GLTF2 / "BoxWithInfinites-glTF-Binary" / "BoxWithInfinites.glb", {"non-finite"});
    expectInputError(ASSIMP_GLTF2 / "IncorrectVertexArrays" / "Cube.gltf", {"/meshes/1/primitives/0", "not a multiple of 3"});
    {
        GltfFile f = quadFile();
        f.doc["meshes"][0]["primitives"][0]["mode"] = 9;
        expectInputError(f.write("bad-mode.gltf"), {"/meshes/0/primitives/0/mode"});
    }
    {
        GltfFile f = quadFile();
        f.doc["meshes"][0]["primitives"][0]["attributes"].erase("POSITION");
        expectInputError(f.write("no-position.gltf"), {"/meshes/0/primitives/0/attributes", "POSITION is missing"});
    }
    // Mistyped JSON values (tinygltf alone would replace them by defaults).
    expectInputError(ASSIMP_GLTF2 / "wrongTypes" / "badArray.gltf", {"/meshes/0/primitives: must be an array"});
    expectInputError(ASSIMP_GLTF2 / "wrongTypes" / "badObject.gltf", {"/materials/0/pbrMetallicRoughness: must be an object"});
    expectInputError(ASSIMP_GLTF2 / "wrongTypes" / "badNumber.gltf", {"/materials/0/normalTexture/scale", "is not a number"});
    expectInputError(ASSIMP_GLTF2 / "wrongTypes" / "badString.gltf", {"/name", "42 is not a string"});
    expectInputError(ASSIMP_GLTF2 / "wrongTypes" / "badUint.gltf", {"/index", "-1 is not a non-negative integer"});
    expectInputError(ASSIMP_GLTF2 / "wrongTypes" / "badExtension.gltf",
                     {"/extensions/KHR_texture_transform: must be an object"});
}

TEST_CASE("gltf bad input: node cycles and shared children, bad references, cameras, lights, samplers, materials") {
    expectInputError(ASSIMP_GLTF2 / "RecursiveNodes" / "RecursiveNodes.gltf", {"/nodes/", "cycle"});
    {
        GltfFile f = quadFile();
        f.doc["nodes"] = json::array({{{"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}});
        f.doc["scenes"] = json::array({{{"nodes", {0, 1}}}});
        expectInputError(f.write("two-parents.gltf"), {"/nodes/1/children/0", "already has parent 0"});
    }
    {
        GltfFile f = quadFile();
        f.doc["nodes"][0]["mesh"] = 3;
        expectInputError(f.write("bad-mesh-ref.gltf"), {"/nodes/0/mesh", "mesh 3 does not exist"});
    }
    {
        GltfFile f = quadFile();
        f.doc["scenes"][0]["nodes"] = {0, 0};
        expectInputError(f.write("root-twice.gltf"), {"/scenes/0/nodes/1"});
    }
    {
        GltfFile f = quadFile();
        f.doc["nodes"][0]["rotation"] = {0, 0, 0};
        expectInputError(f.write("bad-rotation.gltf"), {"/nodes/0/rotation"});
    }
    {
        GltfFile f = quadFile();
        f.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 4.0}, {"znear", 0.1}}}}});
        f.doc["nodes"][0]["camera"] = 0;
        expectInputError(f.write("bad-yfov.gltf"), {"/cameras/0/perspective/yfov"});
        f.doc["cameras"][0]["perspective"] = {{"yfov", 1.0}, {"znear", 1.0}, {"zfar", 0.5}};
        expectInputError(f.write("bad-zfar.gltf"), {"/cameras/0/perspective/zfar"});
    }
    {
        GltfFile f = quadFile();
        f.doc["extensionsUsed"] = {"KHR_lights_punctual"};
        f.doc["extensions"]["KHR_lights_punctual"]["lights"] =
            json::array({{{"type", "spot"}, {"spot", {{"innerConeAngle", 0.7}, {"outerConeAngle", 0.5}}}}});
        f.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
        expectInputError(f.write("bad-spot.gltf"), {"/extensions/KHR_lights_punctual/lights/0/spot/innerConeAngle"});
        f.doc["extensions"]["KHR_lights_punctual"]["lights"][0]["spot"]["innerConeAngle"] = 0.25;
        f.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 4;
        expectInputError(f.write("bad-light-ref.gltf"), {"/nodes/0/extensions/KHR_lights_punctual/light"});
    }
    {
        GltfFile f = quadFile();
        f.doc["samplers"] = json::array({{{"wrapS", 1234}}});
        f.doc["images"] = json::array({{{"uri", "data:image/png;base64," + base64(makePng(1, 1, 0, 8, {0, 1}))}}});
        f.doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}});
        expectInputError(f.write("bad-wrap.gltf"), {"/samplers/0/wrapS", "1234"});
        f.doc["samplers"] = json::array({json::object()});
        f.doc["textures"][0]["source"] = 5;
        expectInputError(f.write("bad-source.gltf"), {"/textures/0/source", "image 5"});
    }
    {
        GltfFile f = quadFile();
        f.doc["materials"] = json::array({{{"alphaMode", "SOMETIMES"}}});
        f.doc["meshes"][0]["primitives"][0]["material"] = 0;
        expectInputError(f.write("bad-alpha-mode.gltf"), {"/materials/0/alphaMode", "SOMETIMES"});
        f.doc["materials"] = json::array({{{"normalTexture", {{"index", 2}}}}});
        expectInputError(f.write("bad-texture-ref.gltf"), {"/materials/0/normalTexture/index", "texture 2"});
        f.doc["materials"] = json::array({json::object()});
        f.doc["meshes"][0]["primitives"][0]["material"] = 1;
        expectInputError(f.write("bad-material-ref.gltf"), {"/meshes/0/primitives/0/material"});
    }
    {
        const fs::path file = quadFile().write("scene-index.gltf");
        Scene scene;
        GltfLoadOptions options;
        options.sceneIndex = 3;
        std::string message;
        try {
            loadGltf(file, scene, options);
        } catch (const InputError& e) {
            message = e.what();
        }
        CHECK(contains(message, file.string() + ": /scenes: scene 3 does not exist"));
    }
}

TEST_CASE("gltf bad input: images that are huge, negative, undecodable or missing") {
    expectInputError(texturedQuad("huge-image.gltf", makePng(20000, 1, 6, 8, {0})),
                     {"/images/0", "20000 x 1 texels is outside 1..16384"});
    expectInputError(texturedQuad("huge-image-header.gltf", makePng(20000, 1, 6, 8, {0})),
                     {"/images/0", "outside 1..16384"}, false);
    expectInputError(texturedQuad("negative-image.gltf", makePng(0x80000000u, 1, 6, 8, {}, false)), {"/images/0"});
    expectInputError(texturedQuad("zero-image.gltf", makePng(0, 1, 6, 8, {}, false)), {"/images/0"});
    // A corrupted IDAT (its CRC no longer matches). Not a truncated file: OIIO 2.4's PNG reader
    // leaks its error string when libpng hits the end of the data (LeakSanitizer would fail).
    std::vector<std::uint8_t> corrupted = makePng(4, 4, 6, 8, std::vector<std::uint8_t>(4 * 17, 9));
    corrupted[8 + 25 + 8 + 10] ^= 0xFF;  // signature, IHDR chunk, IDAT length + type, then payload
    expectInputError(texturedQuad("corrupted-image.gltf", corrupted), {"/images/0", "cannot decode"});
    {
        GltfFile f = quadFile({0, 0, 1, 0, 1, 1, 0, 1});
        f.doc["images"] = json::array({{{"uri", "no-such-image.png"}}});
        expectInputError(f.write("missing-image.gltf"), {"/images/0/uri", "no-such-image.png"});
    }
    {
        GltfFile f = quadFile();
        const std::vector<std::uint8_t> png = makePng(1, 1, 0, 8, {0, 1});
        f.doc["images"] = json::array({{{"bufferView", f.view(png)}, {"mimeType", "image/png"}}});
        const Scene scene = load(f.write("image-in-view.gltf"));
        CHECK(scene.images.at(0).rgba8 == std::vector<std::uint8_t>{1, 1, 1, 255});
        f.doc["bufferViews"][3]["byteOffset"] = 100000;
        expectInputError(f.write("image-view-oob.gltf"), {"/bufferViews/3"});
    }
}

TEST_CASE("gltf bad input: JSON nested deeper than 256 levels is refused before any parse, in .gltf and .glb") {
    // 15,000 nested arrays in "extras" (about 30 KB) overflowed the stack of tinygltf's recursive
    // parse with SIGSEGV; the pre-scan refuses them with an InputError instead.
    constexpr int DEEP_LEVELS = 15000;  // arrays nested inside "extras"
    const std::string deep = std::string(DEEP_LEVELS, '[') + std::string(DEEP_LEVELS, ']');
    const std::string text = R"({"asset": {"version": "2.0"}, "extras": )" + deep + "}";
    const fs::path gltf = scratch("deep-extras.gltf");
    std::ofstream(gltf, std::ios::binary) << text;
    // The root object is level 1, "extras" opens level 2: level 257 is its 256th '[' at byte 39 + 255.
    const std::size_t extrasAt = text.find('[');
    expectInputError(gltf, {"nested deeper than 256 levels", "at byte " + std::to_string(extrasAt + 255)});
    expectInputError(gltf, {"nested deeper than 256 levels"}, false);

    // The same JSON as a .glb's JSON chunk (§4.4.3: header, chunk length, "JSON", padded with spaces).
    std::string chunk = text;
    while (chunk.size() % 4) chunk += ' ';
    std::string glb = "glTF";
    auto putU32 = [&glb](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) glb += char(v >> (8 * i) & 0xFF);
    };
    putU32(2);
    putU32(std::uint32_t(12 + 8 + chunk.size()));
    putU32(std::uint32_t(chunk.size()));
    glb += "JSON";
    glb += chunk;
    const fs::path binary = scratch("deep-extras.glb");
    std::ofstream(binary, std::ios::binary) << glb;
    expectInputError(binary, {"nested deeper than 256 levels"});

    // At the limit, and brackets inside strings (escaped quotes too), load normally.
    GltfFile f = quadFile();
    json nested = json::array();
    for (int wraps = 0; wraps < 253; ++wraps) nested = json::array({nested});  // 254 arrays: levels 3..256 under root and "extras"
    f.doc["extras"] = {{"deep", nested}, {"text", "\\\"[[[[" + std::string(1000, '{')}};
    CHECK(load(f.write("deep-but-allowed.gltf")).meshes.size() == 1);
}

TEST_CASE("gltf bad input: asset.version other than 2.x and asset.minVersion above 2.0 are refused (§3.2)") {
    struct Case { const char* key; json value; const char* needle; };
    const Case cases[] = {
        {"version", "9.0", "glTF 9.0 is not supported"},
        {"version", "3.0", "glTF 3.0 is not supported"},
        {"version", "1.0", "glTF 1.0 is not supported"},
        {"version", "2", "is not a version"},
        {"version", 2.0, "is not a version"},
        {"minVersion", "2.1", "needs glTF 2.1"},
        {"minVersion", "3.0", "needs glTF 3.0"},
        {"minVersion", "two", "is not a version"},
    };
    for (const Case& c : cases) {
        GltfFile f = quadFile();
        f.doc["asset"][c.key] = c.value;
        CAPTURE(f.doc["asset"].dump());
        expectInputError(f.write("asset-version.gltf"), {std::string("/asset/") + c.key, c.needle});
    }
    // Minor versions are backwards compatible: 2.1 with minVersion 2.0 loads.
    GltfFile ok = quadFile();
    ok.doc["asset"] = {{"version", "2.1"}, {"minVersion", "2.0"}};
    CHECK(load(ok.write("asset-2.1.gltf")).meshes.size() == 1);
}

// KHR_lights_punctual README ("Light Shared Properties", "Range Property", "Spot Properties") and
// its light.schema.json: every light the file defines is checked, also one no node places.
namespace {
GltfFile fileWithLights(const json& lights, int placed) {
    GltfFile f = quadFile();
    f.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    f.doc["extensions"]["KHR_lights_punctual"]["lights"] = lights;
    if (placed >= 0) f.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = placed;
    return f;
}
} // namespace

TEST_CASE("gltf KHR_lights_punctual: every defined light is checked, placed by a node or not") {
    const json good = {{"type", "point"}};
    struct Bad {
        const char* name;
        json light;
        const char* pointer;  // the key the error must name
        const char* what;
    };
    const double halfPi = 1.5707963267948966;  // pi/2 in double, the spot bound
    const std::vector<Bad> cases{
        {"unknown-type", {{"type", "area"}}, "/extensions/KHR_lights_punctual/lights/3/type", "'area' is not point, spot or directional"},
        {"negative-range", {{"type", "point"}, {"range", -1.0}}, "/extensions/KHR_lights_punctual/lights/3/range", "-1 is not positive"},
        {"negative-intensity", {{"type", "point"}, {"intensity", -0.5}}, "/extensions/KHR_lights_punctual/lights/3/intensity", "-0.5"},
        {"colour-above-one", {{"type", "point"}, {"color", {1.0, 2.0, 0.0}}}, "/extensions/KHR_lights_punctual/lights/3/color/1",
         "2 is outside [0, 1]"},
        {"colour-negative", {{"type", "directional"}, {"color", {-0.25, 0.0, 0.0}}}, "/extensions/KHR_lights_punctual/lights/3/color/0",
         "-0.25 is outside [0, 1]"},
        {"colour-two-numbers", {{"type", "point"}, {"color", {1.0, 1.0}}}, "/extensions/KHR_lights_punctual/lights/3/color",
         "must be an array of 3 numbers"},
        {"inner-equals-outer", {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.5}, {"outerConeAngle", 0.5}}}},
         "/extensions/KHR_lights_punctual/lights/3/spot/innerConeAngle", "outside [0, outerConeAngle"},
        {"inner-negative", {{"type", "spot"}, {"spot", {{"innerConeAngle", -0.1}, {"outerConeAngle", 0.5}}}},
         "/extensions/KHR_lights_punctual/lights/3/spot/innerConeAngle", "-0.1"},
        {"outer-zero", {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.0}, {"outerConeAngle", 0.0}}}},
         "/extensions/KHR_lights_punctual/lights/3/spot/outerConeAngle", "outside (0, pi/2]"},
        {"outer-beyond-half-pi", {{"type", "spot"}, {"spot", {{"outerConeAngle", halfPi + 0.01}}}},
         "/extensions/KHR_lights_punctual/lights/3/spot/outerConeAngle", "outside (0, pi/2]"},
    };
    for (const Bad& c : cases) {
        const std::string name = c.name;
        CAPTURE(name);
        // Lights 0..2 are good, light 3 is the bad one, and only light 0 is placed by a node.
        GltfFile f = fileWithLights(json::array({good, good, good, c.light}), 0);
        expectInputError(f.write(std::string("khr-light-") + c.name + ".gltf"), {c.pointer, c.what});
    }
    // The bounds themselves are allowed: inner 0, outer exactly pi/2 (the double nearest), range
    // absent (infinite), colour 0 and 1, intensity 0.
    const json edges = json::array({{{"type", "spot"}, {"spot", {{"innerConeAngle", 0.0}, {"outerConeAngle", halfPi}}}},
                                    {{"type", "point"}, {"color", {0.0, 1.0, 0.0}}, {"intensity", 0.0}}});
    std::vector<std::string> warnings;
    const Scene scene = load(fileWithLights(edges, 0).write("khr-light-edges.gltf"), &warnings);
    REQUIRE(scene.lights.size() == 1);
    CHECK(scene.lights[0].spotHalfAngleDeg == 90.0f);  // float(halfPi * 180 / pi) = 90 exactly
}

TEST_CASE("gltf KHR_lights_punctual: the loader says how many lights are defined and how many nodes place") {
    const json point = {{"type", "point"}};
    {
        // 3 defined, 1 placed by the only node: a warning naming the counts.
        std::vector<std::string> warnings;
        const Scene scene = load(fileWithLights(json::array({point, point, point}), 1).write("khr-lights-unreferenced.gltf"), &warnings);
        CHECK(scene.lights.size() == 1);
        bool found = false;
        for (const std::string& w : warnings) found = found || contains(w, "defines 3 lights, 1 placed by a node; 2 unreferenced");
        CHECK_MESSAGE(found, "warnings: " << warnings.size());
    }
    {
        // 2 defined, none placed: "0 placed by nodes; 2 unreferenced" (the scene has no lights).
        std::vector<std::string> warnings;
        const Scene scene = load(fileWithLights(json::array({point, point}), -1).write("khr-lights-none-placed.gltf"), &warnings);
        CHECK(scene.lights.empty());
        bool found = false;
        for (const std::string& w : warnings) found = found || contains(w, "defines 2 lights, 0 placed by nodes; 2 unreferenced");
        CHECK(found);
    }
    {
        // Every light placed: no warning about lights.
        std::vector<std::string> warnings;
        (void)load(fileWithLights(json::array({point}), 0).write("khr-lights-all-placed.gltf"), &warnings);
        for (const std::string& w : warnings) CHECK_FALSE(contains(w, "unreferenced"));
    }
}

} // namespace tessera_test::scene_gltf_loader_test
