// The GL side of the same-frame benchmark (llvmpipe, or a GPU driver with --gl-platform device):
// draws tessera's scene (its draw items, decoded mip chains, view-space lights, camera matrices
// and light volumes) through OpenGL 4.5 core with the GLSL of shaders.h, pass for pass as
// tessera's forward, deferred and forward-plus frames,
// timing each pass with glFinish around it (and, optionally, a GL_TIME_ELAPSED query: the GPU's
// execution time of the pass) and reading back colour, depth and stencil.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <tessera/scene/scene_resources.h>
#include <tessera/techniques/forward.h>

namespace tessera::samefr {

enum class Technique { Forward, ForwardPlus, Deferred };

struct PassTime {
    std::string name;   // tessera's pass name
    double milliseconds = 0.0;      // wall clock, glFinish before and after the pass
    double gpuMilliseconds = -1.0;  // GL_TIME_ELAPSED query (GlOptions::timerQueries), else < 0
};

// Read-back in D3D row order (row 0 at the top), width * height entries.
struct GlImages {
    std::vector<std::uint8_t> rgba8;            // 4 bytes per pixel
    std::vector<std::uint32_t> depthStencil;    // GL_UNSIGNED_INT_24_8: depth code << 8 | stencil
};

struct GlOptions {
    // Diagnostic: sample textures with tessera's D3D11 trilinear rules written in GLSL over
    // texelFetch (shaders.h sampleSlot) instead of llvmpipe's sampler. Attributes image
    // differences; its timings are not llvmpipe's sampler's.
    bool emulatedSampling = false;
    // Also time every pass with a GL_TIME_ELAPSED query (PassTime::gpuMilliseconds).
    bool timerQueries = false;
};

// Forward+ light lists as the culling dispatch left them: grids of (offset, count) per tile,
// row-major, and the global index lists (numTiles * 200 entries).
struct GlLightLists {
    std::vector<std::uint32_t> opaqueGrid, transparentGrid;    // 2 per tile
    std::vector<std::uint32_t> opaqueIndex, transparentIndex;
};

class GlRenderer {
public:
    // Uploads geometry, textures (every level of tessera's decoded chains) and lights, compiles
    // the programs and makes the targets. A GlContext must be current. `setup` is the frame's
    // ForwardPassSetup (camera matrices, texture set, view-space lights), as tessera's technique
    // builds it with its default options. Throws std::runtime_error on a GL or shader error.
    GlRenderer(const SceneResources& resources, const ForwardPassSetup& setup, Technique technique,
               const GlOptions& options = {});
    ~GlRenderer();
    GlRenderer(const GlRenderer&) = delete;
    GlRenderer& operator=(const GlRenderer&) = delete;

    // One frame: every pass between glFinish calls, timed on the wall clock (and by a timer query
    // with GlOptions::timerQueries).
    std::vector<PassTime> renderFrame();
    GlImages readBack() const;
    // Forward+ only (empty otherwise).
    GlLightLists readLightLists() const;

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

} // namespace tessera::samefr
