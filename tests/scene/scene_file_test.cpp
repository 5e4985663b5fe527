// Tests of the scene file: a good file round-trips every field; every validation error names
// the file and the JSON-pointer key path; the bundled scenes/*.json parse and their models
// exist; the schema lists exactly the parser's top-level keys; loadScene builds cameras/lights.
#include <tessera/errors/input_error.h>
#include <tessera/scene/scene_file.h>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::scene_scene_file_test {

namespace fs = std::filesystem;
using tessera::CameraSource;
using tessera::InputError;
using tessera::LightType;
using tessera::Precision;
using tessera::SceneDescription;

namespace {

const fs::path kSceneFile = "/scenes/test/scene.json";
const fs::path kSourceDir = TESSERA_SOURCE_DIR;

// A minimal valid scene with `extra` top-level members spliced in (e.g. R"("resolution": [1, 2])").
std::string scene(const std::string& extra = "") {
    std::string text = R"({"models": [{"path": "m.gltf"}])";
    if (!extra.empty()) text += ", " + extra;
    return text + "}";
}

// Parsing `text` must throw an InputError naming the file, the key path and `what`.
void expectError(const std::string& text, const std::string& keyPath, const std::string& what) {
    CAPTURE(text);
    std::string message;
    try {
        tessera::parseSceneJson(text, kSceneFile);
    } catch (const InputError& e) {
        message = e.what();
    }
    CAPTURE(message);
    REQUIRE_FALSE(message.empty());
    CHECK(message.find(kSceneFile.string() + ": ") == 0);
    if (!keyPath.empty()) CHECK(message.find(": " + keyPath + ": ") != std::string::npos);
    CHECK(message.find(what) != std::string::npos);
}

} // namespace

TEST_CASE("a complete scene file round-trips every field") {
    const std::string text = R"({
      "$schema": "scene.schema.json",
      "description": "all keys",
      "models": [
        {"path": "models/a.gltf"},
        {"path": "/abs/b.glb", "translation": [1, 2, 3], "rotation": [0, 0, 0, 2], "scale": [2, 3, 4]},
        {"path": "../c.gltf", "scale": 0.5}
      ],
      "camera": {"position": [1, 2, 3], "rotation": [0, 1, 0, 1], "fovYDeg": 60, "near": 0.5, "far": 50},
      "resolution": [640, 360],
      "technique": "deferred",
      "options": {"tileSize": 16, "nested": {"a": [1, 2]}},
      "precision": "reference",
      "lights": [
        {"type": "point", "name": "p", "position": [1, 2, 3], "color": [0.5, 0.25, 1], "intensity": 2, "range": 7, "enabled": false},
        {"type": "spot", "position": [0, 1, 0], "direction": [0, -2, 0], "spotAngleDeg": 30},
        {"type": "directional", "direction": [3, 0, 4]},
        {"type": "capsule", "position": [1, 0, 0], "direction": [0, 0, 2], "length": 3, "range": 2}
      ],
      "gltfLights": {"enabled": true, "defaultRange": 12},
      "generate": [
        {"count": 64, "seed": 18446744073709551615, "pointFraction": 0.25, "box": {"min": [-1, -2, -3], "max": [1, 2, 3]},
         "range": [35, 40], "spotAngleDeg": [35, 60], "intensity": [0.5, 2], "colorMin": [0, 0.1, 0.2], "colorMax": [1, 0.9, 0.8]},
        {"count": 0}
      ]
    })";
    const SceneDescription d = tessera::parseSceneJson(text, kSceneFile);
    CHECK(d.file == kSceneFile);
    REQUIRE(d.models.size() == 3);
    CHECK(d.models[0].path == fs::path("/scenes/test/models/a.gltf"));
    CHECK(d.models[1].path == fs::path("/abs/b.glb"));
    CHECK(d.models[2].path == fs::path("/scenes/c.gltf"));
    CHECK(d.models[0].worldFromFile == glm::mat4(1.0f));
    // T * R * S with R = the identity quaternion [0, 0, 0, 2] normalized.
    const glm::mat4 m1 = d.models[1].worldFromFile;
    CHECK(m1[0] == glm::vec4(2, 0, 0, 0));
    CHECK(m1[1] == glm::vec4(0, 3, 0, 0));
    CHECK(m1[2] == glm::vec4(0, 0, 4, 0));
    CHECK(m1[3] == glm::vec4(1, 2, 3, 1));
    CHECK(d.models[2].worldFromFile[1][1] == 0.5f);

    CHECK(d.cameraSource == CameraSource::Explicit);
    CHECK_FALSE(d.cameraFromGltf);
    CHECK(d.camera.positionWorld == glm::vec3(1, 2, 3));
    const float s = 1.0f / std::sqrt(2.0f);  // [0, 1, 0, 1] normalized: 90 degrees about +Y
    CHECK(d.camera.orientationWorld.y == doctest::Approx(s));
    CHECK(d.camera.orientationWorld.w == doctest::Approx(s));
    CHECK(d.camera.orientationWorld.x == 0.0f);
    CHECK(d.camera.fovYDeg == 60.0f);
    CHECK(d.camera.nearZ == 0.5f);
    CHECK(d.camera.farZ == 50.0f);

    CHECK(d.width == 640);
    CHECK(d.height == 360);
    CHECK(d.technique == "deferred");
    CHECK(d.techniqueOptions == nlohmann::json::parse(R"({"tileSize": 16, "nested": {"a": [1, 2]}})"));
    CHECK(d.precision == Precision::Reference);

    REQUIRE(d.explicitLights.size() == 4);
    const auto& p = d.explicitLights[0];
    CHECK(p.type == LightType::Point);
    CHECK(p.name == "p");
    CHECK(p.positionWorld == glm::vec3(1, 2, 3));
    CHECK(p.color == glm::vec3(0.5f, 0.25f, 1.0f));
    CHECK(p.intensity == 2.0f);
    CHECK(p.range == 7.0f);
    CHECK_FALSE(p.enabled);
    const auto& sp = d.explicitLights[1];
    CHECK(sp.type == LightType::Spot);
    CHECK(sp.directionWorld == glm::vec3(0, -1, 0));
    CHECK(sp.spotHalfAngleDeg == 30.0f);
    CHECK(sp.range == 100.0f);  // 3dgep's default Range
    CHECK(sp.color == glm::vec3(1.0f));
    CHECK(sp.intensity == 1.0f);
    CHECK(sp.enabled);
    const auto& dl = d.explicitLights[2];
    CHECK(dl.type == LightType::Directional);
    CHECK(dl.directionWorld == glm::vec3(0.6f, 0.0f, 0.8f));
    CHECK(std::isinf(dl.range));
    const auto& cl = d.explicitLights[3];
    CHECK(cl.type == LightType::Capsule);
    CHECK(cl.positionWorld == glm::vec3(1.0f, 0.0f, 0.0f));
    CHECK(cl.directionWorld == glm::vec3(0.0f, 0.0f, 1.0f));
    CHECK(cl.length == 3.0f);
    CHECK(cl.range == 2.0f);

    CHECK(d.useGltfLights);
    CHECK(d.gltfLightDefaultRange == 12.0f);

    REQUIRE(d.generators.size() == 2);
    const auto& g = d.generators[0];
    CHECK(g.count == 64);
    CHECK(g.seed == 18446744073709551615ull);
    CHECK(g.pointFraction == 0.25f);
    REQUIRE(g.box.has_value());
    CHECK(g.box->minWorld == glm::vec3(-1, -2, -3));
    CHECK(g.box->maxWorld == glm::vec3(1, 2, 3));
    CHECK(g.range == glm::vec2(35, 40));
    CHECK(g.spotHalfAngleDeg == glm::vec2(35, 60));
    CHECK(g.intensity == glm::vec2(0.5f, 2.0f));
    CHECK(g.colorMin == glm::vec3(0.0f, 0.1f, 0.2f));
    CHECK(g.colorMax == glm::vec3(1.0f, 0.9f, 0.8f));
    const auto& g1 = d.generators[1];
    CHECK(g1.count == 0);
    CHECK(g1.seed == 0);
    CHECK_FALSE(g1.box.has_value());
    CHECK(g1.range == glm::vec2(1, 2));
}

TEST_CASE("defaults of a minimal scene file") {
    const SceneDescription d = tessera::parseSceneJson(scene(), kSceneFile);
    CHECK(d.width == 1280);
    CHECK(d.height == 720);
    CHECK(d.technique == "forward");
    CHECK(d.techniqueOptions == nlohmann::json::object());
    CHECK(d.precision == Precision::Exact);
    CHECK(d.cameraSource == CameraSource::Auto);
    CHECK(d.explicitLights.empty());
    CHECK_FALSE(d.useGltfLights);
    CHECK(d.generators.empty());
}

TEST_CASE("camera forms: look-at, glTF camera, framing overrides") {
    SceneDescription d = tessera::parseSceneJson(scene(R"("camera": {"position": [0, 0, 5], "target": [0, 0, 0]})"), kSceneFile);
    CHECK(d.cameraSource == CameraSource::Explicit);
    // Looking from +Z at the origin is the identity orientation (the camera looks down -Z).
    CHECK(std::abs(d.camera.orientationWorld.w) == doctest::Approx(1.0));
    const glm::vec3 forward = d.camera.orientationWorld * glm::vec3(0, 0, -1);
    CHECK(forward.z == doctest::Approx(-1.0));

    d = tessera::parseSceneJson(scene(R"("camera": {"position": [0, 0, 0], "target": [1, 0, 0], "up": [0, 2, 0]})"), kSceneFile);
    const glm::vec3 f2 = d.camera.orientationWorld * glm::vec3(0, 0, -1);
    CHECK(f2.x == doctest::Approx(1.0));
    const glm::vec3 u2 = d.camera.orientationWorld * glm::vec3(0, 1, 0);
    CHECK(u2.y == doctest::Approx(1.0));

    d = tessera::parseSceneJson(scene(R"("camera": {"gltf": 2, "far": 80})"), kSceneFile);
    CHECK(d.cameraSource == CameraSource::Gltf);
    CHECK(d.cameraFromGltf);
    CHECK(d.gltfCameraIndex == 2);
    CHECK(d.cameraFarZ == 80.0f);
    CHECK_FALSE(d.cameraNearZ.has_value());

    d = tessera::parseSceneJson(scene(R"("camera": {"fovYDeg": 30})"), kSceneFile);
    CHECK(d.cameraSource == CameraSource::Framing);
    CHECK(d.cameraFovYDeg == 30.0f);
}

TEST_CASE("invalid JSON names the file and the position") {
    expectError(R"({"models": [ })", "", "invalid JSON (byte ");
    expectError("{\n  \"models\": [],\n  oops\n}", "", "line 3");
    expectError(R"({"models": [{"path": "a"}], "x": NaN})", "", "invalid JSON");
    expectError("[1, 2]", "", "expected an object, got array");
}

TEST_CASE("unknown keys are errors, with the nearest known key suggested") {
    expectError(scene(R"("resolutoin": [1, 1])"), "/resolutoin", "did you mean \"resolution\"");
    expectError(scene(R"("zzzzzzzz": 1)"), "/zzzzzzzz", "unknown key \"zzzzzzzz\" (known keys:");
    expectError(R"({"models": [{"path": "a", "translate": [0, 0, 0]}]})", "/models/0/translate", "did you mean \"translation\"");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "colour": [1, 1, 1]}])"), "/lights/0/colour",
                "did you mean \"color\"");
    expectError(scene(R"("camera": {"fov": 40})"), "/camera/fov", "unknown key");
    expectError(scene(R"("gltfLights": {"range": 3})"), "/gltfLights/range", "unknown key");
    expectError(scene(R"("generate": [{"count": 1, "seeds": 3}])"), "/generate/0/seeds", "did you mean \"seed\"");
    expectError(scene(R"("generate": [{"count": 1, "box": {"min": [0, 0, 0], "max": [1, 1, 1], "mid": 1}}])"),
                "/generate/0/box/mid", "unknown key");
    expectError(scene(R"("a/b~c": 1)"), "/a~1b~0c", "unknown key");  // RFC 6901 escaping
}

TEST_CASE("wrong types name the key path and both types") {
    expectError(scene(R"("resolution": ["1280", 720])"), "/resolution/0", "expected an integer, got string");
    expectError(scene(R"("resolution": [1280.5, 720])"), "/resolution/0", "expected an integer, got number");
    expectError(scene(R"("resolution": [1280])"), "/resolution", "expected an array of 2 elements, got 1");
    expectError(scene(R"("resolution": {"w": 1})"), "/resolution", "expected an array, got object");
    expectError(R"({"models": {"path": "a"}})", "/models", "expected an array, got object");
    expectError(R"({"models": [{"path": 3}]})", "/models/0/path", "expected a string, got integer");
    expectError(scene(R"("technique": 5)"), "/technique", "expected a string, got integer");
    expectError(scene(R"("options": [1])"), "/options", "expected an object, got array");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, "1", 0]}])"), "/lights/0/position/1",
                "expected a number, got string");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "enabled": 1}])"), "/lights/0/enabled",
                "expected a boolean, got integer");
    expectError(scene(R"("gltfLights": {"enabled": "yes"})"), "/gltfLights/enabled", "expected a boolean, got string");
    expectError(scene(R"("generate": [{"count": null}])"), "/generate/0/count", "expected an integer, got null");
    expectError(scene(R"("generate": {"count": 1})"), "/generate", "expected an array, got object");
    expectError(R"({"models": [{"path": "a", "scale": "big"}]})", "/models/0/scale", "expected a number or an array");
}

TEST_CASE("values out of range") {
    expectError(scene(R"("resolution": [0, 720])"), "/resolution/0", "0 is outside 1..16384");
    expectError(scene(R"("resolution": [1280, 16385])"), "/resolution/1", "16385 is outside 1..16384");
    expectError(scene(R"("resolution": [-5, 720])"), "/resolution/0", "-5 is outside 1..16384");
    expectError(scene(R"("resolution": [1000000000, 720])"), "/resolution/0", "is outside 1..16384");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "range": -1}])"), "/lights/0/range", "-1 is negative");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "range": 0}])"), "/lights/0/range", "must be > 0");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "intensity": -0.5}])"), "/lights/0/intensity", "is negative");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "color": [1, -1, 1]}])"), "/lights/0/color/1", "is negative");
    expectError(scene(R"("lights": [{"type": "spot", "position": [0, 0, 0], "direction": [0, -1, 0], "spotAngleDeg": 90}])"),
                "/lights/0/spotAngleDeg", "90 is outside (0, 90)");
    expectError(scene(R"("lights": [{"type": "spot", "position": [0, 0, 0], "direction": [0, -1, 0], "spotAngleDeg": 0}])"),
                "/lights/0/spotAngleDeg", "0 is outside (0, 90)");
    expectError(scene(R"("lights": [{"type": "spot", "position": [0, 0, 0], "direction": [0, 0, 0]}])"), "/lights/0/direction", "zero");
    expectError(scene(R"("generate": [{"count": 1000001}])"), "/generate/0/count", "1000001 is outside 0..1000000");
    expectError(scene(R"("generate": [{"count": -1}])"), "/generate/0/count", "-1 is outside 0..1000000");
    // 1,000,000 lights per generator and for all generators together (a 2 KB file asked for 2.5 GB).
    expectError(scene(R"("generate": [{"count": 600000}, {"count": 300000}, {"count": 100001}])"), "/generate/2/count",
                "the generators make 1000001 lights up to this one; all generators together make at most 1000000");
    expectError(scene(R"("generate": [{"count": 999999}, {"kind": "amd-forwardplus11", "count": 0, "spotCount": 2}])"),
                "/generate/1/count", "make 1000001 lights");
    expectError(scene(R"("generate": [{"count": 1, "seed": -1}])"), "/generate/0/seed", "-1 is outside");
    expectError(scene(R"("generate": [{"count": 1, "pointFraction": 1.5}])"), "/generate/0/pointFraction", "1.5 is outside [0, 1]");
    expectError(scene(R"("generate": [{"count": 1, "range": [2, 1]}])"), "/generate/0/range", "min 2 is greater than max 1");
    expectError(scene(R"("generate": [{"count": 1, "range": [0, 1]}])"), "/generate/0/range/0", "must be > 0");
    expectError(scene(R"("generate": [{"count": 1, "range": [-3, 1]}])"), "/generate/0/range/0", "-3 is negative");
    expectError(scene(R"("generate": [{"count": 1, "spotAngleDeg": [35, 95]}])"), "/generate/0/spotAngleDeg/1", "95 is outside (0, 90)");
    expectError(scene(R"("generate": [{"count": 1, "spotAngleDeg": [60, 35]}])"), "/generate/0/spotAngleDeg", "greater than max");
    expectError(scene(R"("generate": [{"count": 1, "intensity": [-1, 1]}])"), "/generate/0/intensity/0", "is negative");
    expectError(scene(R"("generate": [{"count": 1, "box": {"min": [0, 5, 0], "max": [1, 1, 1]}}])"), "/generate/0/box/min/1",
                "min 5 is greater than max 1");
    expectError(scene(R"("generate": [{"count": 1, "colorMin": [0.5, 0, 0], "colorMax": [0.4, 1, 1]}])"), "/generate/0/colorMin/0",
                "greater than colorMax");
    expectError(scene(R"("gltfLights": {"defaultRange": -2})"), "/gltfLights/defaultRange", "is negative");
    expectError(R"({"models": [{"path": "a", "scale": 0}]})", "/models/0/scale", "must be > 0");
    expectError(R"({"models": [{"path": "a", "scale": [1, -1, 1]}]})", "/models/0/scale/1", "is negative");
    expectError(R"({"models": [{"path": "a", "rotation": [0, 0, 0, 0]}]})", "/models/0/rotation", "zero");
    expectError(R"({"models": [{"path": "a", "rotation": [0, 0, 1]}]})", "/models/0/rotation", "array of 4 elements");
    expectError(scene(R"("camera": {"position": [0, 0, 0], "rotation": [0, 0, 0, 1], "fovYDeg": 180})"), "/camera/fovYDeg", "outside (0, 180)");
    expectError(scene(R"("camera": {"position": [0, 0, 0], "rotation": [0, 0, 0, 1], "near": 0})"), "/camera/near", "must be > 0");
    expectError(scene(R"("camera": {"near": 10, "far": 5})"), "/camera/far", "not greater than near");
    expectError(scene(R"("camera": {"position": [0, 0, 0], "rotation": [0, 0, 0, 1], "near": 2000})"), "/camera/near",
                "not greater than near");
    expectError(scene(R"("camera": {"gltf": -1})"), "/camera/gltf", "is outside");
}

TEST_CASE("non-finite and non-binary32 numbers are rejected everywhere") {
    // JSON has no NaN or Infinity literal; nlohmann_json 3.11 rejects an overflowing literal
    // such as 1e999 while parsing (out_of_range 406), which is reported with its line/column.
    expectError(scene(R"("lights": [{"type": "point", "position": [1e999, 0, 0]}])"), "",
                "invalid JSON at line 1, column 76: number overflow parsing '1e999'");
    expectError("{\n\"models\": [{\"path\": \"a\", \"translation\": [0, -1e999, 0]}]}", "",
                "at line 2, column 45: number overflow parsing '-1e999'");
    expectError(scene(R"("gltfLights": {"defaultRange": 1e400})"), "", "number overflow parsing '1e400'");
    // Finite in double but not in binary32.
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "intensity": 1e39}])"), "/lights/0/intensity",
                "outside the binary32 range");
    expectError(R"({"models": [{"path": "a", "translation": [0, -3.5e38, 0]}]})", "/models/0/translation/1", "outside the binary32 range");
    expectError(scene(R"("camera": {"position": [0, 0, 0], "rotation": [0, 0, 0, 1e300]})"), "/camera/rotation/3", "binary32");
    expectError(scene(R"("generate": [{"count": 1, "box": {"min": [0, 0, 0], "max": [1e50, 1, 1]}}])"), "/generate/0/box/max/0",
                "binary32");
    expectError(scene(R"("lights": [{"type": "spot", "position": [0, 0, 0], "direction": [0, 0, 0]}])"), "/lights/0/direction",
                "the direction is zero");
}

TEST_CASE("directions and quaternions whose squared length over- or underflows binary32 still normalize") {
    // v / sqrt(dot(v, v)) is inf / inf = NaN for 3e38 (dot = 1.8e77) and 0 / 0 for 1e-30
    // (dot = 2e-60 flushes to 0): the scaled path divides by the largest component first.
    const SceneDescription big = tessera::parseSceneJson(
        scene(R"("lights": [{"type": "spot", "position": [0, 0, 0], "direction": [3e38, 3e38, 0]}])"), "big.json");
    CHECK(big.explicitLights[0].directionWorld.x == doctest::Approx(0.70710678).epsilon(1e-7));
    CHECK(big.explicitLights[0].directionWorld.y == big.explicitLights[0].directionWorld.x);
    const SceneDescription tiny = tessera::parseSceneJson(
        scene(R"("lights": [{"type": "spot", "position": [0, 0, 0], "direction": [0, -1e-30, 1e-30]}])"), "tiny.json");
    CHECK(tiny.explicitLights[0].directionWorld.y == doctest::Approx(-0.70710678).epsilon(1e-7));
    CHECK(tiny.explicitLights[0].directionWorld.z == -tiny.explicitLights[0].directionWorld.y);
    // Ordinary vectors keep the plain expression's bits: (1, 2, 2) / 3.
    const SceneDescription plain = tessera::parseSceneJson(
        scene(R"("lights": [{"type": "spot", "position": [0, 0, 0], "direction": [1, 2, 2]}])"), "plain.json");
    CHECK(plain.explicitLights[0].directionWorld == glm::vec3(1.0f / 3.0f, 2.0f / 3.0f, 2.0f / 3.0f));
    // A look-at camera 1e19 away: |target - position|^2 = 3e38 x ... overflowed and was refused as
    // "up is parallel to the view direction"; now it looks at its target.
    const SceneDescription far = tessera::parseSceneJson(
        scene(R"("camera": {"position": [0, 0, 1e19], "target": [0, 0, 0]})"), "far.json");
    const glm::vec3 forwardWorld = far.camera.orientationWorld * glm::vec3(0.0f, 0.0f, -1.0f);
    CHECK(forwardWorld.z == doctest::Approx(-1.0));
    // target - position = -6e38 is itself beyond binary32: refused with the real cause.
    expectError(scene(R"("camera": {"position": [3e38, 0, 0], "target": [-3e38, 0, 1]})"), "/camera/target",
                "target - position overflows binary32");
}

TEST_CASE("structural errors: required keys, conflicting camera forms, light types, technique, precision") {
    expectError("{}", "", "missing required key \"models\"");
    expectError(R"({"models": []})", "/models", "at least one model");
    expectError(R"({"models": [{}]})", "/models/0", "missing required key \"path\"");
    expectError(R"({"models": [{"path": ""}]})", "/models/0/path", "empty");
    expectError(scene(R"("technique": "")"), "/technique", "empty");
    expectError(scene(R"("precision": "medium")"), "/precision", "unknown precision \"medium\"");
    expectError(scene(R"("camera": {"gltf": 0, "position": [0, 0, 0]})"), "/camera/position", "not allowed together with \"gltf\"");
    expectError(scene(R"("camera": {"rotation": [0, 0, 0, 1]})"), "/camera/rotation", "needs \"position\"");
    expectError(scene(R"("camera": {"position": [0, 0, 0]})"), "/camera", "needs \"rotation\" or \"target\"");
    expectError(scene(R"("camera": {"position": [0, 0, 0], "rotation": [0, 0, 0, 1], "target": [1, 0, 0]})"), "/camera/target",
                "not both");
    expectError(scene(R"("camera": {"position": [1, 1, 1], "target": [1, 1, 1]})"), "/camera/target", "equals the position");
    expectError(scene(R"("camera": {"position": [0, 0, 0], "target": [0, 5, 0]})"), "/camera/target", "parallel");
    expectError(scene(R"("lights": [{"position": [0, 0, 0]}])"), "/lights/0", "missing required key \"type\"");
    expectError(scene(R"("lights": [{"type": "area", "position": [0, 0, 0]}])"), "/lights/0/type", "unknown light type \"area\"");
    expectError(scene(R"("lights": [{"type": "point"}])"), "/lights/0", "missing required key \"position\"");
    expectError(scene(R"("lights": [{"type": "spot", "position": [0, 0, 0]}])"), "/lights/0", "missing required key \"direction\"");
    expectError(scene(R"("lights": [{"type": "directional", "direction": [0, -1, 0], "range": 5}])"), "/lights/0/range",
                "not used by a directional light");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "spotAngleDeg": 30}])"), "/lights/0/spotAngleDeg",
                "not used by a point light");
    // Capsule lights: the segment needs a positive length; length belongs to capsules only.
    expectError(scene(R"("lights": [{"type": "capsule", "position": [0, 0, 0], "direction": [1, 0, 0]}])"), "/lights/0",
                "missing required key \"length\"");
    expectError(scene(R"("lights": [{"type": "capsule", "position": [0, 0, 0], "direction": [1, 0, 0], "length": 0}])"),
                "/lights/0/length", "0");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "length": 2}])"), "/lights/0/length",
                "not used by a point light");
    expectError(scene(R"("lights": [{"type": "capsule", "position": [0, 0, 0], "direction": [1, 0, 0], "length": 1, "spotAngleDeg": 9}])"),
                "/lights/0/spotAngleDeg", "not used by a capsule light");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0]}, {"type": "point", "position": [0, 0, 0], "range": -4}])"),
                "/lights/1/range", "-4 is negative");
    expectError(scene(R"("generate": [{"seed": 3}])"), "/generate/0", "missing required key \"count\"");
    expectError(scene(R"("generate": [{"count": 1, "box": {"min": [0, 0, 0]}}])"), "/generate/0/box", "missing required key \"max\"");
}

TEST_CASE("light groups: models and lights list groups 0..7 as bit masks, with the defaults group 0 and every group") {
    const SceneDescription d = tessera::parseSceneJson(
        R"({"models": [{"path": "a.gltf"}, {"path": "b.gltf", "lightGroups": [1, 2]}, {"path": "c.gltf", "lightGroups": []}],
            "lights": [{"type": "point", "position": [0, 0, 0]}, {"type": "point", "position": [0, 0, 0], "lightGroups": [7, 0]}]})",
        kSceneFile);
    REQUIRE(d.models.size() == 3);
    CHECK(d.models[0].lightGroups == 0x01);  // kDefaultGeometryLightGroups
    CHECK(d.models[1].lightGroups == 0x06);  // bits 1 and 2
    CHECK(d.models[2].lightGroups == 0x00);  // in no group: no light reaches it under the stencil test
    REQUIRE(d.explicitLights.size() == 2);
    CHECK(d.explicitLights[0].lightGroups == 0xFF);
    CHECK(d.explicitLights[1].lightGroups == 0x81);
    expectError(R"({"models": [{"path": "a.gltf", "lightGroups": [8]}]})", "/models/0/lightGroups/0", "outside 0..7");
    expectError(R"({"models": [{"path": "a.gltf", "lightGroups": [1, 1]}]})", "/models/0/lightGroups/1", "listed twice");
    expectError(R"({"models": [{"path": "a.gltf", "lightGroups": 3}]})", "/models/0/lightGroups", "expected an array");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "lightGroups": [-1]}])"), "/lights/0/lightGroups/0",
                "outside 0..7");
}

TEST_CASE("parseSceneFile: a missing file and a file with an error name the file") {
    const fs::path missing = fs::path(TESSERA_TEST_OUTPUT_DIR) / "tessera-scene-test-does-not-exist.json";
    try {
        tessera::parseSceneFile(missing);
        FAIL("no exception");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()) == missing.string() + ": no such file");
    }
    const fs::path bad = fs::path(TESSERA_TEST_OUTPUT_DIR) / "tessera-scene-test-bad.json";
    {
        std::ofstream out(bad);
        out << scene(R"("resolution": [0, 1])");
    }
    try {
        tessera::parseSceneFile(bad);
        FAIL("no exception");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()) == bad.string() + ": /resolution/0: 0 is outside 1..16384");
    }
    fs::remove(bad);
}

TEST_CASE("every bundled scenes/*.json parses and names model files that exist") {
    int count = 0;
    for (const auto& entry : fs::directory_iterator(kSourceDir / "scenes")) {
        if (entry.path().extension() != ".json" || entry.path().filename() == "scene.schema.json") continue;
        CAPTURE(entry.path().string());
        ++count;
        SceneDescription d;
        REQUIRE_NOTHROW(d = tessera::parseSceneFile(entry.path()));
        for (const auto& model : d.models) {
            CAPTURE(model.path.string());
            CHECK(fs::is_regular_file(model.path));
        }
    }
    CHECK(count >= 3);  // default, sponza-large-lights, sponza-small-lights

    const SceneDescription large = tessera::parseSceneFile(kSourceDir / "scenes/sponza-large-lights.json");
    CHECK(large.width == 1280);
    CHECK(large.height == 720);
    CHECK(large.camera.fovYDeg == 45.0f);
    CHECK(large.camera.nearZ == 0.1f);
    CHECK(large.camera.farZ == 1000.0f);
    REQUIRE(large.generators.size() == 1);
    CHECK(large.generators[0].range == glm::vec2(35, 40));
    CHECK(large.generators[0].box->minWorld == glm::vec3(-15.0f, 0.1f, -15.0f));
    CHECK(large.generators[0].box->maxWorld == glm::vec3(15.0f, 15.0f, 15.0f));
    const SceneDescription small = tessera::parseSceneFile(kSourceDir / "scenes/sponza-small-lights.json");
    REQUIRE(small.generators.size() == 1);
    CHECK(small.generators[0].range == glm::vec2(1, 2));
    CHECK(small.generators[0].seed == large.generators[0].seed);

    const SceneDescription byDefault = tessera::parseSceneFile(kSourceDir / "scenes/default.json");
    CHECK(byDefault.width == 640);
    CHECK(byDefault.height == 360);
    CHECK(byDefault.technique == "forward");
    CHECK(byDefault.explicitLights.size() >= 3);
}

TEST_CASE("the schema is valid JSON and lists exactly the parser's top-level keys") {
    std::ifstream in(kSourceDir / "scenes/scene.schema.json");
    REQUIRE(in);
    nlohmann::json schema;
    REQUIRE_NOTHROW(schema = nlohmann::json::parse(in));
    CHECK(schema.at("$schema") == "https://json-schema.org/draft/2020-12/schema");
    CHECK(schema.at("additionalProperties") == false);
    std::set<std::string> schemaKeys;
    for (const auto& item : schema.at("properties").items()) {
        schemaKeys.insert(item.key());
        CHECK_MESSAGE(item.value().contains("description"), item.key());
    }
    const auto& parserKeys = tessera::sceneFileTopLevelKeys();
    CHECK(schemaKeys == std::set<std::string>(parserKeys.begin(), parserKeys.end()));
    CHECK(parserKeys.size() == schemaKeys.size());
    // Each parser key is accepted: a file using all of them parses.
    CHECK_NOTHROW(tessera::parseSceneJson(R"({"$schema": "x", "description": "y", "models": [{"path": "a"}], "camera": {},
        "resolution": [1, 1], "technique": "t", "options": {}, "precision": "fast", "lights": [], "gltfLights": {},
        "generate": []})", kSceneFile));
}

TEST_CASE("loadScene: a missing model names the scene file, the key path and the resolved path") {
    const SceneDescription d = tessera::parseSceneJson(
        R"({"models": [{"path": "khronos/Box/glTF/Box.gltf"}, {"path": "nowhere/missing.gltf"}]})", kSourceDir / "scenes/x.json");
    try {
        (void)tessera::loadScene(d, false);
        FAIL("no exception");
    } catch (const InputError& e) {
        const std::string message = e.what();
        CAPTURE(message);
        CHECK(message.find((kSourceDir / "scenes/x.json").string() + ": /models/1/path: ") == 0);
        CHECK(message.find((kSourceDir / "scenes/nowhere/missing.gltf").string()) != std::string::npos);
    }
}

TEST_CASE("loadScene: lights in order (explicit, glTF, generated), generators fill the bounds, cameras") {
    const std::string text = R"({
      "models": [{"path": "khronos/Box/glTF/Box.gltf", "translation": [10, 0, 0], "scale": 2}],
      "lights": [{"type": "point", "name": "first", "position": [0, 0, 0]}],
      "gltfLights": {"defaultRange": 5},
      "generate": [{"count": 100, "seed": 1, "pointFraction": 0.5},
                   {"count": 3, "box": {"min": [100, 100, 100], "max": [101, 101, 101]}}]
    })";
    const SceneDescription d = tessera::parseSceneJson(text, kSourceDir / "scenes/x.json");
    tessera::Camera camera;
    const tessera::Scene s = tessera::loadScene(d, false, &camera);
    REQUIRE(s.lights.size() == 1 + 100 + 3);  // Box has no KHR lights
    CHECK(s.lights[0].name == "first");
    const tessera::Bounds b = s.bounds();
    CHECK(b.minWorld.x == doctest::Approx(9.0));  // the unit box scaled by 2 around x = 10
    CHECK(b.maxWorld.x == doctest::Approx(11.0));
    for (std::size_t i = 1; i <= 100; ++i) {
        for (glm::length_t axis = 0; axis < 3; ++axis) {
            CHECK(s.lights[i].positionWorld[axis] >= b.minWorld[axis]);
            CHECK(s.lights[i].positionWorld[axis] <= b.maxWorld[axis]);
        }
    }
    for (std::size_t i = 101; i < 104; ++i) CHECK(s.lights[i].positionWorld.x >= 100.0f);
    // No camera in the file and none in Box.gltf: framing looks at the bounds' centre down -Z.
    CHECK(camera.positionWorld.x == doctest::Approx(10.0));
    CHECK(camera.positionWorld.z > b.maxWorld.z);
    CHECK(camera.orientationWorld.w == 1.0f);
    // The bounding sphere (radius sqrt(3)) fits the 45-degree vertical FOV: d = r / sin(22.5 deg).
    const double radius = std::sqrt(3.0);
    CHECK(double(camera.positionWorld.z) == doctest::Approx(radius / std::sin(22.5 * 3.14159265358979323846 / 180.0)).epsilon(1e-5));
    CHECK(camera.nearZ > 0.0f);
    CHECK(camera.farZ > camera.nearZ);

    SceneDescription gltfCamera = tessera::parseSceneJson(
        R"({"models": [{"path": "khronos/Box/glTF/Box.gltf"}], "camera": {"gltf": 0}})", kSourceDir / "scenes/x.json");
    try {
        (void)tessera::loadScene(gltfCamera, false, &camera);
        FAIL("no exception");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("/camera/gltf: glTF camera 0 does not exist") != std::string::npos);
    }
}

TEST_CASE("loadScene: the bundled default scene loads") {
    const SceneDescription d = tessera::parseSceneFile(kSourceDir / "scenes/default.json");
    tessera::Camera camera;
    const tessera::Scene s = tessera::loadScene(d, false, &camera);
    CHECK(s.lights.size() == d.explicitLights.size());
    CHECK(s.instances.size() >= 3);
    CHECK(camera.positionWorld == glm::vec3(0.0f, 2.2f, 7.5f));
    CHECK(camera.farZ == 100.0f);
}

TEST_CASE("generate kind amd-forwardplus11: the demo's lights over the scene's bounds, and its errors") {
    // The scene's bounds are the unit box scaled by 2 around x = 10 (the test above); the lights
    // must be exactly generateLightsAmdForwardPlus11 over those bounds (tests/scene/
    // amd_light_generator_test.cpp checks that generator against the demo's formulas), first 5
    // points then first 3 spots, after the 2 lights of a uniform generator.
    const std::string text = R"({
      "models": [{"path": "khronos/Box/glTF/Box.gltf", "translation": [10, 0, 0], "scale": 2}],
      "generate": [{"count": 2, "seed": 7},
                   {"kind": "amd-forwardplus11", "count": 5, "spotCount": 3},
                   {"kind": "amd-forwardplus11", "count": 1, "argumentOrder": "left-to-right",
                    "box": {"min": [-1, -1, -1], "max": [1, 1, 1]}}]
    })";
    const SceneDescription d = tessera::parseSceneJson(text, kSourceDir / "scenes/x.json");
    REQUIRE(d.generators.size() == 3);
    CHECK(d.generators[1].kind == tessera::LightGeneratorKind::AmdForwardPlus11);
    CHECK(d.generators[1].spotCount == 3);
    const tessera::Scene s = tessera::loadScene(d, false, nullptr);
    REQUIRE(s.lights.size() == 2 + 5 + 3 + 1);
    const std::vector<tessera::Light> expected = tessera::lightsFromAmdForwardPlus11(
        tessera::generateLightsAmdForwardPlus11(s.bounds(), tessera::kAmdForwardPlus11MaxLights), 5, 3);
    for (std::size_t i = 0; i < expected.size(); ++i) {
        CAPTURE(i);
        CHECK(s.lights[2 + i].type == expected[i].type);
        CHECK(s.lights[2 + i].positionWorld == expected[i].positionWorld);
        CHECK(s.lights[2 + i].range == expected[i].range);
        CHECK(s.lights[2 + i].color == expected[i].color);
        CHECK(s.lights[2 + i].directionWorld == expected[i].directionWorld);
    }
    CHECK(s.lights[2].type == LightType::Point);
    CHECK(s.lights[7].type == LightType::Spot);
    // The given box and the other argument order: x drawn last instead of first.
    tessera::Bounds box;
    box.minWorld = glm::vec3(-1.0f);
    box.maxWorld = glm::vec3(1.0f);
    const tessera::Light last = tessera::lightsFromAmdForwardPlus11(
        tessera::generateLightsAmdForwardPlus11(box, tessera::kAmdForwardPlus11MaxLights, tessera::CallArgumentOrder::LeftToRight), 1, 0)[0];
    CHECK(s.lights[10].positionWorld == last.positionWorld);

    expectError(scene(R"("generate": [{"kind": "amd"}])"), "/generate/0/kind", "unknown generator kind \"amd\"");
    expectError(scene(R"("generate": [{"kind": "amd-forwardplus11", "count": 2049}])"), "/generate/0/count", "2049 is outside 0..2048");
    expectError(scene(R"("generate": [{"kind": "amd-forwardplus11", "count": 1, "spotCount": 4096}])"), "/generate/0/spotCount",
                "4096 is outside 0..2048");
    expectError(scene(R"("generate": [{"kind": "amd-forwardplus11", "count": 1, "seed": 3}])"), "/generate/0/seed",
                "\"seed\" does not apply to kind amd-forwardplus11");
    expectError(scene(R"("generate": [{"count": 1, "spotCount": 3}])"), "/generate/0/spotCount",
                "applies to kind amd-forwardplus11 only");
    expectError(scene(R"("generate": [{"kind": "amd-forwardplus11", "count": 1, "argumentOrder": "msvc"}])"),
                "/generate/0/argumentOrder", "unknown argument order");
    expectError(scene(R"("generate": [{"kind": "amd-forwardplus11", "spotCount": 1}])"), "/generate/0", "count");
    // A count past 2048 set after parsing (the command line's --lights) is an error at load time.
    SceneDescription overridden = d;
    overridden.generators[1].count = 4096;
    try {
        (void)tessera::loadScene(overridden, false, nullptr);
        FAIL("no exception");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("/generate/1/count: 4096 point lights; AMD ForwardPlus11 has at most 2048") != std::string::npos);
    }
    // The total of every generator is checked again at load time, before any light is made.
    SceneDescription many = d;
    many.generators[0].count = 1000000;
    try {
        (void)tessera::loadScene(many, false, nullptr);
        FAIL("no exception");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("/generate/1/count: the generators make 1000") != std::string::npos);
    }
}

TEST_CASE("duplicate keys are refused with the JSON pointer of the repeated key") {
    expectError(scene(R"("technique": "forward", "technique": "deferred")"), "/technique", "duplicate key \"technique\"");
    expectError(scene(R"("camera": {"position": [0, 0, 0], "target": [0, 0, -1], "target": [1, 0, 0]})"), "/camera/target",
                "duplicate key");
    expectError(scene(R"("lights": [{"type": "point", "position": [0,0,0], "range": 1},
                                    {"type": "point", "position": [0,0,0], "range": 1, "range": 2}])"),
                "/lights/1/range", "duplicate key");
    // Inside "options", passed on verbatim, and after nested arrays (indices counted past them).
    expectError(scene(R"("options": {"a": [[1, 2], {"x": 1}, [3]], "b": [{"k": 1}, {"k": 2, "k": 3}]})"), "/options/b/1/k",
                "duplicate key");
    expectError(scene(R"("options": {"a/b~c": {"d": 1, "d": 2}})"), "/options/a~1b~0c/d", "duplicate key");
    // The same key in different objects is fine.
    const SceneDescription d = tessera::parseSceneJson(scene(R"("options": {"a": {"k": 1}, "b": {"k": 2}})"), kSceneFile);
    CHECK(d.techniqueOptions["b"]["k"] == 2);
}

TEST_CASE("JSON nested deeper than 256 levels is refused before it is parsed or copied") {
    // 10^6 levels in "options" overflowed the stack with SIGSEGV (the recursive copy of "options").
    constexpr std::size_t DEEP_LEVELS = 1000000;  // nested arrays
    const std::string deep = std::string(DEEP_LEVELS, '[') + std::string(DEEP_LEVELS, ']');
    const std::string text = scene(R"("options": {"x": )" + deep + "}");
    expectError(text, "", "JSON nested deeper than 256 levels (at byte " + std::to_string(text.find("[[") + 254) + ")");
    // Unbalanced and inside strings: still refused at the bracket, or not counted at all.
    expectError(std::string(300, '{'), "", "nested deeper than 256 levels");
    std::string nested = "1";
    for (int level = 0; level < 254; ++level) nested = "[" + nested + "]";  // root + options + 254 arrays = 256 levels
    const SceneDescription d = tessera::parseSceneJson(
        scene(R"("options": {"x": )" + nested + R"(, "s": "\"[[[[{{{{)" + std::string(1000, '[') + "\"}"), kSceneFile);
    CHECK(d.techniqueOptions["x"].is_array());
}

TEST_CASE("shadow casters and the indirect light: all, none, a list checked against the final light list") {
    const auto load = [](const std::string& extra) {
        const std::string text = R"({"models": [{"path": "khronos/Box/glTF/Box.gltf"}],
          "lights": [{"type": "point", "position": [0, 0, 0]},
                     {"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "indirect": true}],
          "generate": [{"count": 3, "seed": 1}])" + extra + "}";
        const SceneDescription d = tessera::parseSceneJson(text, kSourceDir / "scenes/x.json");
        return tessera::loadScene(d, false);
    };
    const tessera::Scene none = load("");
    REQUIRE(none.lights.size() == 5);
    for (const tessera::Light& l : none.lights) CHECK(!l.castsShadows);
    CHECK(none.lights[1].indirect);
    CHECK(!none.lights[0].indirect);
    const tessera::Scene all = load(R"(, "shadowCasters": "all")");
    for (const tessera::Light& l : all.lights) CHECK(l.castsShadows);  // generated lights too
    const tessera::Scene list = load(R"(, "shadowCasters": [4, 0])");
    CHECK(list.lights[0].castsShadows);
    CHECK(!list.lights[1].castsShadows);
    CHECK(list.lights[4].castsShadows);  // the last generated light: explicit 0..1, generated 2..4
    try {
        (void)load(R"(, "shadowCasters": [1, 5])");
        FAIL("no exception");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("/shadowCasters/1: light 5 does not exist (the scene has 5 lights") != std::string::npos);
    }
    expectError(scene(R"("shadowCasters": "some")"), "/shadowCasters", "is not \"all\", \"none\" or a list");
    expectError(scene(R"("shadowCasters": [-1])"), "/shadowCasters/0", "");
    expectError(scene(R"("lights": [{"type": "point", "position": [0, 0, 0], "indirect": true}])"), "/lights/0/indirect",
                "spot or directional");
    expectError(scene(R"("lights": [{"type": "directional", "direction": [0, -1, 0], "indirect": true},
                                    {"type": "directional", "direction": [0, -1, 0], "indirect": true}])"),
                "/lights/1/indirect", "only one light may be indirect");
}

TEST_CASE("near 0: an orthographic glTF camera takes it (glTF 2.0 §5.13 znear >= 0), a perspective one refuses it") {
    // The fuzz corpus file has a perspective camera (glTF camera 0, znear 0.1) and an
    // orthographic one (camera 1, "top", znear 0), each placed by a node of scene 0.
    const std::filesystem::path model = kSourceDir / "tests/fuzz/corpus/gltf/lights-cameras.gltf";
    const auto withCamera = [&](const std::string& camera) {
        return R"({"models": [{"path": ")" + model.generic_string() + R"("}], "camera": )" + camera + "}";
    };
    const SceneDescription probe = tessera::parseSceneJson(withCamera(R"({"gltf": 0})"), kSceneFile);
    tessera::Camera camera;
    const tessera::Scene s = tessera::loadScene(probe, false, &camera);
    int orthographic = -1, perspective = -1;
    for (std::size_t i = 0; i < s.cameras.size(); ++i)
        (s.cameras[i].projection == tessera::ProjectionKind::Orthographic ? orthographic : perspective) = int(i);
    REQUIRE(orthographic >= 0);
    REQUIRE(perspective >= 0);
    // The file's own znear 0, and a scene file's "near": 0 over it.
    for (const std::string& extra : {std::string(), std::string(R"(, "near": 0)")}) {
        CAPTURE(extra);
        const SceneDescription d = tessera::parseSceneJson(withCamera(R"({"gltf": )" + std::to_string(orthographic) + extra + "}"), kSceneFile);
        (void)tessera::loadScene(d, false, &camera);
        CHECK(camera.projection == tessera::ProjectionKind::Orthographic);
        CHECK(camera.nearZ == 0.0f);
    }
    // Over the perspective camera, "near": 0 is refused where the camera is resolved.
    const SceneDescription bad = tessera::parseSceneJson(withCamera(R"({"gltf": )" + std::to_string(perspective) + R"(, "near": 0})"), kSceneFile);
    try {
        (void)tessera::loadScene(bad, false, &camera);
        FAIL("near 0 over a perspective camera was accepted");
    } catch (const tessera::InputError& e) {
        CHECK(std::string(e.what()).find("/camera/near") != std::string::npos);
        CHECK(std::string(e.what()).find("only an orthographic camera may take near 0") != std::string::npos);
    }
}

} // namespace tessera_test::scene_scene_file_test
