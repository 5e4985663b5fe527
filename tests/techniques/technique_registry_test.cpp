// The technique registry as a test or an embedding program uses it: a technique registered at run
// time (here a made-up one that fills the back buffer with one grey level) is listed, built,
// optioned (its catalogue checked, unknown keys refused), captioned and estimated as the built-in
// ones are, without any change to the library, the command line or the benchmarks.
#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <tessera/errors/input_error.h>
#include <tessera/frame/buffer_registry.h>
#include <tessera/techniques/technique.h>

#include "support/grey_fill_technique.h"
#include "support/room_scene.h"

namespace tessera_test::techniques_technique_registry {

using namespace tessera;

namespace {

using test::kGreyFill;
using test::kGreyPasses;

TechniqueContext contextFor(const SceneResources& resources, Device& device, nlohmann::json options) {
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.width = 8;
    ctx.height = 4;
    ctx.options = std::move(options);
    return ctx;
}

} // namespace

TEST_CASE("technique registry: a technique registered at run time is listed, built, optioned, captioned and estimated") {
    const TechniqueInfo& info = test::registerGreyFill();
    int listed = 0;
    for (const TechniqueInfo& t : techniques()) listed += t.id == "test-grey-fill" ? 1 : 0;
    CHECK(listed == 1);
    CHECK(&requireTechnique("test-grey-fill", "memory.json") == &info);
    REQUIRE(findOption("test-grey-fill", "grey"));
    CHECK(techniqueOptions("test-grey-fill").size() == 1);

    const Scene scene = test::oneTriangle(-2.0f);
    const SceneResources resources(scene);
    Device device(DeviceConfig{64, 1});
    BufferRegistry registry;
    buildTechnique("test-grey-fill", contextFor(resources, device, {{"grey", 255}}), "memory.json").run(registry);
    CHECK(registry.get(kBackBufferName).load(7, 3) == glm::vec4(1.0f));

    // Keys outside its catalogue are refused by buildTechnique, naming the key; so is MSAA.
    try {
        buildTechnique("test-grey-fill", contextFor(resources, device, {{"gray", 255}}), "memory.json");
        FAIL("an unknown option key built");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("/options/gray") != std::string::npos);
    }
    TechniqueContext msaa = contextFor(resources, device, nlohmann::json::object());
    msaa.sampleCount = 4;
    CHECK_THROWS_AS(buildTechnique("test-grey-fill", msaa, "memory.json"), InputError);

    // Captions: its own pass from its row, "clear" from the shared ones, nothing for a pass it lacks.
    CHECK(passCaption(info, "fill") == kGreyPasses[0].text);
    CHECK(passCaption(info, "clear") == passCaption(*findTechnique("forward"), "clear"));
    CHECK(passCaption(info, "lights").empty());

    // The memory estimate runs its probe frames through the registry too: one RGBA8 target, 4 B a pixel.
    const FrameMemoryEstimate e = estimateFrameMemory("test-grey-fill", contextFor(resources, device, nlohmann::json::object()),
                                                      "memory.json");
    CHECK(e.bytesPerPixel == doctest::Approx(4.0));
}

TEST_CASE("technique registry: a registration without an id or a build function, or with a taken id, is refused") {
    test::registerGreyFill();
    CHECK_THROWS_AS(registerTechnique(kGreyFill), std::invalid_argument);  // taken
    TechniqueInfo noId = kGreyFill;
    noId.id = "";
    CHECK_THROWS_AS(registerTechnique(noId), std::invalid_argument);
    TechniqueInfo noBuild = kGreyFill;
    noBuild.id = "test-no-build";
    noBuild.build = nullptr;
    CHECK_THROWS_AS(registerTechnique(noBuild), std::invalid_argument);
    CHECK(!findTechnique("test-no-build"));
    TechniqueInfo forward = *findTechnique("forward");
    CHECK_THROWS_AS(registerTechnique(forward), std::invalid_argument);  // a built-in id
}

// The sweep (bench/sweep.py) takes its techniques and option sets from the registry's JSON: the
// made-up technique, saved with the built-in ones as `tessera options --json` prints them, is swept
// with its defaults and (--full) each other listed value of its option, with no edit to bench/.
TEST_CASE("technique registry: a technique registered at run time is swept by bench/sweep.py") {
    (void)test::registerGreyFill();
    const nlohmann::json json = techniqueRegistryJson();
    const nlohmann::json* mine = nullptr;
    for (const nlohmann::json& t : json)
        if (t["id"] == "test-grey-fill") mine = &t;
    REQUIRE(mine != nullptr);
    CHECK((*mine)["passes"]["fill"] == "Writes one grey level over the back buffer (a test's technique).");
    CHECK((*mine)["options"][0]["values"] == nlohmann::json::array({"128", "0", "255"}));
    const std::filesystem::path file = std::filesystem::path(TESSERA_TEST_OUTPUT_DIR) / "registry-with-test-technique.json";
    std::ofstream(file) << json.dump(1);
    const std::string command = "python3 " + std::string(TESSERA_SOURCE_DIR) + "/bench/sweep.py --registry " + file.string() +
                                " --scenes default --precisions exact --full --print-cells 2>&1";
    std::string output;
    if (FILE* pipe = popen(command.c_str(), "r")) {
        char buffer[4096];
        while (const std::size_t n = std::fread(buffer, 1, sizeof(buffer), pipe)) output.append(buffer, n);
        CHECK(pclose(pipe) == 0);
    }
    INFO(output);
    // Cell ids: scene.technique.knobs.lights.size.threads.precision (the default scene has its own lights).
    for (const char* cell : {"default.test-grey-fill.defaults.Lscene.320x180.t0.exact\n",
                             "default.test-grey-fill.grey=0.Lscene.320x180.t0.exact\n",
                             "default.test-grey-fill.grey=255.Lscene.320x180.t0.exact\n",
                             "default.forward.defaults.Lscene.320x180.t0.exact\n"})
        CHECK_MESSAGE(output.find(cell) != std::string::npos, cell);
}

} // namespace tessera_test::techniques_technique_registry
