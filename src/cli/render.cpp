// `tessera render [SCENE]`: loads a scene (a scene file, a glTF file, a bundled scene's name or
// `builtin`), renders it with its technique (or --technique) and writes the back buffer; with
// --dump every buffer, with --probe a pixel's history, with --stats times and counters. The flags
// and output paths are checked before anything loads, the memory before anything large is
// allocated, and a render that fails leaves no file behind.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <tbb/task_arena.h>

#include <glm/gtc/matrix_transform.hpp>

#include <tessera/frame/memory_limit.h>
#include <tessera/scene/camera.h>
#include <tessera/scene/default_lights.h>
#include <tessera/scene/depth_precision.h>
#include <tessera/scene/scene_file.h>
#include <tessera/scene/scene_resources.h>
#include <tessera/techniques/builtin_scene.h>
#include <tessera/techniques/technique.h>

#include "commands.h"
#include "dump_staging.h"
#include "frame_runs.h"
#include "memory_check.h"
#include "output_check.h"
#include "progress.h"
#include "render_args.h"
#include "render_output.h"
#include "scene_args.h"

namespace tessera::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kRenderUsage = R"(usage: tessera render [SCENE] [options]

Renders SCENE (default: the bundled scene 'default') with its technique and writes the back
buffer: PNG stores the 8-bit bytes as rendered, EXR the decoded values (half or float).

options:
  --technique ID    technique to use instead of the scene file's (see `tessera list`)
  --option KEY=VALUE  a technique option, over the scene file's (repeatable; VALUE is JSON, or a
                    bare word taken as a string: --option coneTest=corrected --option tileSize=32);
                    checked against the technique before anything loads (see `tessera options`)
  -o, --out FILE    output image, .png or .exr (default: tessera.png): the back buffer as stored, alpha
                    included (as the goldens and --dump keep it); with --precision reference the double
                    result (PNG: rounded once to 8 bits, EXR: its float values)
  --exr TYPE        EXR pixel type: half or float (default: float)
  --width W         width in px, 1..16384 (default: the scene file's)
  --height H        height in px, 1..16384 (default: the scene file's)
  --precision MODE  reference, exact or fast (default: the scene file's, else exact)
  --orbit AZ,EL      the camera on a sphere around the scene's bounds looking at their centre, far
                    enough for the bounds to fit the view: AZ degrees about +Y from +Z towards +X, EL
                    degrees up from the horizontal (-89..89)
  --camera-position X,Y,Z  the eye, world units; with --camera-target the camera a scene file's
                    {"position", "target"} makes (+Y up), alone it looks at the scene's bounds' centre
  --camera-target X,Y,Z    the point looked at (alone: from the scene's camera position)
  --fov DEG         vertical field of view over the scene's camera, 0..180 exclusive
  --lights N        light count of every generator in the scene file, 0..1000000 (all of them
                    together at most 1000000)
  --memory-limit G  refuse, before allocating, a render whose scene and frame buffers would need more
                    than G GiB (default: 3/4 of the memory this process may use: the least of physical
                    memory, the cgroup's memory.max and RLIMIT_AS); exit code 2, nothing written
  --threads N       worker threads, 0 = all cores (default 0)
  --tile T          tile size in px, even, 8..1024 (default 64)
  --scalar-raster   rasterize every quad on the scalar path instead of 8x8 SIMD blocks (the same
                    bytes; for comparing speed, and as the oracle the tests hold the SIMD path to)
  --draw-by-draw    run every draw on its own (setup, tiles, barrier) instead of binning a pass's
                    draws into shared tile lists (the same bytes; for comparing speed and scaling);
                    the default with --threads 1, where binning saves no barrier and costs cache
  --binned          bin a pass's draws even with --threads 1 (the same bytes; for measuring)
  --msaa S          samples per pixel, 1, 2, 4 or 8 (default 1); techniques without MSAA refuse more
  --dump DIR        also write every named buffer into DIR (<name>.png/.exr/.tif, stencil as <name>.stencil.png),
                    a viewable picture of each in DIR/view/ (depth stretched, stencil and integers through
                    palettes with a colour bar) and DIR/manifest.json (passes, buffers, formats, decode rules,
                    camera, options, command line)
  --dump-after PASS[,PASS]  with --dump: also the buffers as they stand after each named pass, in
                    DIR/after-<PASS>/ (the pass names are `pass` lines of --stats); `all`: every pass
  --dump-lights I[,J]  with --dump, deferred and deferred-killzone: also the buffers after each step of
                    light I (scene order, from 0): DIR/light-I-unmark/ and DIR/light-I-shade/ (Killzone:
                    -mark, -count, -shade), so the stencil can be watched being marked and cleared;
                    `A-B`: the lights from A to B the scene has, `all`: every light (both: nothing, not
                    an error, for techniques without light steps)
  --exposure E      scale of float colour buffers in DIR/view/ (default 1)
  --probe X,Y       print the history of window pixel (X, Y): each primitive that covered it (draw,
                    coverage, depth test, shader output, texels before/after), every buffer's value
                    there after each pass and light step where it changed, and for the tiled
                    techniques the pixel's tile, depth range, frustum planes and light list
  --json            with --probe: the history as one JSON object
  --repeat N        render the frame N times after loading once, 1..100000 (default 1); --stats then
                    prints each pass's and the frame's median over the N runs; the last run is written
  --warmup K        render K untimed frames before the N timed ones, 0..100000 (default 0)
  --no-output       render but write no file (timing and --stats only); not with --out or --dump
  --no-default-lights  a scene without any light stays unlit under a lighting technique (by default
                    it gets a key and a fill point light from the camera, announced on stderr)
  --double-sided-normals reverse|keep  back faces of double-sided glTF materials: lit with the normal
                    and tangent frame reversed, as glTF 2.0 §3.9.5 requires (reverse, default), or with
                    the front face's normal (keep: such back faces come out unlit, for comparison)
  --generated-bitangent up|down  tangents generated for glTF primitives without TANGENT: bitangent
                    up the image, as glTF 2.0 §3.9.3 reads normal textures (up, default), or down it
                    (tessera's generator before ERRATA #33, which read a normal map's green channel
                    inverted; for comparison)
  --stats           print load, per-pass and frame times, draw counters, the draw paths taken, the
                    frame's buffers by why they exist (read later, image, inspection), peak memory
                    (peak RSS) and the FNV-1a 64 hash of each written file
  --progress        show a progress bar even when stderr is not a terminal
  --quiet           print nothing on success (no progress bar, no warnings or note about what the
                    technique skipped or clamped; --dump's manifest.json keeps them under "notes")
  --help            show this text
)";

void warn(const std::string& text) { std::fprintf(stderr, "tessera: warning: %s\n", text.c_str()); }

// Output paths checked before anything loads or renders (output_check.h): --out's folder takes a
// new file, --dump is a folder or can become one. A render that would fail at its end fails now.
void checkOutputPaths(const RenderOptions& o) {
    if (o.noOutput) return;
    requireOutputFile("--out", o.out);
    if (!o.dumpDir.empty()) requireOutputFolder("--dump", o.dumpDir);
}

// The back buffer's pixels saturated to white (R = G = B = 255 in an 8-bit back buffer; every
// sample with MSAA resolved): light past what the sources' 8-bit target holds, clipped.
std::uint64_t saturatedPixels(const tessera::BufferRegistry& registry) {
    const tessera::Surface* back = registry.find(tessera::kBackBufferName);
    if (!back || (back->format() != tessera::Format::R8G8B8A8_UNORM && back->format() != tessera::Format::R8G8B8A8_UNORM_SRGB)) return 0;
    std::uint64_t n = 0;
    for (std::uint32_t y = 0; y < back->height(); ++y)
        for (std::uint32_t x = 0; x < back->width(); ++x) {
            const std::byte* t = back->texel(x, y);
            n += (t[0] == std::byte{255} && t[1] == std::byte{255} && t[2] == std::byte{255}) ? 1u : 0u;
        }
    return n;
}

// The faithful choices (option_catalog.h) not already named by a frame note's erratum, as
// "key=value (#N)", with the remedy "--option key=corrected".
void faithfulChoiceNotes(const std::string& technique, const nlohmann::json& options, const std::vector<int>& named,
                         std::vector<std::string>& labels, std::vector<std::string>& remedies) {
    for (const tessera::FaithfulChoice& c : tessera::faithfulChoices(tessera::techniqueOptions(technique), options)) {
        const tessera::OptionInfo& opt = *c.option;
        if (std::find(named.begin(), named.end(), opt.erratum) != named.end()) continue;
        labels.push_back(std::string(opt.key) + "=" + c.value + " (#" + std::to_string(opt.erratum) + ")");
        remedies.push_back("--option " + std::string(opt.key) + "=" + std::string(opt.corrected));
    }
}

// The frame's notes (frame/frame_notes.h) on stderr: one warning per kind a technique skipped or
// clamped, with the count, the ERRATA.md row and what changes it; then one note naming what
// visibly changes this image (the visible kinds, and pixels saturated to white), the faithful
// choices still in effect that an erratum's correction changes (the option table's), and the
// options that correct them. Nothing about the technique is compared here: the records say it all.
void printFrameNotes(const std::string& technique, const nlohmann::json& options, const tessera::FrameNotes& notes,
                     const tessera::BufferRegistry& registry) {
    std::vector<std::string> visible, remedies;
    std::vector<int> named;
    for (const tessera::FrameNote& n : notes.list()) {
        if (n.erratum) named.push_back(n.erratum);
        warn(technique + ": " + tessera::noteText(n));
        if (!n.visible) continue;
        const std::size_t cut = n.what.find_first_of(":(");
        std::string label = std::to_string(n.count) + " " + (cut == std::string::npos ? n.what : n.what.substr(0, cut));
        while (!label.empty() && label.back() == ' ') label.pop_back();
        if (n.erratum) label += " (#" + std::to_string(n.erratum) + ")";
        visible.push_back(label);
        if (!n.remedy.empty() && std::find(remedies.begin(), remedies.end(), n.remedy) == remedies.end()) remedies.push_back(n.remedy);
    }
    if (const std::uint64_t saturated = saturatedPixels(registry))
        visible.push_back(std::to_string(saturated) + " pixels saturated to white (light past the 8-bit back buffer's 1.0, clipped; "
                                                      "the sources have no tone mapping)");
    std::vector<std::string> faithful;
    faithfulChoiceNotes(technique, options, named, faithful, remedies);
    if (visible.empty() && faithful.empty()) return;
    std::string text;
    if (!visible.empty()) {
        text = "what changes this image visibly: ";
        for (std::size_t i = 0; i < visible.size(); ++i) text += (i ? "; " : "") + visible[i];
    }
    if (!faithful.empty()) {
        text += text.empty() ? "faithful" : ". Faithful";
        text += " to the source, each of which may change it (tessera report measures how much): ";
        for (std::size_t i = 0; i < faithful.size(); ++i) text += (i ? ", " : "") + faithful[i];
    }
    if (!remedies.empty()) {
        text += ". Corrected:";
        for (const std::string& r : remedies) text += " " + r;
    }
    std::fprintf(stderr, "tessera: note: %s (ERRATA.md, README \"Warnings\")\n", text.c_str());
}

// "deferred and deferred-killzone": the techniques that declare `feature` (TechniqueInfo::features).
std::string techniquesWith(std::uint32_t feature) {
    std::vector<std::string> ids;
    for (const tessera::TechniqueInfo& t : tessera::techniques())
        if (t.features & feature) ids.emplace_back(t.id);
    std::string text;
    for (std::size_t i = 0; i < ids.size(); ++i) text += (i == 0 ? "" : i + 1 == ids.size() ? " and " : ", ") + ids[i];
    return text;
}

// The scene a render draws: the file, its description with the command line laid over it, the
// loaded scene and camera, the technique's declared features and the load time.
struct LoadedScene {
    fs::path file;
    tessera::SceneDescription desc;
    tessera::Camera camera;
    tessera::Scene scene;
    std::uint32_t features = 0;
    double loadMs = 0.0;
};

// The scene file's description with the command line laid over it (--technique and its
// --option values, size, precision, light counts), checked before anything loads: an unknown or
// unimplemented technique, MSAA it cannot do, --dump-lights it cannot step.
// --fov, and --camera-position with --camera-target, laid over the scene's camera before it loads:
// the look-at camera a scene file's {"position", "target"} gives (same function, same bits), its
// fovYDeg, near and far as the file has them. A position or target alone needs the loaded
// scene (aimCameraArgs).
void applyCameraArgs(const RenderOptions& o, tessera::SceneDescription& desc, const fs::path& sceneFile) {
    if (o.fovDeg) {
        if (desc.cameraSource == tessera::CameraSource::Explicit && desc.camera.projection != tessera::ProjectionKind::Perspective)
            throw UsageError("--fov: " + sceneFile.string() + "'s camera is orthographic");
        desc.cameraFovYDeg = *o.fovDeg;
        if (desc.cameraSource == tessera::CameraSource::Explicit) desc.camera.fovYDeg = *o.fovDeg;
    }
    if (!(o.cameraPosition && o.cameraTarget)) return;
    const tessera::LookAt look = tessera::lookAtOrientation(*o.cameraPosition, *o.cameraTarget, glm::vec3(0.0f, 1.0f, 0.0f));
    if (look.problem != tessera::LookAt::Problem::None) throw UsageError(std::string("--camera-target: ") + look.why());
    tessera::Camera camera;
    camera.name = "command line";
    camera.positionWorld = *o.cameraPosition;
    camera.orientationWorld = look.orientationWorld;
    if (desc.cameraFovYDeg) camera.fovYDeg = *desc.cameraFovYDeg;
    if (desc.cameraNearZ) camera.nearZ = *desc.cameraNearZ;
    if (desc.cameraFarZ) camera.farZ = *desc.cameraFarZ;
    desc.camera = camera;
    desc.cameraSource = tessera::CameraSource::Explicit;
}

// A --camera-position or --camera-target given alone, over the loaded camera: a position looks at
// the scene's bounds' centre, a target is looked at from the camera's own position.
void aimCameraArgs(const RenderOptions& o, const tessera::Scene& scene, tessera::Camera& camera) {
    if (o.orbitDeg) {
        // On the sphere around the bounds' centre at the distance where the bounding sphere fills
        // the vertical field of view with 10% to spare: azimuth about +Y from +Z towards +X,
        // elevation up from the horizontal plane.
        constexpr float kSpare = 1.1f;
        const tessera::Bounds bounds = scene.bounds();
        if (bounds.empty()) throw UsageError("--orbit: the scene is empty, nothing to orbit");
        const glm::vec3 centre = (bounds.minWorld + bounds.maxWorld) * 0.5f;
        const float radius = std::max(glm::length(bounds.maxWorld - bounds.minWorld) * 0.5f, 1.0e-6f);
        const float distance = kSpare * radius / std::sin(glm::radians(camera.fovYDeg) * 0.5f);
        const float az = glm::radians(o.orbitDeg->x), el = glm::radians(o.orbitDeg->y);
        const glm::vec3 direction(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
        const tessera::LookAt look = tessera::lookAtOrientation(centre + direction * distance, centre, glm::vec3(0.0f, 1.0f, 0.0f));
        if (look.problem != tessera::LookAt::Problem::None) throw UsageError(std::string("--orbit: ") + look.why());
        camera.positionWorld = centre + direction * distance;
        camera.orientationWorld = look.orientationWorld;
        camera.farZ = std::max(camera.farZ, distance + 2.0f * radius);
        return;
    }
    if (o.cameraPosition.has_value() == o.cameraTarget.has_value()) return;  // both: applyCameraArgs; none
    const tessera::Bounds bounds = scene.bounds();
    const glm::vec3 position = o.cameraPosition.value_or(camera.positionWorld);
    const glm::vec3 target = o.cameraTarget ? *o.cameraTarget : (bounds.minWorld + bounds.maxWorld) * 0.5f;
    if (!o.cameraTarget && bounds.empty()) throw UsageError("--camera-position: the scene is empty, nothing to look at (give --camera-target)");
    const tessera::LookAt look = tessera::lookAtOrientation(position, target, glm::vec3(0.0f, 1.0f, 0.0f));
    if (look.problem != tessera::LookAt::Problem::None)
        throw UsageError(std::string(o.cameraTarget ? "--camera-target: " : "--camera-position: ") + look.why() +
                         (o.cameraTarget ? "" : " (the scene's bounds' centre)"));
    camera.positionWorld = position;
    camera.orientationWorld = look.orientationWorld;
}

// Each light's reach on screen, for pictures drawn over the image (tessera serve): the window-px
// rectangle [x0, y0, x1, y1] bounding its range sphere (a spot's cone lies inside it), through the
// camera's D3D projection (glm perspectiveRH_ZO / orthoRH_ZO); null where the sphere crosses the
// near plane or the light has no range (it may cover the whole screen), empty ([0, 0, 0, 0]) when
// it lies off screen. Display only: no technique reads it.
nlohmann::json lightExtents(const tessera::Scene& scene, const tessera::Camera& camera, std::uint32_t width, std::uint32_t height) {
    const float aspect = camera.aspect > 0.0f ? camera.aspect : float(width) / float(height);
    const float farZ = std::isfinite(camera.farZ) ? camera.farZ : camera.nearZ * 1.0e6f;
    const glm::mat4 clipFromView = camera.projection == tessera::ProjectionKind::Perspective
                                       ? glm::perspectiveRH_ZO(glm::radians(camera.fovYDeg), aspect, camera.nearZ, farZ)
                                       : glm::orthoRH_ZO(-camera.xMag, camera.xMag, -camera.yMag, camera.yMag, camera.nearZ, farZ);
    const glm::mat4 viewFromWorld = camera.viewFromWorld();
    nlohmann::json out = nlohmann::json::array();
    for (std::size_t i = 0; i < scene.lights.size(); ++i) {
        const tessera::Light& l = scene.lights[i];
        nlohmann::json e{{"light", i}, {"name", l.name}, {"type", std::string(l.type == tessera::LightType::Point ? "point"
                                                                             : l.type == tessera::LightType::Spot ? "spot"
                                                                             : l.type == tessera::LightType::Directional ? "directional" : "capsule")},
                         {"rectWindow", nullptr}};
        const float r = l.range + (l.type == tessera::LightType::Capsule ? l.length : 0.0f);
        if (l.type != tessera::LightType::Directional && std::isfinite(r)) {
            const glm::vec3 centreView = glm::vec3(viewFromWorld * glm::vec4(l.positionWorld, 1.0f));
            if (centreView.z + r < -camera.nearZ) {  // the sphere's view-space box lies beyond the near plane
                float x0 = float(width), y0 = float(height), x1 = 0.0f, y1 = 0.0f;
                for (int corner = 0; corner < 8; ++corner) {
                    const glm::vec3 p = centreView + glm::vec3(corner & 1 ? r : -r, corner & 2 ? r : -r, corner & 4 ? r : -r);
                    const glm::vec4 clip = clipFromView * glm::vec4(p, 1.0f);
                    const float x = (clip.x / clip.w * 0.5f + 0.5f) * float(width), y = (0.5f - clip.y / clip.w * 0.5f) * float(height);
                    x0 = std::min(x0, x);
                    x1 = std::max(x1, x);
                    y0 = std::min(y0, y);
                    y1 = std::max(y1, y);
                }
                x0 = std::clamp(x0, 0.0f, float(width));
                x1 = std::clamp(x1, 0.0f, float(width));
                y0 = std::clamp(y0, 0.0f, float(height));
                y1 = std::clamp(y1, 0.0f, float(height));
                e["rectWindow"] = x1 > x0 && y1 > y0 ? nlohmann::json{x0, y0, x1, y1} : nlohmann::json{0, 0, 0, 0};
            }
        }
        out.push_back(e);
    }
    return out;
}

tessera::SceneDescription describeForRender(RenderOptions& o, const fs::path& sceneFile) {
    tessera::SceneDescription desc = describe(sceneFile);
    if (!o.technique.empty() && o.technique != desc.technique) {
        // A scene file's "options" belong to its own technique.
        if (desc.techniqueOptions.is_object() && !desc.techniqueOptions.empty())
            warn(sceneFile.string() + "'s options are " + desc.technique + "'s; --technique " + o.technique +
                 " renders without them");
        desc.techniqueOptions = nlohmann::json::object();
        desc.technique = o.technique;
    }
    // The scene file's technique (--technique was checked with the flags): unknown is exit 2 naming the file.
    (void)tessera::requireTechnique(desc.technique, sceneFile.string());
    applyOptionArgs(o, desc.technique, desc.techniqueOptions);
    if (const tessera::TechniqueInfo* info = tessera::findTechnique(desc.technique); info && info->build && o.msaa > 1 && !info->msaa) {
        std::string ready;
        for (const tessera::TechniqueInfo& t : tessera::techniques())
            if (t.msaa) ready += (ready.empty() ? "" : ", ") + std::string(t.id);
        throw UsageError("--msaa: technique " + desc.technique + " does not render with MSAA yet (MSAA: " + ready + ")");
    }
    o.viewTileSize = lightGridTileSize(desc);
    if (!o.dumpLights.empty() && !(tessera::findTechnique(desc.technique)->features & tessera::kPerLightSteps))
        throw UsageError("--dump-lights: " + desc.technique + " does not shade light by light (" +
                         techniquesWith(tessera::kPerLightSteps) + " do); --dump-after shows its passes");
    if (o.width) desc.width = o.width;
    if (o.height) desc.height = o.height;
    applyCameraArgs(o, desc, sceneFile);
    if (o.precision) desc.precision = *o.precision;
    desc.generatedBitangentUp = o.generatedBitangentUp;
    if (o.lights) {
        if (desc.generators.empty())
            warn("--lights: " + sceneFile.string() + " has no light generators; the flag changes nothing");
        for (auto& g : desc.generators) g.count = *o.lights;
    }
    if (!tessera::findTechnique(desc.technique) || !tessera::findTechnique(desc.technique)->build) {
        tessera::TechniqueContext probe;  // reports unknown / unimplemented with the key path
        (void)tessera::buildTechnique(desc.technique, probe, sceneFile.string());
    }
    return desc;
}

// Warnings for lights the technique does not honour (capsule lights, light groups, shadow
// casters and indirect lights), each naming the techniques that do. forward-plus-amd notes what
// its "auto" options leave out itself (frame notes, printed after the render).
void warnUnhonouredLights(const fs::path& sceneFile, const tessera::SceneDescription& desc, const tessera::Scene& scene,
                          std::uint32_t features) {
    // Capsule lights are the Cookbook's: every other technique skips them (viewLights disables them).
    if (!(features & tessera::kShadesCapsuleLights)) {
        const auto capsules = std::count_if(scene.lights.begin(), scene.lights.end(),
                                            [](const tessera::Light& l) { return l.type == tessera::LightType::Capsule; });
        if (capsules > 0)
            warn(sceneFile.string() + " has " + std::to_string(capsules) + " capsule light(s); " + desc.technique +
                 " does not shade capsule lights (" + techniquesWith(tessera::kShadesCapsuleLights) + " does), so they are skipped");
    }
    // Light groups are PR&C's stencil groups: deferred-classic and light-prepass honour them.
    if (!(features & tessera::kHonoursLightGroups)) {
        if (scene.usesLightGroups())
            warn(sceneFile.string() + " uses lightGroups; " + desc.technique +
                 " lights every surface with every light (" + techniquesWith(tessera::kHonoursLightGroups) + " honour the groups)");
    }
    // Ray-cast shadows and VPLs are GPU Pro 4's Forward+ extensions: forward-plus-amd alone.
    if (!(features & tessera::kShadowRaysAndVpls)) {
        const bool casters = std::any_of(scene.lights.begin(), scene.lights.end(), [](const tessera::Light& l) { return l.castsShadows; });
        const bool indirect = std::any_of(scene.lights.begin(), scene.lights.end(), [](const tessera::Light& l) { return l.indirect; });
        if (casters || indirect)
            warn(sceneFile.string() + " marks " + (casters ? "shadow-casting" : "") + (casters && indirect ? " and " : "") +
                 (indirect ? "indirect" : "") + " lights; " + desc.technique +
                 " has no ray-cast shadows or VPLs (" + techniquesWith(tessera::kShadowRaysAndVpls) + " does), so they light as plain lights");
    }
}

// The scene a render draws: described (describeForRender), loaded with its images, lit by the
// default rig when it has no light and the technique needs one, and warned about.
LoadedScene loadForRender(RenderOptions& o, Progress& progress) {
    // Loading: bad input is exit 2 (InputError); everything else that fails is exit 1.
    const auto t0 = Clock::now();
    LoadedScene s;
    s.file = resolveScene(o.scene);
    s.desc = describeForRender(o, s.file);
    const fs::path& sceneFile = s.file;
    const tessera::SceneDescription& desc = s.desc;
    progress.update("loading " + sceneFile.filename().string(), 0, 0);
    s.scene = tessera::loadScene(desc, true, &s.camera);
    tessera::Scene& scene = s.scene;
    aimCameraArgs(o, scene, s.camera);
    const tessera::Camera& camera = s.camera;
    if (o.generatedBitangentGiven) {
        // Generated tangents change a render only where a normal texture reads them.
        const auto readsGenerated = [&scene](const tessera::MeshPrimitive& p) {
            return p.tangentsGenerated && p.material >= 0 && scene.materials[std::size_t(p.material)].normalTexture.present();
        };
        const bool anyRead = std::any_of(scene.meshes.begin(), scene.meshes.end(), [&](const tessera::Mesh& m) {
            return std::any_of(m.primitives.begin(), m.primitives.end(), readsGenerated);
        });
        if (!anyRead)
            warn("--generated-bitangent: " + sceneFile.string() +
                 " has no normal-mapped primitive without TANGENT; the flag changes nothing");
    }
    if (o.keepBackFaceNormals) {
        const bool anyDoubleSided = std::any_of(scene.materials.begin(), scene.materials.end(),
                                                [](const tessera::Material& m) { return m.doubleSided; });
        if (!anyDoubleSided) warn("--double-sided-normals: " + sceneFile.string() + " has no double-sided material; the flag changes nothing");
        for (tessera::Material& m : scene.materials) m.reverseBackFaceNormals = false;
    }
    // A scene with no lights at all gets the default rig under a lighting technique (preview has
    // its own head light), announced, unless --no-default-lights.
    s.features = tessera::findTechnique(desc.technique)->features;
    const std::uint32_t features = s.features;
    if (scene.lights.empty() && !(features & tessera::kOwnHeadLight) && !o.noDefaultLights) {
        scene.lights = tessera::defaultLightRig(scene.bounds(), camera);
        if (!scene.lights.empty() && !o.quiet)
            std::fprintf(stderr, "tessera: note: %s has no lights; shading with the default rig (a key and a fill point "
                                 "light from the camera, README \"Scenes\"); --no-default-lights turns it off\n",
                         sceneFile.string().c_str());
    }
    if (const auto depth = tessera::depthPrecisionWarning(camera, scene.bounds())) warn(sceneFile.string() + ": " + *depth);
    // COLOR_0 is loaded but no shader applies it (README "glTF conformance"): a primitive whose
    // vertex colours are not all white renders differently from a glTF viewer's, so say so.
    std::size_t coloured = 0;
    for (const tessera::Mesh& mesh : scene.meshes)
        for (const tessera::MeshPrimitive& prim : mesh.primitives)
            coloured += std::any_of(prim.colors0.begin(), prim.colors0.end(), [](const glm::vec4& c) { return c != glm::vec4(1.0f); })
                            ? 1u
                            : 0u;
    if (coloured > 0)
        warn(sceneFile.string() + ": " + std::to_string(coloured) + " primitive(s) carry COLOR_0 vertex colours, which tessera does "
             "not apply (the 3dgep material has none; README \"glTF conformance\"): they render with the base colour alone");
    if (scene.gltfLightsNotUsed > 0 && !(features & tessera::kOwnHeadLight))
        warn(sceneFile.string() + ": its glTF files place " + std::to_string(scene.gltfLightsNotUsed) +
             " KHR_lights_punctual light(s), which this scene file leaves out; \"gltfLights\": {\"enabled\": true} uses them");
    warnUnhonouredLights(sceneFile, desc, scene, features);
    s.loadMs = msSince(t0);
    return s;
}

// --dump's manifest.json for a scene render: manifestBase's passes and buffers, then the scene,
// technique, precision, size, options, the frame notes and the camera.
nlohmann::json sceneManifest(const tessera::Frame& frame, const FrameRuns& runs, const RenderOptions& o, const LoadedScene& loaded,
                             const tessera::FrameNotes& notes, const nlohmann::json& lightSteps) {
    const fs::path& sceneFile = loaded.file;
    const tessera::SceneDescription& desc = loaded.desc;
    const tessera::Scene& scene = loaded.scene;
    const tessera::Camera& camera = loaded.camera;
    nlohmann::json manifest = manifestBase(frame, runs, o);
    manifest["scene"] = sceneFile.string();
    manifest["technique"] = desc.technique;
    manifest["precision"] = std::string(tessera::precisionName(desc.precision));
    manifest["width"] = desc.width;
    manifest["height"] = desc.height;
    manifest["msaa"] = o.msaa;
    manifest["options"] = desc.techniqueOptions.is_null() ? nlohmann::json::object() : desc.techniqueOptions;
    manifest["lights"] = scene.lights.size();
    manifest["lightExtents"] = lightExtents(scene, camera, desc.width, desc.height);
    nlohmann::json noteList = nlohmann::json::array();
    for (const tessera::FrameNote& n : notes.list())
        noteList.push_back({{"kind", n.kind}, {"count", n.count}, {"what", n.what}, {"erratum", n.erratum},
                            {"remedy", n.remedy}, {"visible", n.visible}});
    manifest["notes"] = noteList;
    const glm::quat& q = camera.orientationWorld;
    manifest["camera"] = {{"positionWorld", {camera.positionWorld.x, camera.positionWorld.y, camera.positionWorld.z}},
                          {"orientationWorld", {q.x, q.y, q.z, q.w}},
                          {"projection", camera.projection == tessera::ProjectionKind::Perspective ? "perspective" : "orthographic"},
                          {"fovYDeg", camera.fovYDeg},
                          {"near", camera.nearZ},
                          {"far", camera.farZ}};
    if (!o.dumpLights.empty()) manifest["lightSteps"] = lightSteps;
    return manifest;
}

// --stats for a scene render: the scene line, load and texture times, pass and frame times, draw
// and shadow counters, peak memory, the shader variants drawn and the written files' hashes.
void printSceneStats(const LoadedScene& loaded, const tessera::SceneResources& resources, double texturesMs, const FrameRuns& runs,
                     const RenderOptions& o, const tessera::DrawStats& drawStats, const tessera::Frame& frame,
                     const tessera::BufferRegistry& registry,
                     const std::map<std::string, std::uint64_t>& variantCounts, const std::vector<WrittenFile>& written,
                     const DumpStaging* staging) {
    const fs::path& sceneFile = loaded.file;
    const tessera::SceneDescription& desc = loaded.desc;
    const tessera::Scene& scene = loaded.scene;
    const double loadMs = loaded.loadMs;
        std::printf("scene %s: %llu triangles, %zu draws, %zu lights, technique %s, precision %s, %ux%u\n",
                    sceneFile.string().c_str(), (unsigned long long)scene.triangleCount(), resources.drawItems().size(),
                    scene.lights.size(), desc.technique.c_str(), std::string(tessera::precisionName(desc.precision)).c_str(),
                    desc.width, desc.height);
        std::printf("load     %9.3f ms (glTF, images, lights)\n", loadMs);
        std::printf("textures %9.3f ms (%zu textures with mips, %.1f MiB)\n", texturesMs, resources.textureCount(),
                    double(resources.textureBytes()) / (1024.0 * 1024.0));
        printTimings(runs, o, true);
        printDrawStats(drawStats);
        printShadowStats(registry);
        printBufferStats(frame, registry, inspects(o));
        printPeakMemory();
        for (const auto& [variant, draws] : variantCounts)
            std::printf("variant  %-40s %6llu draws\n", variant.c_str(), (unsigned long long)draws);
        printHashes(written, staging);
}

// A scene file (or glTF, or bundled name) rendered: loaded, its textures decoded within the
// memory limit, the frame built (refused before allocating past the limit), run, written and
// reported. `staging` holds --dump's folder until everything succeeded.
int renderScene(RenderOptions& o, DumpStaging& staging) {
    tessera::cli::Progress progress(o.progress);
    LoadedScene loaded = loadForRender(o, progress);
    const fs::path& sceneFile = loaded.file;
    const tessera::SceneDescription& desc = loaded.desc;
    const tessera::Scene& scene = loaded.scene;
    const tessera::Camera& camera = loaded.camera;
    // Textures are decoded next: refuse now if they (and the mip filter's rows) cannot fit.
    const SceneBytes bytes = sceneBytes(scene);
    const tessera::TextureMemoryEstimate textures = tessera::SceneResources::estimateTextureMemory(
        scene, tessera::findTechnique(desc.technique)->textures, std::size_t(tbb::this_task_arena::max_concurrency()));
    checkMemory(o, sceneFile.string(), "decoding the scene's textures",
                bytes.geometry + bytes.images + textures.textureBytes + textures.transientBytes);
    const double residentBytes = bytes.geometry + bytes.images + textures.textureBytes;
    const auto t1 = Clock::now();
    const tessera::SceneResources resources(
        scene, [&](std::size_t done, std::size_t total) { progress.update("textures and mips", done, total); },
        tessera::findTechnique(desc.technique)->textures);
    const double texturesMs = msSince(t1);

    tessera::Device device(o.device);
    tessera::DrawStats drawStats;
    tessera::TechniqueContext ctx = frameContext(device, resources, camera, desc, sceneFile);
    ctx.sampleCount = o.msaa;
    ctx.stats = &drawStats;
    std::map<std::string, std::uint64_t> variantCounts;
    ctx.variantCounts = &variantCounts;
    tessera::FrameNotes notes;
    ctx.notes = &notes;
    // --dump-lights: the chosen lights' steps, written during the last (written) run only.
    if (o.dumpLightsRange && (tessera::findTechnique(desc.technique)->features & tessera::kPerLightSteps))
        for (std::uint32_t light = (*o.dumpLightsRange)[0]; light <= (*o.dumpLightsRange)[1] && light < scene.lights.size(); ++light)
            o.dumpLights.push_back(light);
    for (const std::uint32_t light : o.dumpLights)
        if (light >= scene.lights.size())
            throw UsageError("--dump-lights: light " + std::to_string(light) + " does not exist (" + sceneFile.string() + " has " +
                             std::to_string(scene.lights.size()) + " lights, 0.." +
                             std::to_string(scene.lights.size() == 0 ? 0 : scene.lights.size() - 1) + ")");
    std::uint32_t runsStarted = 0;
    std::vector<WrittenFile> lightWritten;
    nlohmann::json lightSteps = nlohmann::json::object();
    std::optional<tessera::PixelHistory> history = probeHistory(o, desc.width, desc.height);
    if (history) {
        std::vector<std::string> names;
        for (const auto& light : scene.lights) names.push_back(light.name);
        history->nameLights(std::move(names));
    }
    tessera::PixelWatch watch;
    if (o.probe) watch = {(*o.probe)[0], (*o.probe)[1], {}};
    if (!o.dumpLights.empty() || history)
        ctx.afterLightStep = [&](std::size_t light, std::string_view step, const tessera::BufferRegistry& now) {
            if (runsStarted != o.warmup + o.repeat) return;
            if (history) {
                history->addDrawEvents("lights", watch, static_cast<long long>(light), step);
                history->record("lights", now, static_cast<long long>(light), step);
            }
            if (std::find(o.dumpLights.begin(), o.dumpLights.end(), light) == o.dumpLights.end()) return;
            const std::string folder = "light-" + std::to_string(light) + "-" + std::string(step);
            nlohmann::json buffers = nlohmann::json::array();
            dumpRegistry(now, fs::path(o.dumpDir) / folder, o, true, lightWritten, buffers);
            lightSteps[std::to_string(light)][std::string(step)] = {{"folder", folder}, {"buffers", buffers}};
        };
    if (!frameSurelyFits(o, desc.width, desc.height, scene.lights.size())) {
        progress.update("estimating memory", 0, 0);
        const tessera::FrameMemoryEstimate e = tessera::estimateFrameMemory(desc.technique, ctx, sceneFile.string());
        checkMemory(o, sceneFile.string(),
                    "rendering " + std::to_string(desc.width) + "x" + std::to_string(desc.height) + " with " + desc.technique +
                        (o.msaa > 1 ? " at --msaa " + std::to_string(o.msaa) : "") + " (frame buffers " +
                        tessera::formatBytes(e.bytes) + ", " + std::to_string(int(std::lround(e.bytesPerPixel))) +
                        " B per pixel; scene and textures " + tessera::formatBytes(residentBytes) + ")",
                    residentBytes + e.bytes);
    }
    const tessera::Frame frame = tessera::buildTechnique(desc.technique, ctx, sceneFile.string());
    checkDumpAfter(frame, o);

    try {
        tessera::BufferRegistry registry;
        registry.setByteLimit(std::uint64_t(std::max(0.0, double(memoryLimitBytes(o)) - residentBytes)), memoryLimitText(o));
        const FrameRuns runs = runFrames(frame, registry, o, progress, "rendering " + desc.technique, [&] {
            ++runsStarted;
            drawStats = {};
            variantCounts.clear();
            notes.clear();
        }, history ? &*history : nullptr, o.probe ? &watch : nullptr, &device);
        progress.update("writing " + o.out, 0, 0);
        const nlohmann::json manifest = sceneManifest(frame, runs, o, loaded, notes, lightSteps);
        std::vector<WrittenFile> written = writeOutputs(registry, o, manifest, &staging);
        written.insert(written.begin(), runs.afterWritten.begin(), runs.afterWritten.end());
        written.insert(written.begin(), lightWritten.begin(), lightWritten.end());
        progress.finish();
        if (!o.quiet && !o.probeJson) printFrameNotes(desc.technique, ctx.options, notes, registry);  // --json: one JSON object
        if (o.stats) printSceneStats(loaded, resources, texturesMs, runs, o, drawStats, frame, registry, variantCounts, written, &staging);
        if (history) {
            history->addTileInfo(registry, lightGridTileSize(desc), scene.lights.size());
            if (o.probeJson) {
                const nlohmann::json j{{"pixel", {(*o.probe)[0], (*o.probe)[1]}}, {"technique", desc.technique},
                                       {"events", history->events()}, {"final", history->last()}, {"tile", history->tile()},
                                       {"lightNames", history->lightNames()}};
                std::printf("%s\n", j.dump().c_str());
            } else {
                std::fputs(history->text().c_str(), stdout);
            }
        }
        if (o.quiet || o.probeJson) {
            // nothing more: --json prints one JSON object
        } else if (o.noOutput)
            std::printf("rendered %ux%u with %s, nothing written (--no-output)\n", desc.width, desc.height, desc.technique.c_str());
        else
            std::printf("wrote %s (%ux%u, %s)\n", o.out.c_str(), desc.width, desc.height, desc.technique.c_str());
        return 0;
    } catch (const tessera::InputError&) {  // MemoryLimitError from a buffer past the limit: exit 2
        progress.finish();
        throw;
    } catch (const std::exception& e) {
        progress.finish();
        std::fprintf(stderr, "tessera render: %s\n", staging.named(e.what()).c_str());
        return 1;
    }
}

// `tessera render builtin`: the generated scene (techniques/builtin_scene.h), which needs no files.
int renderBuiltin(RenderOptions& o, DumpStaging* staging) {
    tessera::BuiltinSceneOptions opt;
    opt.width = o.width ? o.width : opt.width;
    opt.height = o.height ? o.height : opt.height;
    opt.sampleCount = o.msaa;
    opt.precision = o.precision.value_or(tessera::Precision::Exact);
    tessera::Device device(o.device);
    tessera::DrawStats drawStats;
    if (!frameSurelyFits(o, opt.width, opt.height, 0)) {
        // Two probe frames (64 x 64 and 128 x 64 px): every builtin buffer grows with the pixels.
        const auto bytesAt = [&](std::uint32_t width) {
            tessera::BuiltinSceneOptions probe = opt;
            probe.width = width;
            probe.height = 64;
            tessera::DrawStats probeStats;
            tessera::BufferRegistry probeRegistry;
            tessera::buildBuiltinScene(device, probe, probeStats).run(probeRegistry);
            return double(probeRegistry.bytes());
        };
        const double small = bytesAt(64), large = bytesAt(128);
        const double perPixel = (large - small) / (64.0 * 64.0);
        checkMemory(o, "builtin", "rendering " + std::to_string(opt.width) + "x" + std::to_string(opt.height) + " at --msaa " +
                                      std::to_string(opt.sampleCount),
                    small + perPixel * (double(opt.width) * opt.height - 64.0 * 64.0));
    }
    tessera::BufferRegistry registry;
    registry.setByteLimit(memoryLimitBytes(o), memoryLimitText(o));
    const tessera::Frame frame = tessera::buildBuiltinScene(device, opt, drawStats);
    tessera::cli::Progress progress(o.progress);
    checkDumpAfter(frame, o);
    std::optional<tessera::PixelHistory> history = probeHistory(o, opt.width, opt.height);
    tessera::PixelWatch watch;
    if (o.probe) watch = {(*o.probe)[0], (*o.probe)[1], {}};
    const FrameRuns runs =
        runFrames(frame, registry, o, progress, "rendering builtin", [&] { drawStats = {}; }, history ? &*history : nullptr,
                  o.probe ? &watch : nullptr, &device);
    nlohmann::json manifest = manifestBase(frame, runs, o);
    manifest["scene"] = "builtin";
    manifest["technique"] = "builtin";
    manifest["precision"] = std::string(tessera::precisionName(opt.precision));
    manifest["width"] = opt.width;
    manifest["height"] = opt.height;
    manifest["msaa"] = opt.sampleCount;
    std::vector<WrittenFile> written = writeOutputs(registry, o, manifest, staging);
    written.insert(written.begin(), runs.afterWritten.begin(), runs.afterWritten.end());
    progress.finish();
    if (o.stats) {
        printTimings(runs, o, o.repeat > 1);
        printDrawStats(drawStats);
        printBufferStats(frame, registry, inspects(o));
        printPeakMemory();
        printHashes(written, staging);
    }
    if (history) {
        if (o.probeJson)
            std::printf("%s\n", nlohmann::json{{"pixel", {(*o.probe)[0], (*o.probe)[1]}}, {"technique", "builtin"},
                                               {"events", history->events()}, {"final", history->last()}, {"tile", nullptr}}
                                   .dump()
                                   .c_str());
        else std::fputs(history->text().c_str(), stdout);
    }
    if (o.quiet || o.probeJson) {
        // nothing more: --json prints one JSON object
    } else if (o.noOutput) std::printf("rendered %ux%u, nothing written (--no-output)\n", opt.width, opt.height);
    else std::printf("wrote %s (%ux%u)\n", o.out.c_str(), opt.width, opt.height);
    return 0;
}

} // namespace

int renderCommand(const std::vector<std::string_view>& args) {
    bool help = false;
    RenderOptions o = parseRenderArgs(args, help);
    if (help) {
        std::fputs(kRenderUsage, stdout);
        return 0;
    }
    checkOutputPaths(o);
    DumpStaging staging(o);
    if (o.scene == "builtin") return renderBuiltin(o, &staging);
    return renderScene(o, staging);
}

} // namespace tessera::cli
