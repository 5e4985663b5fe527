// The programmable stages as C++ functors constrained by concepts (no virtual call per
// fragment): a vertex shader maps a vertex to SV_Position + typed varyings; a pixel shader
// maps interpolated varyings (+ SV_Position, SV_IsFrontFace, SV_Coverage) to up to 8 outputs.
#pragma once

#include <array>
#include <bit>
#include <concepts>
#include <cstdint>
#include <span>
#include <type_traits>

#include <glm/glm.hpp>

namespace tessera {

// Varyings are a trivially copyable struct made only of floats (float, glm::vec2/3/4, arrays
// of them): the rasterizer interpolates them component by component as a float array.
// kMaxVaryingFloats = 64 floats (16 float4 registers; D3D11 allows 32, the sources' shaders use <= 6).
inline constexpr std::size_t kMaxVaryingFloats = 64;

template <class V>
concept Varyings = std::is_trivially_copyable_v<V> && std::is_default_constructible_v<V> &&
                   sizeof(V) % sizeof(float) == 0 && alignof(V) == alignof(float) &&
                   sizeof(V) / sizeof(float) <= kMaxVaryingFloats;

// A struct with no members still occupies one byte; this is the "no varyings" type.
struct NoVaryings {
    float unused = 0.0f;
};

template <Varyings V>
inline constexpr std::size_t kVaryingFloatCount = sizeof(V) / sizeof(float);

template <Varyings V>
using VaryingArray = std::array<float, kVaryingFloatCount<V>>;

// A varyings member's name and width in floats. A varyings type may list its members as
// `static constexpr std::array<VaryingField, N> kFields` (in declaration order), so that tools
// (`tessera probe`) can name the shader's inputs; the rasterizer itself never reads names.
struct VaryingField {
    const char* name;
    std::uint32_t floats;
};

// V::kFields when it declares them, otherwise empty.
template <Varyings V>
constexpr std::span<const VaryingField> varyingFields() {
    if constexpr (requires { V::kFields; }) {
        static_assert([] {
            std::size_t floats = 0;
            for (const VaryingField& f : V::kFields) floats += f.floats;
            return floats == kVaryingFloatCount<V>;
        }(), "kFields must cover every float of the varyings, in order");
        return std::span<const VaryingField>(V::kFields);
    } else {
        return {};
    }
}

template <Varyings V>
struct VertexOutput {
    glm::vec4 posClip;  // SV_Position out of the vertex shader (D3D clip space: 0 <= z <= w)
    V varyings;
};

// A vertex shader: vs(vertex) -> VertexOutput<V>.
template <class VS, class Vertex>
concept VertexShaderFor = requires(const VS& vs, const Vertex& v) {
    typename VS::Varyings;
    requires Varyings<typename VS::Varyings>;
    { vs(v) } -> std::same_as<VertexOutput<typename VS::Varyings>>;
};

// What a pixel shader receives for one pixel (or one sample when it runs per sample).
template <Varyings V>
struct PixelInput {
    V varyings;          // perspective-correct at the pixel centre (or sample position)
    V ddx, ddy;          // coarse derivatives over the 2x2 quad: right - left, bottom - top (top row / left column)
    glm::vec4 posWindow; // SV_Position: x,y window px (centre +0.5), z depth, w clip-space w
    bool isFrontFace;    // SV_IsFrontFace
    std::uint32_t coverage;     // SV_Coverage: bit s set when sample s is covered
    std::uint32_t sampleIndex;  // SV_SampleIndex (0 unless the shader runs per sample)
};

// Up to 8 colour outputs (SV_Target0..7) and SV_Depth. For UINT targets, write the integer
// bit pattern with glm::uintBitsToFloat (shader registers are typeless, as in D3D).
template <int N>
struct PixelOutput {
    static_assert(N >= 0 && N <= 8, "D3D11 has at most 8 render targets");
    std::array<glm::vec4, (N > 0 ? N : 1)> target{};
    float depth = 0.0f;   // SV_Depth, read only when the shader declares kWritesDepth
    bool discarded = false;
    void discard() { discarded = true; }  // HLSL discard / clip(): no writes of any kind
};

// A pixel shader: `void operator()(const PixelInput<Varyings>&, PixelOutput<kTargetCount>&) const`
// plus optional traits (all default false):
//   static constexpr bool kWritesDepth  - outputs SV_Depth (disables early depth/stencil)
//   static constexpr bool kPerSample    - runs once per covered sample (reads SV_SampleIndex)
//   static constexpr bool kMayDiscard   - may call discard()
//   static constexpr SampleRates kSampleRates - the target sample counts the rasterizer is compiled
//                                       for with this shader (default Both; per-sample shaders:
//                                       Multi). Each compiled rate costs build time
//                                       (raster/detail/draw_impl.h: DepthKernel).
enum class SampleRates : std::uint8_t { Single = 1, Multi = 2, Both = 3 };

template <class PS>
concept PixelShader = requires(const PS& ps, const PixelInput<typename PS::Varyings>& in,
                               PixelOutput<PS::kTargetCount>& out) {
    typename PS::Varyings;
    requires Varyings<typename PS::Varyings>;
    { PS::kTargetCount } -> std::convertible_to<int>;
    ps(in, out);
};

// Depth/stencil-only passes bind no pixel shader at all (no colour writes, no discard).
struct NoPixelShader {};

template <class PS>
concept PixelShaderOrNone = PixelShader<PS> || std::same_as<PS, NoPixelShader>;

namespace detail {
template <class PS> constexpr bool writesDepth() { if constexpr (requires { PS::kWritesDepth; }) return PS::kWritesDepth; else return false; }
template <class PS> constexpr bool perSample() { if constexpr (requires { PS::kPerSample; }) return PS::kPerSample; else return false; }
template <class PS> constexpr bool mayDiscard() { if constexpr (requires { PS::kMayDiscard; }) return PS::kMayDiscard; else return false; }
template <class PS> constexpr SampleRates sampleRates() {
    if constexpr (requires { PS::kSampleRates; }) return PS::kSampleRates;
    else return perSample<PS>() ? SampleRates::Multi : SampleRates::Both;
}
template <class PS> constexpr bool compiledFor(SampleRates rate) { return (std::uint8_t(sampleRates<PS>()) & std::uint8_t(rate)) != 0; }
} // namespace detail

} // namespace tessera
