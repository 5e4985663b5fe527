// D3D11_RASTERIZER_DESC as a value type: culling, winding, depth clip, scissor, MSAA.
// Fill mode is always SOLID and depth bias is not modelled (none of the sources use them).
#pragma once

#include <cstdint>

namespace tessera {

enum class CullMode : std::uint8_t { None = 1, Front, Back };

struct RasterizerState {
    CullMode cullMode = CullMode::Back;
    // D3D meaning: a triangle is front facing when its vertices run counter-clockwise in
    // window space (y down) if true, clockwise if false (the D3D default).
    bool frontCounterClockwise = false;
    // true: clip against 0 <= z <= w. false: no near/far clipping; depth is clamped to the
    // viewport's [MinDepth, MaxDepth] (D3D11.3 §15.? "Depth Clamp").
    bool depthClipEnable = true;
    bool scissorEnable = false;
    // With an MSAA target: coverage is tested at the standard sample positions. Without it
    // (and a multisampled target) D3D11 still uses the sample positions (per D3D11.3 the
    // flag only selects line AA modes); tessera follows D3D11 and ignores the flag for
    // triangles, keeping it only so that descriptions round-trip.
    bool multisampleEnable = false;
};

} // namespace tessera
