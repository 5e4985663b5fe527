// The llvmpipe peer: renders a neutral description of D3D11-style draws through Mesa's
// llvmpipe (EGL surfaceless + FBO, GL 4.5 core) so tests and benchmarks can compare tessera
// against a real rasterizer. Mapping of D3D conventions to GL is documented in gl_peer.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tessera::peer {

// D3D11 enums mirrored as plain ints so this header does not depend on tessera's.
enum class Cmp : std::uint8_t { Never, Less, Equal, LessEqual, Greater, NotEqual, GreaterEqual, Always };
enum class StencilOp : std::uint8_t { Keep, Zero, Replace, IncrSat, DecrSat, Invert, Incr, Decr };
enum class Cull : std::uint8_t { None, Front, Back };
// D3D11_BLEND / D3D11_BLEND_OP subsets that GL expresses one to one (no dual source, no SRC_ALPHA_SAT).
enum class BlendFactor : std::uint8_t {
    Zero, One, SrcColor, InvSrcColor, SrcAlpha, InvSrcAlpha, DestAlpha, InvDestAlpha, DestColor, InvDestColor,
    BlendFactor, InvBlendFactor
};
enum class BlendOp : std::uint8_t { Add, Subtract, RevSubtract, Min, Max };
// The depth-stencil buffer: GL_DEPTH32F_STENCIL8 (D3D D32_FLOAT_S8X24_UINT) or GL_DEPTH24_STENCIL8
// (D3D D24_UNORM_S8_UINT).
enum class DepthFormat : std::uint8_t { D32FS8, D24S8 };

struct PeerBlend {
    bool enable = false;
    BlendFactor src = BlendFactor::One, dst = BlendFactor::Zero, srcAlpha = BlendFactor::One, dstAlpha = BlendFactor::Zero;
    BlendOp op = BlendOp::Add, opAlpha = BlendOp::Add;
};

struct StencilFace {
    StencilOp failOp = StencilOp::Keep, depthFailOp = StencilOp::Keep, passOp = StencilOp::Keep;
    Cmp func = Cmp::Always;
};

// One draw: a triangle list in D3D clip space (x,y,z,w per vertex; D3D: 0 <= z <= w),
// with one flat RGBA colour per triangle (or none: white), and the fixed-function state.
struct PeerDraw {
    std::vector<std::array<float, 4>> posClip;  // 3 per triangle
    std::vector<std::array<float, 4>> colorPerTriangle;
    Cull cull = Cull::None;
    bool frontCounterClockwise = false;         // D3D meaning: in window space, y down
    bool depthClipEnable = true;
    bool depthEnable = true;
    bool depthWrite = true;
    Cmp depthFunc = Cmp::Less;
    bool stencilEnable = false;
    std::uint8_t stencilReadMask = 0xFF, stencilWriteMask = 0xFF, stencilRef = 0;
    StencilFace front, back;
    bool colorWrite = true;
    bool additiveBlend = false;                 // ONE + ONE, for counting coverage (overrides `blend`)
    PeerBlend blend;                            // used when additiveBlend is false
    std::array<float, 4> blendFactor{1, 1, 1, 1};
    std::uint8_t colorWriteMask = 0xF;          // D3D11_COLOR_WRITE_ENABLE bits (R=1, G=2, B=4, A=8), with colorWrite
    bool scissorEnable = false;
    std::array<int, 4> scissor{0, 0, 0, 0};     // D3D11_RECT left, top, right, bottom (px, D3D rows)
};

struct PeerFrame {
    int width = 0, height = 0;
    std::array<float, 4> clearColor{0, 0, 0, 0};
    float clearDepth = 1.0f;
    std::uint8_t clearStencil = 0;
    DepthFormat depthFormat = DepthFormat::D32FS8;
    int samples = 1;                            // 1, or 4 (llvmpipe's only MSAA count: the D3D standard 4x pattern)
    std::vector<PeerDraw> draws;
};

// Read-back in D3D row order: row 0 is the top of the D3D image. Sample s of pixel (x, y) is
// element (y*width + x)*samples + s (with one sample: y*width + x).
struct PeerImage {
    int width = 0, height = 0, samples = 1;
    std::vector<std::uint8_t> rgba8;   // 4 per sample
    std::vector<float> depth;          // D32F: the stored float; D24S8: depthCode / (2^24 - 1)
    std::vector<std::uint32_t> depthCode;  // D24S8 only: the stored 24-bit code (see depthCodeExact)
    bool depthCodeExact = true;        // false for D24S8 with 4 samples: decoded from a float fetch (+-1 code)
    std::vector<std::uint8_t> stencil;
    std::uint64_t samplesPassed = 0;   // GL_SAMPLES_PASSED summed over all draws
};

class GlPeer {
public:
    // Creates the EGL surfaceless context. Returns nullopt with a reason in *why when no
    // llvmpipe context can be made (tests then fail with that reason; they do not skip).
    static std::optional<GlPeer> create(std::string* why);
    GlPeer(GlPeer&&) noexcept;
    GlPeer& operator=(GlPeer&&) noexcept;
    ~GlPeer();

    std::string renderer() const;      // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    // Renders and reads back. Throws std::invalid_argument on a malformed frame and
    // std::runtime_error on a GL error. A peer is bound to the thread that created it.
    PeerImage render(const PeerFrame& frame);
    // Times `repeats` renders of the frame (after one warm-up), returning seconds per render
    // (median), each ended with glFinish; vertices are uploaded once, before the clock. For the
    // benchmark; Mesa reads LP_NUM_THREADS when the EGL display is initialised, i.e. at the
    // first create() while no other peer is alive, so set it before that.
    double timeRender(const PeerFrame& frame, int repeats);

private:
    GlPeer();
    struct Impl;
    Impl* mImpl = nullptr;
};

} // namespace tessera::peer
