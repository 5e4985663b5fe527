// A sampler as a small value type mirroring D3D11_SAMPLER_DESC (D3D11.3 §7.18 "Texture
// Sampling"): min/mag/mip filters, per-axis addressing, LOD bias and clamps, border colour.
// Anisotropic filtering and comparison samplers are not modelled.
#pragma once

#include <glm/glm.hpp>

namespace tessera {

enum class Filter { Point, Linear };
// D3D11_TEXTURE_ADDRESS_MODE: WRAP, MIRROR, CLAMP, BORDER, MIRROR_ONCE.
enum class AddressMode { Wrap, Mirror, Clamp, Border, MirrorOnce };

struct SamplerState {
    Filter minFilter = Filter::Linear;
    Filter magFilter = Filter::Linear;
    Filter mipFilter = Filter::Linear;  // Point: nearest mip level; Linear: blend the two nearest
    AddressMode addressU = AddressMode::Clamp;  // D3D11 default sampler: CLAMP
    AddressMode addressV = AddressMode::Clamp;
    float mipLodBias = 0.0f;     // added to the computed LOD (levels)
    float minLod = -3.402823466e+38f;  // D3D11 default: -FLT_MAX
    float maxLod = 3.402823466e+38f;   // D3D11 default: FLT_MAX
    glm::vec4 borderColor{0.0f};       // AddressMode::Border
    bool operator==(const SamplerState&) const = default;
};

} // namespace tessera
