// The built-in scene (`tessera render builtin`): a generated lit ground
// plane and cubes (opaque pass) and an alpha-blended pane (transparent pass), as a Frame.
#pragma once

#include <cstdint>

#include <tessera/frame/frame.h>
#include <tessera/raster/device.h>
#include <tessera/state/precision.h>

namespace tessera {

struct BuiltinSceneOptions {
    std::uint32_t width = 640, height = 360;
    std::uint32_t sampleCount = 1;
    // Reference: the Lambert shading in double, also written to "backbuffer.reference"
    // (R32G32B32A32_FLOAT); fast: the raster's fast path (DrawState::precision).
    Precision precision = Precision::Exact;
};

// Builds the frame's passes; buffers: "backbuffer" (RGBA8 sRGB-less UNORM, resolved when
// MSAA), "depth" (D24S8), with MSAA "backbuffer.msaa", with precision reference
// "backbuffer.reference" (and "backbuffer.reference.msaa" with MSAA).
Frame buildBuiltinScene(Device& device, const BuiltinSceneOptions& options, DrawStats& stats);

} // namespace tessera
