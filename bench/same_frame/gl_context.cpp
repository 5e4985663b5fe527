// EGL + GL 4.5 core context creation for the same-frame benchmark. Surfaceless: the recipe of the
// llvmpipe peer (tests/peer/gl_peer.cpp), EGL_MESA_platform_surfaceless display, no config, no
// surface. Device: EGL_EXT_platform_device on an enumerated device, with a pbuffer config and a
// 1x1 pbuffer only where the driver lacks EGL_KHR_no_config_context / EGL_KHR_surfaceless_context.
// The display is terminated with the context so the next one re-reads LP_NUM_THREADS.
#include "gl_context.h"

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace tessera::samefr {
namespace {

[[noreturn]] void eglFail(const std::string& what) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(eglGetError()));
    throw std::runtime_error("same_frame: " + what + " failed (EGL error " + code + ")");
}

// Whole-word match in a space-separated extension list.
bool hasExtension(const char* list, const char* name) {
    if (list == nullptr) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

template <class Fn> Fn eglProc(const char* name) {
    const auto fn = reinterpret_cast<Fn>(eglGetProcAddress(name));
    if (fn == nullptr) throw std::runtime_error(std::string("same_frame: ") + name + " missing from libEGL");
    return fn;
}

EGLDisplay surfacelessDisplay(unsigned threads) {
    setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
    const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!hasExtension(clientExts, "EGL_MESA_platform_surfaceless"))
        throw std::runtime_error("same_frame: EGL_MESA_platform_surfaceless missing (install libegl-mesa0)");
    const auto getPlatformDisplay = eglProc<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
    EGLDisplay dpy = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (dpy == EGL_NO_DISPLAY) eglFail("eglGetPlatformDisplayEXT(SURFACELESS_MESA)");
    return dpy;
}

// Software renderers among EGL devices: Mesa's llvmpipe/softpipe device names
// EGL_MESA_device_software in its extension string.
bool isSoftwareDevice(const char* deviceExts) { return hasExtension(deviceExts, "EGL_MESA_device_software"); }

EGLDisplay deviceDisplay(int wanted) {
    const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const bool base = hasExtension(clientExts, "EGL_EXT_device_base");  // = enumeration + query
    for (const char* ext : {"EGL_EXT_device_enumeration", "EGL_EXT_device_query", "EGL_EXT_platform_device"})
        if (!hasExtension(clientExts, ext) && !(base && std::strcmp(ext, "EGL_EXT_platform_device") != 0))
            throw std::runtime_error(std::string("same_frame: --gl-platform device: client extension ") + ext +
                                     " missing (libEGL is not GLVND's, or no EGL vendor library offers devices; "
                                     "EGL client extensions: " + (clientExts ? clientExts : "none") + ")");
    const auto queryDevices = eglProc<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
    const auto queryDeviceString = eglProc<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT");
    const auto getPlatformDisplay = eglProc<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
    EGLint count = 0;
    if (queryDevices(0, nullptr, &count) != EGL_TRUE) eglFail("eglQueryDevicesEXT(count)");
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
    if (count > 0 && queryDevices(count, devices.data(), &count) != EGL_TRUE) eglFail("eglQueryDevicesEXT");
    devices.resize(static_cast<std::size_t>(count));
    int chosen = -1;
    for (int i = 0; i < count; ++i) {
        const char* exts = queryDeviceString(devices[std::size_t(i)], EGL_EXTENSIONS);
        const char* drm = hasExtension(exts, "EGL_EXT_device_drm") ? queryDeviceString(devices[std::size_t(i)], EGL_DRM_DEVICE_FILE_EXT)
                                                                     : nullptr;
        const bool software = isSoftwareDevice(exts);
        std::fprintf(stderr, "EGL device %d: %s%s%s; extensions: %s\n", i, software ? "software" : "hardware",
                     drm ? ", " : "", drm ? drm : "", exts ? exts : "(none)");
        if (wanted < 0 && chosen < 0 && !software) chosen = i;
    }
    if (wanted >= 0) {
        if (wanted >= count)
            throw std::runtime_error("same_frame: --gl-device " + std::to_string(wanted) + ": only " + std::to_string(count) +
                                     " EGL device(s)");
        chosen = wanted;
    }
    if (chosen < 0)
        throw std::runtime_error("same_frame: --gl-platform device: no hardware EGL device among the " + std::to_string(count) +
                                 " found (software renderers skipped; --gl-device N picks one anyway). With NVIDIA: "
                                 "is the driver's EGL vendor file found (__EGL_VENDOR_LIBRARY_FILENAMES=.../10_nvidia.json)?");
    std::fprintf(stderr, "EGL device %d chosen\n", chosen);
    EGLDisplay dpy = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[std::size_t(chosen)], nullptr);
    if (dpy == EGL_NO_DISPLAY) eglFail("eglGetPlatformDisplayEXT(PLATFORM_DEVICE_EXT, device " + std::to_string(chosen) + ")");
    return dpy;
}

std::string glString(GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "";
}

} // namespace

GlContext::GlContext(const GlContextOptions& options) {
    const bool device = options.platform == GlPlatform::Device;
    EGLDisplay dpy = device ? deviceDisplay(options.device) : surfacelessDisplay(options.threads);
    EGLint major = 0, minor = 0;
    if (eglInitialize(dpy, &major, &minor) != EGL_TRUE)
        eglFail(device ? "eglInitialize(device display)" : "eglInitialize (install libgl1-mesa-dri)");
    mDisplay = dpy;
    try {
        const char* displayExts = eglQueryString(dpy, EGL_EXTENSIONS);
        const bool noConfig = hasExtension(displayExts, "EGL_KHR_no_config_context") ||
                              hasExtension(displayExts, "EGL_MESA_configless_context");
        const bool surfaceless = hasExtension(displayExts, "EGL_KHR_surfaceless_context");
        if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) eglFail("eglBindAPI(EGL_OPENGL_API)");
        const auto chooseConfig = [&] {
            const EGLint want[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
            EGLConfig config = nullptr;
            EGLint found = 0;
            if (eglChooseConfig(dpy, want, &config, 1, &found) != EGL_TRUE || found < 1)
                eglFail("eglChooseConfig(PBUFFER_BIT, OPENGL_BIT)");
            return config;
        };
        EGLConfig config = noConfig && surfaceless ? EGL_NO_CONFIG_KHR : chooseConfig();
        const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                  EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, attribs);
        if (ctx == EGL_NO_CONTEXT && config == EGL_NO_CONFIG_KHR) {  // configless refused: try a pbuffer config
            config = chooseConfig();
            ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, attribs);
        }
        if (ctx == EGL_NO_CONTEXT) eglFail("eglCreateContext(GL 4.5 core)");
        mContext = ctx;
        EGLSurface surface = EGL_NO_SURFACE;
        if (!surfaceless) {  // rendering goes to FBOs; the pbuffer only satisfies eglMakeCurrent
            const EGLint size[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
            surface = eglCreatePbufferSurface(dpy, config, size);
            if (surface == EGL_NO_SURFACE) eglFail("eglCreatePbufferSurface(1x1)");
            mSurface = surface;
        }
        if (eglMakeCurrent(dpy, surface, surface, ctx) != EGL_TRUE) eglFail("eglMakeCurrent");
    } catch (...) {
        release();  // the destructor does not run for a throwing constructor
        throw;
    }
    mVendor = glString(GL_VENDOR);
    mRenderer = glString(GL_RENDERER);
    mVersion = glString(GL_VERSION);
    std::fprintf(stderr, "GL_VENDOR: %s\nGL_RENDERER: %s\nGL_VERSION: %s\n", mVendor.c_str(), mRenderer.c_str(), mVersion.c_str());
}

void GlContext::release() {
    auto* dpy = static_cast<EGLDisplay>(mDisplay);
    if (mContext != nullptr) {
        eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(dpy, static_cast<EGLContext>(mContext));
        mContext = nullptr;
    }
    if (mSurface != nullptr) {
        eglDestroySurface(dpy, static_cast<EGLSurface>(mSurface));
        mSurface = nullptr;
    }
    if (dpy != nullptr) eglTerminate(dpy);  // the next display re-reads LP_NUM_THREADS
    mDisplay = nullptr;
}

GlContext::~GlContext() { release(); }

} // namespace tessera::samefr
