// An EGL OpenGL 4.5 core context for the same-frame benchmark, on one of two platforms:
// - surfaceless (EGL_MESA_platform_surfaceless): Mesa llvmpipe, made with LP_NUM_THREADS set to
//   the requested worker count (Mesa reads it when the display is initialised, so each thread
//   count gets a fresh display and context, as bench/raster_bench.cpp);
// - device (EGL_EXT_platform_device): a GPU driver's display on an enumerated EGL device (e.g.
//   NVIDIA's, headless), chosen by index or as the first device that is not a software renderer.
// Rendering goes to FBOs either way: no window, no surface unless the driver lacks
// EGL_KHR_surfaceless_context (then a 1x1 pbuffer is current, never drawn to).
#pragma once

#include <string>

namespace tessera::samefr {

enum class GlPlatform { Surfaceless, Device };

struct GlContextOptions {
    GlPlatform platform = GlPlatform::Surfaceless;
    int device = -1;        // Device: index into eglQueryDevicesEXT's list; -1: first non-software one
    unsigned threads = 1;   // Surfaceless: LP_NUM_THREADS
};

class GlContext {
public:
    // Initialises the display and makes a GL 4.5 core context current on this thread; prints
    // GL_VENDOR / GL_RENDERER / GL_VERSION (and the EGL device chosen) to stderr. Throws
    // std::runtime_error naming the failing EGL call.
    explicit GlContext(const GlContextOptions& options);
    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    const std::string& vendor() const { return mVendor; }
    const std::string& renderer() const { return mRenderer; }
    const std::string& version() const { return mVersion; }

private:
    void release();
    void* mDisplay = nullptr;
    void* mContext = nullptr;
    void* mSurface = nullptr;
    std::string mVendor, mRenderer, mVersion;
};

} // namespace tessera::samefr
