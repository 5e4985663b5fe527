// The llvmpipe peer: draws a PeerFrame (D3D11-convention clip-space triangles + fixed-function
// state) through Mesa llvmpipe via EGL surfaceless + FBO, and reads colour/depth/stencil back in
// D3D row order. The D3D -> GL mapping (y negation, front face, stencil faces, rows) is derived
// below and checked by tests/conformance/gl_peer_selftest_test.cpp.
//
// Mapping, derived:
// * Rows. D3D: yWindow = (1 - yNdc) * H/2, row 0 at the top. The vertex shader emits
//   gl_Position.y = -posClip.y, so GL (lower-left origin) computes
//   yGlWindow = (-yNdc + 1) * H/2 = yWindow: the same number. GL memory row r covers
//   yGlWindow in [r, r+1), so D3D row r is glReadPixels row r; no flip on read-back.
//   Measured (Mesa 22.3.6 llvmpipe): with GL_LOWER_LEFT llvmpipe includes pixel centres on min-x and
//   min-row edges, which in D3D row space is exactly the top-left rule.
// * Front face. GL computes the signed area a = 1/2 sum(x_i*y_{i+1} - x_{i+1}*y_i) in GL window
//   coordinates and calls a > 0 "counter-clockwise" (y up). Our GL window coordinates equal the
//   D3D window coordinates numerically, and in D3D's y-down window a > 0 is clockwise on screen
//   (e.g. (0,0) -> (1,0) -> (0,1): top-left, top-right, bottom-left; a = +1/2). So
//   D3D FrontCounterClockwise=false (front = clockwise on screen, a > 0) -> glFrontFace(GL_CCW);
//   FrontCounterClockwise=true -> glFrontFace(GL_CW). GL's front/back then select exactly the
//   D3D front/back triangles, so D3D's FrontFace stencil state goes to GL_FRONT and BackFace to
//   GL_BACK unchanged (and D3D CULL_BACK -> GL_BACK, CULL_FRONT -> GL_FRONT).
// * Stencil compare. D3D: (StencilRef & ReadMask) Func (stored & ReadMask); GL glStencilFunc:
//   (ref & mask) Func (stored & mask), ref on the left too. Same function, no swap.
// * Stencil ops. D3D INCR_SAT/DECR_SAT clamp = GL_INCR/GL_DECR; D3D INCR/DECR wrap =
//   GL_INCR_WRAP/GL_DECR_WRAP.
// * Depth. glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) + glDepthRange(0,1): clip volume
//   0 <= z <= w and zWindow = zNdc, as in D3D with MinDepth=0, MaxDepth=1.
//   DepthClipEnable=false -> GL_DEPTH_CLAMP (no near/far clipping, depth clamped to [0,1]).
// * Scissor. D3D11_RECT (left, top, right, bottom) in D3D rows; GL memory row r == D3D row r, so
//   glScissor(left, top, right - left, bottom - top) selects the same pixels.
// * MSAA. llvmpipe supports 4 samples only, at lp_sample_pos_4x = (0.375, 0.125), (0.875, 0.375),
//   (0.125, 0.625), (0.625, 0.875) from the pixel's corner at the lowest GL x and y. GL window y
//   equals D3D window y here (rows above), so these are the D3D11 standard 4x offsets
//   (-2,-6), (6,-2), (-6,2), (2,6) in 1/16 px from the centre (D3D11.3 §19.2.4), in the same order.
//   Samples are read back one at a time with texelFetch from multisample textures.
#include "gl_peer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <stdexcept>
#include <utility>

namespace tessera::peer {
namespace {

constexpr const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec4 aPosClip;
layout(location = 1) in vec4 aColor;
flat out vec4 vColor;
void main() {
    // D3D clip space -> GL clip space: negate y so D3D window row r is GL memory row r.
    gl_Position = vec4(aPosClip.x, -aPosClip.y, aPosClip.z, aPosClip.w);
    vColor = aColor;
}
)";

constexpr const char* kFragmentShader = R"(#version 450 core
flat in vec4 vColor;
layout(location = 0) out vec4 oColor;
void main() { oColor = vColor; }
)";

constexpr int kFloatsPerVertex = 8;  // vec4 posClip, vec4 colour

// Read-back of one sample of multisample textures: a full-screen triangle whose fragments copy
// sample uSample of colour and depth (pass 1), or of stencil (pass 2, the depth-stencil texture
// switched to GL_STENCIL_INDEX mode) into single-sample targets.
constexpr const char* kResolveVertexShader = R"(#version 450 core
void main() {
    const vec2 p[3] = vec2[3](vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
    gl_Position = vec4(p[gl_VertexID], 0.0, 1.0);
}
)";
constexpr const char* kResolveColorDepthShader = R"(#version 450 core
layout(binding = 0) uniform sampler2DMS uColor;
layout(binding = 1) uniform sampler2DMS uDepth;
uniform int uSample;
layout(location = 0) out vec4 oColor;
layout(location = 1) out float oDepth;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    oColor = texelFetch(uColor, p, uSample);
    oDepth = texelFetch(uDepth, p, uSample).r;
}
)";
constexpr const char* kResolveStencilShader = R"(#version 450 core
layout(binding = 2) uniform usampler2DMS uStencil;
uniform int uSample;
layout(location = 0) out uint oStencil;
void main() { oStencil = texelFetch(uStencil, ivec2(gl_FragCoord.xy), uSample).r; }
)";

GLenum toGl(BlendFactor f) {
    switch (f) {
    case BlendFactor::Zero: return GL_ZERO;
    case BlendFactor::One: return GL_ONE;
    case BlendFactor::SrcColor: return GL_SRC_COLOR;
    case BlendFactor::InvSrcColor: return GL_ONE_MINUS_SRC_COLOR;
    case BlendFactor::SrcAlpha: return GL_SRC_ALPHA;
    case BlendFactor::InvSrcAlpha: return GL_ONE_MINUS_SRC_ALPHA;
    case BlendFactor::DestAlpha: return GL_DST_ALPHA;
    case BlendFactor::InvDestAlpha: return GL_ONE_MINUS_DST_ALPHA;
    case BlendFactor::DestColor: return GL_DST_COLOR;
    case BlendFactor::InvDestColor: return GL_ONE_MINUS_DST_COLOR;
    case BlendFactor::BlendFactor: return GL_CONSTANT_COLOR;        // D3D11_BLEND_BLEND_FACTOR
    case BlendFactor::InvBlendFactor: return GL_ONE_MINUS_CONSTANT_COLOR;
    }
    return GL_ONE;
}

GLenum toGl(BlendOp op) {
    switch (op) {
    case BlendOp::Add: return GL_FUNC_ADD;
    case BlendOp::Subtract: return GL_FUNC_SUBTRACT;                // src - dst, as D3D11_BLEND_OP_SUBTRACT
    case BlendOp::RevSubtract: return GL_FUNC_REVERSE_SUBTRACT;
    case BlendOp::Min: return GL_MIN;                               // factors ignored in both APIs
    case BlendOp::Max: return GL_MAX;
    }
    return GL_FUNC_ADD;
}

GLenum toGl(Cmp c) {
    switch (c) {
    case Cmp::Never: return GL_NEVER;
    case Cmp::Less: return GL_LESS;
    case Cmp::Equal: return GL_EQUAL;
    case Cmp::LessEqual: return GL_LEQUAL;
    case Cmp::Greater: return GL_GREATER;
    case Cmp::NotEqual: return GL_NOTEQUAL;
    case Cmp::GreaterEqual: return GL_GEQUAL;
    case Cmp::Always: return GL_ALWAYS;
    }
    return GL_ALWAYS;
}

GLenum toGl(StencilOp op) {
    switch (op) {
    case StencilOp::Keep: return GL_KEEP;
    case StencilOp::Zero: return GL_ZERO;
    case StencilOp::Replace: return GL_REPLACE;
    case StencilOp::IncrSat: return GL_INCR;       // D3D11_STENCIL_OP_INCR_SAT: clamps at 255
    case StencilOp::DecrSat: return GL_DECR;       // D3D11_STENCIL_OP_DECR_SAT: clamps at 0
    case StencilOp::Invert: return GL_INVERT;
    case StencilOp::Incr: return GL_INCR_WRAP;     // D3D11_STENCIL_OP_INCR: wraps
    case StencilOp::Decr: return GL_DECR_WRAP;     // D3D11_STENCIL_OP_DECR: wraps
    }
    return GL_KEEP;
}

const char* eglErrorName(EGLint e) {
    switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return "EGL error";
    }
}

std::string eglFailure(const char* what) {
    const EGLint e = eglGetError();
    char code[16];
    std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(e));
    return std::string(what) + " failed: " + eglErrorName(e) + " (" + code + ")";
}

void throwOnGlError(const char* where) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        char code[16];
        std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(e));
        throw std::runtime_error(std::string("gl_peer: GL error ") + code + " in " + where);
    }
}

// Compiles one stage; returns 0 and fills *log on failure.
GLuint compileShader(GLenum stage, const char* source, std::string* log) {
    const GLuint shader = glCreateShader(stage);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint len = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
        std::string text(static_cast<std::size_t>(std::max(len, 1)), '\0');
        glGetShaderInfoLog(shader, len, nullptr, text.data());
        *log = "shader compile failed: " + text;
        glDeleteShader(shader);
        return 0;
    }
    return shader;
}

// Compiles and links a vertex + fragment program; returns 0 and fills *log on failure.
GLuint linkProgram(const char* vertexSource, const char* fragmentSource, std::string* log) {
    const GLuint vs = compileShader(GL_VERTEX_SHADER, vertexSource, log);
    if (vs == 0) return 0;
    const GLuint fs = compileShader(GL_FRAGMENT_SHADER, fragmentSource, log);
    if (fs == 0) {
        glDeleteShader(vs);
        return 0;
    }
    const GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint linked = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (linked != GL_TRUE) {
        *log = "program link failed";
        glDeleteProgram(program);
        return 0;
    }
    return program;
}

// Live peers on the (process-wide) surfaceless display; the last one out terminates it so a
// later create() re-initialises llvmpipe (and re-reads LP_NUM_THREADS).
int gLivePeers = 0;

} // namespace

struct GlPeer::Impl {
    EGLDisplay dpy = EGL_NO_DISPLAY;
    EGLContext ctx = EGL_NO_CONTEXT;
    std::string rendererName;
    GLuint program = 0, vao = 0, vbo = 0, fbo = 0, colorRb = 0, depthStencilRb = 0, query = 0;
    int fbWidth = 0, fbHeight = 0, fbSamples = 0;
    DepthFormat fbDepthFormat = DepthFormat::D32FS8;
    // Multisample frames: textures instead of renderbuffers, and the per-sample read-back targets.
    GLuint colorTex = 0, depthStencilTex = 0;
    GLuint resolveColorDepthProgram = 0, resolveStencilProgram = 0, emptyVao = 0;
    GLuint resolveFbo = 0, resolveStencilFbo = 0, resolveColorRb = 0, resolveDepthRb = 0, resolveStencilRb = 0;
    GLsizeiptr vboBytes = 0;

    void makeCurrent() const {
        if (eglGetCurrentContext() != ctx &&
            eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx) != EGL_TRUE) {
            throw std::runtime_error("gl_peer: " + eglFailure("eglMakeCurrent"));
        }
    }

    void deleteFramebuffer() {
        const GLuint rbs[] = {colorRb, depthStencilRb, resolveColorRb, resolveDepthRb, resolveStencilRb};
        const GLuint fbos[] = {fbo, resolveFbo, resolveStencilFbo};
        const GLuint texs[] = {colorTex, depthStencilTex};
        glDeleteRenderbuffers(5, rbs);
        glDeleteFramebuffers(3, fbos);
        glDeleteTextures(2, texs);
        colorRb = depthStencilRb = resolveColorRb = resolveDepthRb = resolveStencilRb = 0;
        fbo = resolveFbo = resolveStencilFbo = colorTex = depthStencilTex = 0;
    }

    static void checkComplete(GLuint framebuffer, const char* what) {
        const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE) {
            throw std::runtime_error(std::string("gl_peer: ") + what + " framebuffer incomplete (" + std::to_string(status) + ")");
        }
    }

    void ensureFramebuffer(int width, int height, DepthFormat depthFormat, int samples) {
        if (width <= 0 || height <= 0) throw std::invalid_argument("gl_peer: empty frame");
        if (samples != 1 && samples != 4) throw std::invalid_argument("gl_peer: samples must be 1 or 4 (llvmpipe)");
        if (fbo != 0 && width == fbWidth && height == fbHeight && depthFormat == fbDepthFormat && samples == fbSamples) return;
        if (fbo != 0) deleteFramebuffer();
        const GLenum dsFormat = depthFormat == DepthFormat::D24S8 ? GL_DEPTH24_STENCIL8 : GL_DEPTH32F_STENCIL8;
        glCreateFramebuffers(1, &fbo);
        if (samples == 1) {
            glCreateRenderbuffers(1, &colorRb);
            glNamedRenderbufferStorage(colorRb, GL_RGBA8, width, height);
            glCreateRenderbuffers(1, &depthStencilRb);
            glNamedRenderbufferStorage(depthStencilRb, dsFormat, width, height);
            glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colorRb);
            glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depthStencilRb);
        } else {
            // Fixed sample locations: the standard pattern in every pixel.
            glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &colorTex);
            glTextureStorage2DMultisample(colorTex, samples, GL_RGBA8, width, height, GL_TRUE);
            glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &depthStencilTex);
            glTextureStorage2DMultisample(depthStencilTex, samples, dsFormat, width, height, GL_TRUE);
            glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, colorTex, 0);
            glNamedFramebufferTexture(fbo, GL_DEPTH_STENCIL_ATTACHMENT, depthStencilTex, 0);
            // Single-sample read-back targets: RGBA8 + R32F (pass 1), R32UI (pass 2).
            glCreateRenderbuffers(1, &resolveColorRb);
            glNamedRenderbufferStorage(resolveColorRb, GL_RGBA8, width, height);
            glCreateRenderbuffers(1, &resolveDepthRb);
            glNamedRenderbufferStorage(resolveDepthRb, GL_R32F, width, height);
            glCreateRenderbuffers(1, &resolveStencilRb);
            glNamedRenderbufferStorage(resolveStencilRb, GL_R32UI, width, height);
            glCreateFramebuffers(1, &resolveFbo);
            glNamedFramebufferRenderbuffer(resolveFbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolveColorRb);
            glNamedFramebufferRenderbuffer(resolveFbo, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, resolveDepthRb);
            const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
            glNamedFramebufferDrawBuffers(resolveFbo, 2, both);
            checkComplete(resolveFbo, "read-back");
            glCreateFramebuffers(1, &resolveStencilFbo);
            glNamedFramebufferRenderbuffer(resolveStencilFbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolveStencilRb);
            glNamedFramebufferDrawBuffer(resolveStencilFbo, GL_COLOR_ATTACHMENT0);
            checkComplete(resolveStencilFbo, "stencil read-back");
        }
        glNamedFramebufferDrawBuffer(fbo, GL_COLOR_ATTACHMENT0);
        glNamedFramebufferReadBuffer(fbo, GL_COLOR_ATTACHMENT0);
        checkComplete(fbo, "render");
        fbWidth = width;
        fbHeight = height;
        fbDepthFormat = depthFormat;
        fbSamples = samples;
        throwOnGlError("ensureFramebuffer");
    }

    // Reads every sample of the multisample targets into img (layout in gl_peer.h).
    void readSamples(PeerImage& img) {
        const int w = img.width, h = img.height, n = img.samples;
        const auto pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
        std::vector<std::uint8_t> rgba(pixels * 4);
        std::vector<float> depth(pixels);
        std::vector<std::uint32_t> stencil(pixels);
        glViewport(0, 0, w, h);
        glDisable(GL_SCISSOR_TEST);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_STENCIL_TEST);
        glDisable(GL_BLEND);
        glDisable(GL_CULL_FACE);
        glDisable(GL_MULTISAMPLE);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glBindVertexArray(emptyVao);
        glBindTextureUnit(0, colorTex);
        glBindTextureUnit(1, depthStencilTex);
        glBindTextureUnit(2, depthStencilTex);
        for (int s = 0; s < n; ++s) {
            glTextureParameteri(depthStencilTex, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
            glBindFramebuffer(GL_FRAMEBUFFER, resolveFbo);
            glUseProgram(resolveColorDepthProgram);
            glUniform1i(glGetUniformLocation(resolveColorDepthProgram, "uSample"), s);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, resolveFbo);
            glReadBuffer(GL_COLOR_ATTACHMENT0);
            glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
            glReadBuffer(GL_COLOR_ATTACHMENT1);
            glReadPixels(0, 0, w, h, GL_RED, GL_FLOAT, depth.data());

            glTextureParameteri(depthStencilTex, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_STENCIL_INDEX);
            glBindFramebuffer(GL_FRAMEBUFFER, resolveStencilFbo);
            glUseProgram(resolveStencilProgram);
            glUniform1i(glGetUniformLocation(resolveStencilProgram, "uSample"), s);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, resolveStencilFbo);
            glReadBuffer(GL_COLOR_ATTACHMENT0);
            glReadPixels(0, 0, w, h, GL_RED_INTEGER, GL_UNSIGNED_INT, stencil.data());
            throwOnGlError("per-sample read-back");
            for (std::size_t i = 0; i < pixels; ++i) {
                const std::size_t o = i * std::size_t(n) + std::size_t(s);
                std::copy(rgba.begin() + std::ptrdiff_t(i * 4), rgba.begin() + std::ptrdiff_t(i * 4 + 4),
                          img.rgba8.begin() + std::ptrdiff_t(o * 4));
                img.depth[o] = depth[i];
                img.stencil[o] = static_cast<std::uint8_t>(stencil[i]);
                if (fbDepthFormat == DepthFormat::D24S8) {
                    // The sampler returns code / (2^24 - 1) rounded to float (within about one
                    // float ulp, 2^-24 near 1): scaling back recovers the code within +-1.
                    img.depthCode[o] = static_cast<std::uint32_t>(std::lround(double(depth[i]) * 16777215.0));
                }
            }
        }
        glTextureParameteri(depthStencilTex, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
    }

    // Interleaves every draw's vertices into the VBO (once per render/timeRender call).
    // Returns the first vertex of each draw.
    std::vector<GLint> upload(const PeerFrame& frame) {
        std::size_t vertexCount = 0;
        for (const PeerDraw& d : frame.draws) {
            if (d.posClip.size() % 3 != 0) {
                throw std::invalid_argument("gl_peer: posClip size is not a multiple of 3");
            }
            if (!d.colorPerTriangle.empty() && d.colorPerTriangle.size() * 3 != d.posClip.size()) {
                throw std::invalid_argument("gl_peer: colorPerTriangle must be empty or one per triangle");
            }
            vertexCount += d.posClip.size();
        }
        if (vertexCount > static_cast<std::size_t>(std::numeric_limits<GLint>::max() / 2)) {
            throw std::invalid_argument("gl_peer: too many vertices");
        }
        std::vector<float> interleaved(vertexCount * kFloatsPerVertex);
        std::vector<GLint> firstVertex;
        firstVertex.reserve(frame.draws.size());
        std::size_t v = 0;
        for (const PeerDraw& d : frame.draws) {
            firstVertex.push_back(static_cast<GLint>(v));
            for (std::size_t i = 0; i < d.posClip.size(); ++i, ++v) {
                const std::array<float, 4> white{1, 1, 1, 1};
                const std::array<float, 4>& color = d.colorPerTriangle.empty() ? white : d.colorPerTriangle[i / 3];
                float* dst = interleaved.data() + v * kFloatsPerVertex;
                std::copy(d.posClip[i].begin(), d.posClip[i].end(), dst);
                std::copy(color.begin(), color.end(), dst + 4);
            }
        }
        const auto bytes = static_cast<GLsizeiptr>(interleaved.size() * sizeof(float));
        if (bytes > vboBytes) {
            glNamedBufferData(vbo, bytes, interleaved.data(), GL_STATIC_DRAW);
            vboBytes = bytes;
        } else if (bytes > 0) {
            glNamedBufferSubData(vbo, 0, bytes, interleaved.data());
        }
        throwOnGlError("upload");
        return firstVertex;
    }

    static void applyState(const PeerDraw& d) {
        // Front face: see the derivation at the top of this file.
        glFrontFace(d.frontCounterClockwise ? GL_CW : GL_CCW);
        if (d.cull == Cull::None) {
            glDisable(GL_CULL_FACE);
        } else {
            glEnable(GL_CULL_FACE);
            glCullFace(d.cull == Cull::Back ? GL_BACK : GL_FRONT);
        }
        if (d.depthClipEnable) glDisable(GL_DEPTH_CLAMP); else glEnable(GL_DEPTH_CLAMP);

        if (d.depthEnable) {
            glEnable(GL_DEPTH_TEST);
            glDepthFunc(toGl(d.depthFunc));
            glDepthMask(d.depthWrite ? GL_TRUE : GL_FALSE);
        } else {
            glDisable(GL_DEPTH_TEST);   // D3D: test passes, nothing written; GL the same
        }

        if (d.stencilEnable) {
            glEnable(GL_STENCIL_TEST);
            const auto setFace = [&](GLenum glFace, const StencilFace& f) {
                glStencilFuncSeparate(glFace, toGl(f.func), d.stencilRef, d.stencilReadMask);
                glStencilOpSeparate(glFace, toGl(f.failOp), toGl(f.depthFailOp), toGl(f.passOp));
                glStencilMaskSeparate(glFace, d.stencilWriteMask);
            };
            setFace(GL_FRONT, d.front);   // GL front == D3D front (glFrontFace above)
            setFace(GL_BACK, d.back);
        } else {
            glDisable(GL_STENCIL_TEST);
        }

        const auto bit = [&](int b) -> GLboolean { return d.colorWrite && (d.colorWriteMask & b) != 0 ? GL_TRUE : GL_FALSE; };
        glColorMask(bit(1), bit(2), bit(4), bit(8));
        if (d.additiveBlend) {
            glEnable(GL_BLEND);
            glBlendEquation(GL_FUNC_ADD);
            glBlendFunc(GL_ONE, GL_ONE);
        } else if (d.blend.enable) {
            glEnable(GL_BLEND);
            glBlendEquationSeparate(toGl(d.blend.op), toGl(d.blend.opAlpha));
            glBlendFuncSeparate(toGl(d.blend.src), toGl(d.blend.dst), toGl(d.blend.srcAlpha), toGl(d.blend.dstAlpha));
            glBlendColor(d.blendFactor[0], d.blendFactor[1], d.blendFactor[2], d.blendFactor[3]);
        } else {
            glDisable(GL_BLEND);
        }
        if (d.scissorEnable) {
            // D3D rows == GL memory rows (top of file): no flip.
            glEnable(GL_SCISSOR_TEST);
            glScissor(d.scissor[0], d.scissor[1], std::max(0, d.scissor[2] - d.scissor[0]), std::max(0, d.scissor[3] - d.scissor[1]));
        } else {
            glDisable(GL_SCISSOR_TEST);
        }
    }

    void clear(const PeerFrame& frame) const {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, frame.width, frame.height);
        // Clears obey the write masks, so reset them after the previous frame's draws.
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthMask(GL_TRUE);
        glStencilMask(0xFF);
        glDisable(GL_SCISSOR_TEST);   // clears obey the scissor too
        if (frame.samples > 1) glEnable(GL_MULTISAMPLE); else glDisable(GL_MULTISAMPLE);
        glClearColor(frame.clearColor[0], frame.clearColor[1], frame.clearColor[2], frame.clearColor[3]);
        glClearDepth(static_cast<double>(frame.clearDepth));
        glClearStencil(frame.clearStencil);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    }

    void drawAll(const PeerFrame& frame, const std::vector<GLint>& firstVertex) const {
        glUseProgram(program);
        glBindVertexArray(vao);
        for (std::size_t i = 0; i < frame.draws.size(); ++i) {
            const PeerDraw& d = frame.draws[i];
            if (d.posClip.empty()) continue;
            applyState(d);
            glDrawArrays(GL_TRIANGLES, firstVertex[i], static_cast<GLsizei>(d.posClip.size()));
        }
    }

    void destroy() {
        if (ctx != EGL_NO_CONTEXT) {
            if (eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx) == EGL_TRUE) {
                glDeleteQueries(1, &query);
                deleteFramebuffer();
                glDeleteProgram(resolveColorDepthProgram);
                glDeleteProgram(resolveStencilProgram);
                glDeleteVertexArrays(1, &emptyVao);
                glDeleteBuffers(1, &vbo);
                glDeleteVertexArrays(1, &vao);
                glDeleteProgram(program);
            }
            eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(dpy, ctx);
            ctx = EGL_NO_CONTEXT;
        }
        if (dpy != EGL_NO_DISPLAY) {
            if (--gLivePeers == 0) eglTerminate(dpy);
            dpy = EGL_NO_DISPLAY;
        }
    }
};

GlPeer::GlPeer() : mImpl(new Impl) {}
GlPeer::GlPeer(GlPeer&& other) noexcept : mImpl(std::exchange(other.mImpl, nullptr)) {}
GlPeer& GlPeer::operator=(GlPeer&& other) noexcept {
    if (this != &other) {
        if (mImpl != nullptr) {
            mImpl->destroy();
            delete mImpl;
        }
        mImpl = std::exchange(other.mImpl, nullptr);
    }
    return *this;
}
GlPeer::~GlPeer() {
    if (mImpl != nullptr) {
        mImpl->destroy();
        delete mImpl;
    }
}

std::optional<GlPeer> GlPeer::create(std::string* why) {
    const auto fail = [&](std::string reason) -> std::optional<GlPeer> {
        if (why != nullptr) *why = "gl_peer: " + std::move(reason);
        return std::nullopt;
    };

    const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (clientExts == nullptr || std::strstr(clientExts, "EGL_MESA_platform_surfaceless") == nullptr) {
        return fail("EGL client extension EGL_MESA_platform_surfaceless missing (is libegl-mesa0 installed?)");
    }
    const auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (getPlatformDisplay == nullptr) return fail("eglGetPlatformDisplayEXT not available");

    GlPeer peer;
    Impl& im = *peer.mImpl;
    im.dpy = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (im.dpy == EGL_NO_DISPLAY) return fail(eglFailure("eglGetPlatformDisplayEXT(SURFACELESS_MESA)"));
    EGLint major = 0, minor = 0;
    if (eglInitialize(im.dpy, &major, &minor) != EGL_TRUE) {
        im.dpy = EGL_NO_DISPLAY;
        return fail(eglFailure("eglInitialize") + " (is libgl1-mesa-dri installed?)");
    }
    ++gLivePeers;   // from here on destroy() balances it
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) return fail(eglFailure("eglBindAPI(EGL_OPENGL_API)"));
    const EGLint contextAttribs[] = {
        EGL_CONTEXT_MAJOR_VERSION, 4,
        EGL_CONTEXT_MINOR_VERSION, 5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
        EGL_NONE,
    };
    im.ctx = eglCreateContext(im.dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, contextAttribs);
    if (im.ctx == EGL_NO_CONTEXT) return fail(eglFailure("eglCreateContext(GL 4.5 core, no config)"));
    if (eglMakeCurrent(im.dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, im.ctx) != EGL_TRUE) {
        return fail(eglFailure("eglMakeCurrent(no surface)"));
    }

    const auto* rendererStr = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    im.rendererName = rendererStr != nullptr ? rendererStr : "";

    std::string log;
    im.program = linkProgram(kVertexShader, kFragmentShader, &log);
    if (im.program == 0) return fail(log);
    im.resolveColorDepthProgram = linkProgram(kResolveVertexShader, kResolveColorDepthShader, &log);
    if (im.resolveColorDepthProgram == 0) return fail(log);
    im.resolveStencilProgram = linkProgram(kResolveVertexShader, kResolveStencilShader, &log);
    if (im.resolveStencilProgram == 0) return fail(log);
    glCreateVertexArrays(1, &im.emptyVao);

    glCreateBuffers(1, &im.vbo);
    glCreateVertexArrays(1, &im.vao);
    constexpr auto stride = static_cast<GLsizei>(kFloatsPerVertex * sizeof(float));
    glVertexArrayVertexBuffer(im.vao, 0, im.vbo, 0, stride);
    glEnableVertexArrayAttrib(im.vao, 0);
    glVertexArrayAttribFormat(im.vao, 0, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(im.vao, 0, 0);
    glEnableVertexArrayAttrib(im.vao, 1);
    glVertexArrayAttribFormat(im.vao, 1, 4, GL_FLOAT, GL_FALSE, static_cast<GLuint>(4 * sizeof(float)));
    glVertexArrayAttribBinding(im.vao, 1, 0);
    glCreateQueries(GL_SAMPLES_PASSED, 1, &im.query);

    // Frame-independent state: D3D clip volume and depth range, no dithering (multisampling and
    // the scissor are set per frame and per draw).
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthRange(0.0, 1.0);
    glDisable(GL_DITHER);
    glDisable(GL_MULTISAMPLE);
    glDisable(GL_SCISSOR_TEST);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
        return fail("GL error " + std::to_string(e) + " during setup");
    }
    return std::optional<GlPeer>(std::move(peer));
}

std::string GlPeer::renderer() const { return mImpl != nullptr ? mImpl->rendererName : std::string(); }

PeerImage GlPeer::render(const PeerFrame& frame) {
    Impl& im = *mImpl;
    im.makeCurrent();
    im.ensureFramebuffer(frame.width, frame.height, frame.depthFormat, frame.samples);
    const std::vector<GLint> firstVertex = im.upload(frame);

    im.clear(frame);
    glBeginQuery(GL_SAMPLES_PASSED, im.query);
    im.drawAll(frame, firstVertex);
    glEndQuery(GL_SAMPLES_PASSED);
    throwOnGlError("render");

    PeerImage img;
    img.width = frame.width;
    img.height = frame.height;
    img.samples = frame.samples;
    const auto pixels = static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height);
    const std::size_t count = pixels * static_cast<std::size_t>(frame.samples);
    const bool d24 = frame.depthFormat == DepthFormat::D24S8;
    img.rgba8.resize(count * 4);
    img.depth.resize(count);
    img.stencil.resize(count);
    if (d24) img.depthCode.resize(count);
    GLuint64 samples = 0;
    glGetQueryObjectui64v(im.query, GL_QUERY_RESULT, &samples);
    img.samplesPassed = samples;
    if (frame.samples > 1) {
        img.depthCodeExact = !d24;
        im.readSamples(img);
        throwOnGlError("read-back");
        return img;
    }
    // GL memory row r == D3D row r (see top of file): read without flipping.
    glBindFramebuffer(GL_READ_FRAMEBUFFER, im.fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, frame.width, frame.height, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba8.data());
    if (d24) {
        // GL_UNSIGNED_INT depth is the 24-bit code c rescaled to 32-bit unorm,
        // round(c * (2^32 - 1) / (2^24 - 1)) = c * 256 + c / 65793 (Mesa replicates the top bits):
        // either way the top 24 bits are c exactly, since c / 65793 < 256.
        std::vector<GLuint> z32(pixels);
        glReadPixels(0, 0, frame.width, frame.height, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, z32.data());
        for (std::size_t i = 0; i < pixels; ++i) {
            img.depthCode[i] = z32[i] >> 8;
            img.depth[i] = static_cast<float>(double(img.depthCode[i]) / 16777215.0);
        }
    } else {
        glReadPixels(0, 0, frame.width, frame.height, GL_DEPTH_COMPONENT, GL_FLOAT, img.depth.data());
    }
    glReadPixels(0, 0, frame.width, frame.height, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, img.stencil.data());
    throwOnGlError("read-back");
    return img;
}

double GlPeer::timeRender(const PeerFrame& frame, int repeats) {
    Impl& im = *mImpl;
    im.makeCurrent();
    im.ensureFramebuffer(frame.width, frame.height, frame.depthFormat, frame.samples);
    const std::vector<GLint> firstVertex = im.upload(frame);
    const auto once = [&] {
        im.clear(frame);
        im.drawAll(frame, firstVertex);
        glFinish();
    };
    once();   // warm-up: shader JIT, first-touch of the framebuffer
    throwOnGlError("timeRender warm-up");
    std::vector<double> seconds;
    const int n = std::max(repeats, 1);
    seconds.reserve(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        once();
        const auto t1 = std::chrono::steady_clock::now();
        seconds.push_back(std::chrono::duration<double>(t1 - t0).count());
    }
    throwOnGlError("timeRender");
    std::sort(seconds.begin(), seconds.end());
    const std::size_t mid = seconds.size() / 2;
    return seconds.size() % 2 == 1 ? seconds[mid] : 0.5 * (seconds[mid - 1] + seconds[mid]);
}

} // namespace tessera::peer
