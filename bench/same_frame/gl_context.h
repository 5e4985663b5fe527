// An EGL surfaceless OpenGL 4.5 core context on Mesa llvmpipe for the same-frame benchmark, made
// with LP_NUM_THREADS set to the requested worker count (Mesa reads it when the display is
// initialised, so each thread count gets a fresh display and context, as bench/raster_bench.cpp).
#pragma once

#include <memory>
#include <string>

namespace tessera::samefr {

class GlContext {
public:
    // Sets LP_NUM_THREADS=threads, initialises the surfaceless display and makes a GL 4.5 core
    // context current on this thread. Throws std::runtime_error naming the failing EGL call.
    explicit GlContext(unsigned threads);
    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    const std::string& renderer() const { return mRenderer; }

private:
    void release();
    void* mDisplay = nullptr;
    void* mContext = nullptr;
    std::string mRenderer;
};

} // namespace tessera::samefr
