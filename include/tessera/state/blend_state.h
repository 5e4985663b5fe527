// D3D11_BLEND_DESC as a value type: per render target blend factors, ops and write mask.
// Dual-source factors (SRC1_*) are not supported and rejected by validation.
#pragma once

#include <array>
#include <cstdint>

namespace tessera {

enum class Blend : std::uint8_t {
    Zero = 1, One, SrcColor, InvSrcColor, SrcAlpha, InvSrcAlpha, DestAlpha, InvDestAlpha,
    DestColor, InvDestColor, SrcAlphaSat, BlendFactor = 14, InvBlendFactor,
    Src1Color, InvSrc1Color, Src1Alpha, InvSrc1Alpha
};
enum class BlendOp : std::uint8_t { Add = 1, Subtract, RevSubtract, Min, Max };

// D3D11_COLOR_WRITE_ENABLE bits.
enum ColorWrite : std::uint8_t { WriteRed = 1, WriteGreen = 2, WriteBlue = 4, WriteAlpha = 8, WriteAll = 15 };

struct RenderTargetBlendDesc {
    bool blendEnable = false;
    Blend srcBlend = Blend::One, destBlend = Blend::Zero;
    BlendOp blendOp = BlendOp::Add;
    Blend srcBlendAlpha = Blend::One, destBlendAlpha = Blend::Zero;
    BlendOp blendOpAlpha = BlendOp::Add;
    std::uint8_t renderTargetWriteMask = WriteAll;
};

inline constexpr int kMaxRenderTargets = 8;  // D3D11_SIMULTANEOUS_RENDER_TARGET_COUNT

struct BlendState {
    bool alphaToCoverageEnable = false;  // not supported; validation rejects true
    bool independentBlendEnable = false; // false: renderTarget[0] applies to all targets
    std::array<RenderTargetBlendDesc, kMaxRenderTargets> renderTarget{};
};

// Alpha blending as the reproduced sources use it (SRC_ALPHA, INV_SRC_ALPHA, ADD).
inline constexpr RenderTargetBlendDesc kAlphaBlend{true, Blend::SrcAlpha, Blend::InvSrcAlpha, BlendOp::Add,
                                                    Blend::One, Blend::InvSrcAlpha, BlendOp::Add, WriteAll};
// Additive accumulation (ONE, ONE, ADD), as deferred light passes use it.
inline constexpr RenderTargetBlendDesc kAdditiveBlend{true, Blend::One, Blend::One, BlendOp::Add,
                                                       Blend::One, Blend::One, BlendOp::Add, WriteAll};

} // namespace tessera
