// The glTF 2.0 rules that change a rendered image, each against geometric truth: hand-built glTF
// files (JSON with base64 data URIs, loaded from memory: nothing is written) whose expected
// pixels are computed here from the geometry, the camera and the material, then rendered through
// the loader, SceneResources and a technique. README "glTF conformance" lists them.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <tessera/buffers/conversion.h>
#include <tessera/raster/pixel_watch.h>
#include <tessera/scene/gltf_loader.h>
#include <tessera/techniques/technique.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::scene_gltf_rules_test {

using nlohmann::json;
using namespace tessera;

namespace {

constexpr int kFloat = 5126, kUshort = 5123;
constexpr double kPi = 3.14159265358979323846;

std::string base64(const std::vector<std::uint8_t>& bytes) {
    static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t n = std::uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? bytes[i + 1] << 8 : 0) |
                                (i + 2 < bytes.size() ? bytes[i + 2] : 0);
        out += kAlphabet[n >> 18 & 63];
        out += kAlphabet[n >> 12 & 63];
        out += i + 1 < bytes.size() ? kAlphabet[n >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? kAlphabet[n & 63] : '=';
    }
    return out;
}

// ---- a minimal PNG (8-bit RGBA, stored deflate block) for texture cases
std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
    std::uint32_t crc = ~0u;
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
// One row of RGBA8 texels.
std::vector<std::uint8_t> rgbaRowPng(const std::vector<std::uint8_t>& rgba) {
    std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    std::vector<std::uint8_t> header;
    putBigEndian(header, std::uint32_t(rgba.size() / 4));
    putBigEndian(header, 1);
    header.insert(header.end(), {8, 6, 0, 0, 0});
    pngChunk(png, "IHDR", header);
    std::vector<std::uint8_t> rows = {0};  // filter none
    rows.insert(rows.end(), rgba.begin(), rgba.end());
    std::vector<std::uint8_t> zlib = {0x78, 0x01, 0x01};
    const auto length = std::uint16_t(rows.size());
    zlib.insert(zlib.end(), {std::uint8_t(length), std::uint8_t(length >> 8), std::uint8_t(~length), std::uint8_t(~length >> 8)});
    zlib.insert(zlib.end(), rows.begin(), rows.end());
    std::uint32_t a = 1, b = 0;  // Adler-32
    for (const std::uint8_t byte : rows) {
        a = (a + byte) % 65521;
        b = (b + a) % 65521;
    }
    putBigEndian(zlib, b << 16 | a);
    pngChunk(png, "IDAT", zlib);
    pngChunk(png, "IEND", {});
    return png;
}

// A glTF document under construction: one buffer, embedded as a data URI.
struct GltfDoc {
    json doc = {{"asset", {{"version", "2.0"}}}, {"bufferViews", json::array()}, {"accessors", json::array()}};
    std::vector<std::uint8_t> bin;
    template <class T>
    int data(const std::vector<T>& values, int componentType, const char* type, std::size_t components) {
        while (bin.size() % 4) bin.push_back(0);
        const std::size_t offset = bin.size();
        bin.resize(offset + values.size() * sizeof(T));
        std::memcpy(bin.data() + offset, values.data(), values.size() * sizeof(T));
        doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
        doc["accessors"].push_back({{"bufferView", int(doc["bufferViews"].size() - 1)},
                                    {"componentType", componentType},
                                    {"count", values.size() / components},
                                    {"type", type}});
        return int(doc["accessors"].size() - 1);
    }
    std::string text() const {
        json out = doc;
        out["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
        return out.dump();
    }
};

// The quad [0, 1] x [0, 1] in z = 0, normal +Z, counter-clockwise seen from +Z; its UVs upright
// (glTF 2.0 §3.8, Texture Data: UV (0, 0) is the image's top-left, so v runs down while y runs up).
json quadPrimitive(GltfDoc& g, bool tangents = false, float tangentW = 1.0f) {
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::vector<float> uvs = {0, 1, 1, 1, 1, 0, 0, 0};
    const std::vector<std::uint16_t> indices = {0, 1, 2, 0, 2, 3};
    json p = {{"attributes",
               {{"POSITION", g.data(positions, kFloat, "VEC3", 3)},
                {"NORMAL", g.data(normals, kFloat, "VEC3", 3)},
                {"TEXCOORD_0", g.data(uvs, kFloat, "VEC2", 2)}}},
              {"indices", g.data(indices, kUshort, "SCALAR", 1)},
              {"material", 0}};
    if (tangents) {
        const std::vector<float> t = {1, 0, 0, tangentW, 1, 0, 0, tangentW, 1, 0, 0, tangentW, 1, 0, 0, tangentW};
        p["attributes"]["TANGENT"] = g.data(t, kFloat, "VEC4", 4);
    }
    return p;
}

void singleNode(GltfDoc& g, json primitive, json node = json::object()) {
    g.doc["meshes"] = json::array({{{"primitives", json::array({primitive})}}});
    node["mesh"] = 0;
    g.doc["nodes"] = json::array({node});
    g.doc["scenes"] = json::array({{{"nodes", {0}}}});
    g.doc["scene"] = 0;
}

Scene loadText(const std::string& text, bool generatedBitangentUp = true) {
    Scene scene;
    std::vector<std::string> warnings;
    GltfLoadOptions options;
    options.warnings = &warnings;
    options.generatedBitangentUp = generatedBitangentUp;
    loadGltfFromMemory(text, "rules.gltf", ".", scene, options);
    return scene;
}

// A camera on +Z at distance `eyeZ` looking down -Z at (x, y) = (0, 0), 45 degrees vertical.
Camera cameraOnZ(float eyeZ) {
    Camera c;
    c.positionWorld = {0.0f, 0.0f, eyeZ};
    c.nearZ = 0.1f;
    c.farZ = 100.0f;
    return c;
}

struct Frame1 {
    BufferRegistry registry;
    const Surface& get(std::string_view name) { return registry.get(name); }
};

void renderScene(const Scene& scene, const Camera& camera, const std::string& technique, std::uint32_t w, std::uint32_t h,
                 Precision precision, Frame1& out, PixelWatch* watch = nullptr) {
    const SceneResources resources(scene, {}, requireTechnique(technique, "rules.gltf").textures);
    Device device(DeviceConfig{32, 2});
    if (watch) device.setPixelWatch(watch);
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.camera = camera;
    ctx.width = w;
    ctx.height = h;
    ctx.precision = precision;
    ctx.options = json::object();
    ctx.sceneFile = "rules.gltf";
    buildTechnique(technique, ctx, ctx.sceneFile).run(out.registry);
}

// Window pixel centre -> the world point where its ray meets z = 0, for a camera on +Z looking
// down -Z (view axes = world axes): NDC x = (px + 0.5) / W * 2 - 1, y = 1 - (py + 0.5) / H * 2;
// perspective: world = NDC * (tan(fovY / 2) * (aspect, 1)) * eyeZ (D3D11.3 §15.5 viewport
// transform inverted, glTF 2.0 §3.10.3 projection); orthographic: world = NDC * (xmag, ymag).
using PixelToWorld = std::function<glm::dvec2(std::uint32_t, std::uint32_t)>;
PixelToWorld perspectiveRay(std::uint32_t w, std::uint32_t h, double fovYRad, double aspect, double eyeZ) {
    return [=](std::uint32_t px, std::uint32_t py) {
        const double xNdc = (double(px) + 0.5) / double(w) * 2.0 - 1.0, yNdc = 1.0 - (double(py) + 0.5) / double(h) * 2.0;
        const double t = std::tan(fovYRad / 2.0) * eyeZ;
        return glm::dvec2(xNdc * t * aspect, yNdc * t);
    };
}
PixelToWorld orthographicRay(std::uint32_t w, std::uint32_t h, double xMag, double yMag) {
    return [=](std::uint32_t px, std::uint32_t py) {
        const double xNdc = (double(px) + 0.5) / double(w) * 2.0 - 1.0, yNdc = 1.0 - (double(py) + 0.5) / double(h) * 2.0;
        return glm::dvec2(xNdc * xMag, yNdc * yMag);
    };
}

// Every pixel whose centre's ray meets z = 0 inside [x0, x1] x [y0, y1] is covered (depth < 1)
// and every pixel whose point lies outside is not; centres within kEdgeMargin world units of an
// edge are skipped (the fill rule's ties and float snapping decide them, not the glTF rule).
// Returns the covered pixels counted.
int checkCoverage(const Surface& depth, const PixelToWorld& toWorld, double x0, double x1, double y0, double y1) {
    constexpr double kEdgeMargin = 1e-3;  // world units; a pixel here spans >= 0.01
    int covered = 0;
    for (std::uint32_t y = 0; y < depth.height(); ++y)
        for (std::uint32_t x = 0; x < depth.width(); ++x) {
            const glm::dvec2 p = toWorld(x, y);
            const double inside = std::min(std::min(p.x - x0, x1 - p.x), std::min(p.y - y0, y1 - p.y));
            if (std::abs(inside) < kEdgeMargin) continue;
            const bool drawn = depth.loadDepth(x, y) < 1.0f;
            CAPTURE(x);
            CAPTURE(y);
            CHECK(drawn == (inside > 0.0));
            covered += drawn;
        }
    return covered;
}

json emissiveMaterial(float alpha, const char* alphaMode, double cutoff = -1.0) {
    // Black base colour: preview's rgb = base x head light + emissive is then the emissive alone.
    json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.0, 0.0, 0.0, alpha}}}}, {"emissiveFactor", {0.25, 0.5, 1.0}}};
    if (alphaMode) m["alphaMode"] = alphaMode;
    if (cutoff >= 0.0) m["alphaCutoff"] = cutoff;
    return m;
}

} // namespace

TEST_CASE("glTF rules: a node with a negative determinant reverses the winding, so its front face stays (glTF 2.0 §3.7.4)") {
    // Single-sided quads (back faces culled) seen from +Z. Scale (-1, 1, 1) mirrors [0, 1] in x
    // to [-1, 0]; without the reversed winding the mirrored quad would face away and be culled.
    constexpr std::uint32_t w = 96, h = 64;
    const Camera camera = cameraOnZ(3.0f);
    const PixelToWorld toWorld = perspectiveRay(w, h, 45.0 * kPi / 180.0, double(w) / double(h), 3.0);
    for (const bool mirrored : {false, true}) {
        CAPTURE(mirrored);
        GltfDoc g;
        g.doc["materials"] = json::array({emissiveMaterial(1.0f, nullptr)});
        json node = json::object();
        if (mirrored) node["scale"] = {-1.0, 1.0, 1.0};
        singleNode(g, quadPrimitive(g), node);
        Frame1 f;
        renderScene(loadText(g.text()), camera, "preview", w, h, Precision::Exact, f);
        const int covered = mirrored ? checkCoverage(f.get("depth"), toWorld, -1.0, 0.0, 0.0, 1.0)
                                     : checkCoverage(f.get("depth"), toWorld, 0.0, 1.0, 0.0, 1.0);
        // The quad spans 1 / (2 x 3 x tan(22.5 deg)) x 64 = 12.9 px a side: about 166 pixels.
        CHECK(covered > 140);
    }
}

TEST_CASE("glTF rules: alphaMode OPAQUE ignores alpha, MASK cuts at alphaCutoff, BLEND mixes over the background (glTF 2.0 §3.9.4)") {
    constexpr std::uint32_t w = 64, h = 48;
    const Camera camera = cameraOnZ(3.0f);
    const PixelToWorld toWorld = perspectiveRay(w, h, 45.0 * kPi / 180.0, double(w) / double(h), 3.0);
    const auto render = [&](json material, Frame1& f) {
        GltfDoc g;
        g.doc["materials"] = json::array({material});
        singleNode(g, quadPrimitive(g));
        renderScene(loadText(g.text()), camera, "preview", w, h, Precision::Reference, f);
    };
    // A pixel well inside the quad (its centre's point printed for the record).
    const std::uint32_t px = 40, py = 16;
    const glm::dvec2 p = toWorld(px, py);
    MESSAGE("pixel (40, 16) sees (" << p.x << ", " << p.y << ")");
    REQUIRE((p.x > 0.1 && p.x < 0.9 && p.y > 0.1 && p.y < 0.9));
    const glm::vec4 emissive(0.25f, 0.5f, 1.0f, 1.0f);

    SUBCASE("OPAQUE: alpha 0.3 is ignored, the pixel is the emissive colour with alpha 1") {
        Frame1 f;
        render(emissiveMaterial(0.3f, "OPAQUE"), f);
        CHECK(f.get("backbuffer.reference").load(px, py) == emissive);
        checkCoverage(f.get("depth"), toWorld, 0.0, 1.0, 0.0, 1.0);
    }
    SUBCASE("MASK: alpha below alphaCutoff is cut, at or above it is drawn opaque") {
        for (const auto& [alpha, cutoff, drawn] : {std::tuple{0.4f, 0.5, false}, std::tuple{0.6f, 0.5, true},
                                                   std::tuple{0.6f, 0.7, false}, std::tuple{0.5f, 0.5, true}}) {
            const float a = alpha;
            const double c = cutoff;
            const bool d = drawn;
            CAPTURE(a);
            CAPTURE(c);
            Frame1 f;
            render(emissiveMaterial(a, "MASK", c), f);
            CHECK((f.get("depth").loadDepth(px, py) < 1.0f) == d);
            if (d) CHECK(f.get("backbuffer.reference").load(px, py) == emissive);
        }
    }
    SUBCASE("BLEND: src x a + dst x (1 - a) in linear values on the sRGB back buffer, no depth written") {
        Frame1 empty, blended;
        renderScene(Scene{}, camera, "preview", w, h, Precision::Exact, empty);  // the background alone
        const float a = 0.25f;
        render(emissiveMaterial(a, "BLEND"), blended);
        CHECK(blended.get("depth").loadDepth(px, py) == 1.0f);  // the blend pass writes no depth
        // D3D11.3 §3.2.3.7-8: an _SRGB target's destination is decoded to linear, blended and
        // encoded once. The background's code decodes to the nearest float of its exact value and
        // the blend runs in float, so the expected code computed here in double can differ from
        // the stored one only where the blend lands within float rounding of a code boundary: 1 code.
        for (int ch = 0; ch < 3; ++ch) {
            CAPTURE(ch);
            const auto dstCode = std::to_integer<std::uint8_t>(empty.get("backbuffer").texel(px, py)[ch]);
            const double expectedLinear = double(emissive[ch]) * a + double(convert::srgb8ToLinear(dstCode)) * (1.0 - a);
            const int expectedCode = convert::linearToSrgb8(float(expectedLinear));
            const int gotCode = std::to_integer<int>(blended.get("backbuffer").texel(px, py)[ch]);
            CHECK(std::abs(gotCode - expectedCode) <= 1);
        }
    }
}

TEST_CASE("glTF rules: a texture's texCoord 1 samples TEXCOORD_1 (glTF 2.0 textureInfo.texCoord, §3.7.2.1)") {
    // A 2 x 1 texture, red | green, nearest filtering. TEXCOORD_0 is (0.25, 0.5) at every vertex
    // (the red texel), TEXCOORD_1 (0.75, 0.5) (the green one): the emissive texture's texCoord
    // picks the colour, sRGB-decoded 255 -> 1.0 exactly.
    constexpr std::uint32_t w = 64, h = 48;
    const Camera camera = cameraOnZ(3.0f);
    const std::vector<std::uint8_t> png = rgbaRowPng({255, 0, 0, 255, 0, 255, 0, 255});
    for (const int texCoord : {0, 1}) {
        CAPTURE(texCoord);
        GltfDoc g;
        json prim = quadPrimitive(g);
        prim["attributes"]["TEXCOORD_0"] = g.data(std::vector<float>{0.25f, 0.5f, 0.25f, 0.5f, 0.25f, 0.5f, 0.25f, 0.5f}, kFloat, "VEC2", 2);
        prim["attributes"]["TEXCOORD_1"] = g.data(std::vector<float>{0.75f, 0.5f, 0.75f, 0.5f, 0.75f, 0.5f, 0.75f, 0.5f}, kFloat, "VEC2", 2);
        g.doc["images"] = json::array({{{"uri", "data:image/png;base64," + base64(png)}}});
        g.doc["samplers"] = json::array({{{"magFilter", 9728}, {"minFilter", 9728}}});  // NEAREST
        g.doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}});
        g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorFactor", {0.0, 0.0, 0.0, 1.0}}}},
                                           {"emissiveFactor", {1.0, 1.0, 1.0}},
                                           {"emissiveTexture", {{"index", 0}, {"texCoord", texCoord}}}}});
        singleNode(g, prim);
        Frame1 f;
        renderScene(loadText(g.text()), camera, "preview", w, h, Precision::Reference, f);
        const glm::vec4 expected = texCoord == 1 ? glm::vec4(0.0f, 1.0f, 0.0f, 1.0f) : glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);
        CHECK(f.get("backbuffer.reference").load(40, 16) == expected);
    }
}

TEST_CASE("glTF rules: orthographic xmag / ymag and a perspective aspectRatio set the projection (glTF 2.0 §3.10.3)") {
    SUBCASE("orthographic: xmag 2, ymag 1 are the half extents of the view at 128 x 64") {
        constexpr std::uint32_t w = 128, h = 64;
        GltfDoc g;
        g.doc["materials"] = json::array({emissiveMaterial(1.0f, nullptr)});
        singleNode(g, quadPrimitive(g));
        g.doc["cameras"] = json::array({{{"type", "orthographic"}, {"orthographic", {{"xmag", 2.0}, {"ymag", 1.0}, {"znear", 0.1}, {"zfar", 10.0}}}}});
        g.doc["nodes"].push_back({{"camera", 0}, {"translation", {0.0, 0.0, 3.0}}});
        g.doc["scenes"][0]["nodes"] = {0, 1};
        const Scene scene = loadText(g.text());
        REQUIRE(scene.cameras.size() == 1);
        Frame1 f;
        renderScene(scene, scene.cameras[0], "preview", w, h, Precision::Exact, f);
        // 1 world unit = w / (2 xmag) = 32 px across and h / (2 ymag) = 32 px down: 32 x 32 pixels.
        CHECK(checkCoverage(f.get("depth"), orthographicRay(w, h, 2.0, 1.0), 0.0, 1.0, 0.0, 1.0) == 32 * 32);
    }
    SUBCASE("perspective: aspectRatio 2 is used at a square 96 x 96 viewport; absent, the viewport's 1") {
        constexpr std::uint32_t w = 96, h = 96;
        const double yfov = 0.8;  // rad
        for (const bool withAspect : {true, false}) {
            CAPTURE(withAspect);
            GltfDoc g;
            g.doc["materials"] = json::array({emissiveMaterial(1.0f, nullptr)});
            singleNode(g, quadPrimitive(g));
            json perspective = {{"yfov", yfov}, {"znear", 0.1}};
            if (withAspect) perspective["aspectRatio"] = 2.0;
            g.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", perspective}}});
            g.doc["nodes"].push_back({{"camera", 0}, {"translation", {0.0, 0.0, 3.0}}});
            g.doc["scenes"][0]["nodes"] = {0, 1};
            const Scene scene = loadText(g.text());
            REQUIRE(scene.cameras.size() == 1);
            Frame1 f;
            renderScene(scene, scene.cameras[0], "preview", w, h, Precision::Exact, f);
            // The spec's matrix divides x by aspectRatio (a[0][0] = 1 / (aspectRatio tan(0.5 yfov))):
            // the quad is half as wide on screen with aspectRatio 2 as with the viewport's 1.
            checkCoverage(f.get("depth"), perspectiveRay(w, h, yfov, withAspect ? 2.0 : 1.0, 3.0), 0.0, 1.0, 0.0, 1.0);
        }
    }
}

TEST_CASE("glTF rules: tangent w = -1 flips the bitangent, generated tangents read the green channel upright unless the old generator is asked for (glTF 2.0 §3.7.2.1, §3.9.3)") {
    // A 1 x 1 normal map with codes (128, 204, 255): tangent-space n = code / 255 x 2 - 1 =
    // (1/255, 0.6, 1) (glTF 2.0 §3.9.3: +Y up in the image). The quad's frame is T = +X, N = +Z,
    // B = cross(N, T) x w = w x +Y. Mapped N = normalize(n.x T + n.y B + n.z N). A directional
    // light travels along (0, -0.6, -0.8): L = (0, 0.6, 0.8).
    const std::vector<std::uint8_t> png = rgbaRowPng({128, 204, 255, 255});
    const glm::dvec3 nTangent(128.0 / 255.0 * 2.0 - 1.0, 204.0 / 255.0 * 2.0 - 1.0, 1.0);
    const glm::dvec3 lightTo(0.0, 0.6, 0.8);
    const auto expectedNDotL = [&](double w) {
        const glm::dvec3 n = glm::normalize(glm::dvec3(nTangent.x, nTangent.y * w, nTangent.z));
        return glm::dot(n, lightTo);
    };
    MESSAGE("N.L: w = +1 " << expectedNDotL(1.0) << ", w = -1 " << expectedNDotL(-1.0));
    struct Case {
        const char* what;
        bool tangents;
        float w;
        bool bitangentUp;
        double expected;
    };
    // The quad's UVs are upright (the image's top at world +Y), so the image's +Y is world +Y:
    // the truth is w = +1, as an exporter writes it. Generated tangents take B = -dP/dv, up the
    // image (GltfLoadOptions::generatedBitangentUp, the default); with it off they take B = dP/dv,
    // down the image (w = -1: tessera's generator before ERRATA #33 was corrected).
    const Case cases[] = {{"TANGENT w = +1", true, 1.0f, true, expectedNDotL(1.0)},
                          {"TANGENT w = -1", true, -1.0f, true, expectedNDotL(-1.0)},
                          {"TANGENT w = +1, the old generator's option changes nothing", true, 1.0f, false, expectedNDotL(1.0)},
                          {"generated, bitangent down the image (ERRATA #33's old default)", false, 0.0f, false, expectedNDotL(-1.0)},
                          {"generated (default, bitangent up): the truth", false, 0.0f, true, expectedNDotL(1.0)}};
    for (const Case& c : cases) {
        CAPTURE(c.what);
        GltfDoc g;
        g.doc["images"] = json::array({{{"uri", "data:image/png;base64," + base64(png)}}});
        g.doc["textures"] = json::array({{{"source", 0}}});
        g.doc["materials"] = json::array({{{"normalTexture", {{"index", 0}}}}});
        singleNode(g, quadPrimitive(g, c.tangents, c.w));
        Scene scene = loadText(g.text(), c.bitangentUp);
        Light sun;
        sun.type = LightType::Directional;
        sun.directionWorld = {0.0f, -0.6f, -0.8f};
        scene.lights = {sun};
        PixelWatch watch{32, 20, {}};
        Frame1 f;
        renderScene(scene, cameraOnZ(3.0f), "forward", 64, 48, Precision::Exact, f, &watch);
        int terms = 0;
        for (const PixelDrawEvent& e : watch.events)
            for (const LightTerm& term : e.lights) {
                ++terms;
                // Texel decode, the view rotation and two normalizations in float: a few ULPs of 1.
                CHECK(std::abs(double(term.nDotL) - c.expected) < 1e-5);
            }
        CHECK(terms == 1);
    }
}

} // namespace tessera_test::scene_gltf_rules_test
