// EGL surfaceless + GL 4.5 core context creation for the same-frame benchmark (the recipe of the
// llvmpipe peer, tests/peer/gl_peer.cpp): EGL_MESA_platform_surfaceless display, no config, no
// surface; the display is terminated with the context so the next one re-reads LP_NUM_THREADS.
#include "gl_context.h"

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace tessera::samefr {
namespace {

[[noreturn]] void eglFail(const char* what) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(eglGetError()));
    throw std::runtime_error(std::string("same_frame: ") + what + " failed (EGL error " + code + ")");
}

} // namespace

GlContext::GlContext(unsigned threads) {
    setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
    const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (clientExts == nullptr || std::strstr(clientExts, "EGL_MESA_platform_surfaceless") == nullptr)
        throw std::runtime_error("same_frame: EGL_MESA_platform_surfaceless missing (install libegl-mesa0)");
    const auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (getPlatformDisplay == nullptr) throw std::runtime_error("same_frame: eglGetPlatformDisplayEXT missing");
    EGLDisplay dpy = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (dpy == EGL_NO_DISPLAY) eglFail("eglGetPlatformDisplayEXT(SURFACELESS_MESA)");
    EGLint major = 0, minor = 0;
    if (eglInitialize(dpy, &major, &minor) != EGL_TRUE) eglFail("eglInitialize (install libgl1-mesa-dri)");
    mDisplay = dpy;
    try {
        if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) eglFail("eglBindAPI(EGL_OPENGL_API)");
        const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                  EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        EGLContext ctx = eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
        if (ctx == EGL_NO_CONTEXT) eglFail("eglCreateContext(GL 4.5 core)");
        mContext = ctx;
        if (eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx) != EGL_TRUE) eglFail("eglMakeCurrent");
    } catch (...) {
        release();  // the destructor does not run for a throwing constructor
        throw;
    }
    const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    mRenderer = name ? name : "";
}

void GlContext::release() {
    auto* dpy = static_cast<EGLDisplay>(mDisplay);
    if (mContext != nullptr) {
        eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(dpy, static_cast<EGLContext>(mContext));
        mContext = nullptr;
    }
    if (dpy != nullptr) eglTerminate(dpy);  // the next display re-reads LP_NUM_THREADS
    mDisplay = nullptr;
}

GlContext::~GlContext() { release(); }

} // namespace tessera::samefr
