// D3D11_DEPTH_STENCIL_DESC as a value type: depth test and write, two-sided stencil.
// Stencil ops follow D3D11_STENCIL_OP; the test compares (ref & readMask) OP (stored & readMask).
#pragma once

#include <cstdint>

#include <tessera/state/comparison.h>

namespace tessera {

enum class StencilOp : std::uint8_t {
    Keep = 1, Zero, Replace, IncrSat, DecrSat, Invert, Incr, Decr
};

struct StencilFaceDesc {
    StencilOp failOp = StencilOp::Keep;       // stencil test failed
    StencilOp depthFailOp = StencilOp::Keep;  // stencil passed, depth failed
    StencilOp passOp = StencilOp::Keep;       // both passed
    ComparisonFunc func = ComparisonFunc::Always;
};

struct DepthStencilState {
    bool depthEnable = true;
    bool depthWriteEnable = true;              // D3D11_DEPTH_WRITE_MASK_ALL vs ZERO
    ComparisonFunc depthFunc = ComparisonFunc::Less;
    bool stencilEnable = false;
    std::uint8_t stencilReadMask = 0xFF;
    std::uint8_t stencilWriteMask = 0xFF;
    StencilFaceDesc frontFace;
    StencilFaceDesc backFace;
};

// Applies one stencil op to an 8-bit stored value (D3D11_STENCIL_OP semantics).
constexpr std::uint8_t applyStencilOp(StencilOp op, std::uint8_t stored, std::uint8_t ref) {
    switch (op) {
    case StencilOp::Keep: return stored;
    case StencilOp::Zero: return 0;
    case StencilOp::Replace: return ref;
    case StencilOp::IncrSat: return stored == 0xFF ? stored : static_cast<std::uint8_t>(stored + 1);
    case StencilOp::DecrSat: return stored == 0 ? stored : static_cast<std::uint8_t>(stored - 1);
    case StencilOp::Invert: return static_cast<std::uint8_t>(~stored);
    case StencilOp::Incr: return static_cast<std::uint8_t>(stored + 1);   // wraps 255 -> 0
    case StencilOp::Decr: return static_cast<std::uint8_t>(stored - 1);   // wraps 0 -> 255
    }
    return stored;
}

// The stored value after an op, honouring the write mask: bits outside the mask keep
// their old value (D3D11.3: StencilWriteMask).
constexpr std::uint8_t writeStencil(std::uint8_t stored, std::uint8_t computed, std::uint8_t writeMask) {
    return static_cast<std::uint8_t>((stored & ~writeMask) | (computed & writeMask));
}

} // namespace tessera
