#include "render/headless_context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstring>
#include <vector>

namespace plimsoll::editor {

namespace {

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)); p += n) {
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    }
    return false;
}

/// A 4.5 core context on `display`, current with no surface; nullptr when it cannot.
EGLContext makeContext(EGLDisplay display) {
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) return EGL_NO_CONTEXT;
    if (!eglBindAPI(EGL_OPENGL_API)) return EGL_NO_CONTEXT;
    const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    const bool noConfig =
        hasExtension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_no_config_context");
    if (!eglChooseConfig(display, configAttributes, &config, 1, &count) || count == 0) {
        if (!noConfig) return EGL_NO_CONTEXT;
        config = EGL_NO_CONFIG_KHR;
    }
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                        4,
                                        EGL_CONTEXT_MINOR_VERSION,
                                        5,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
    if (context == EGL_NO_CONTEXT) return EGL_NO_CONTEXT;
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        eglDestroyContext(display, context);
        return EGL_NO_CONTEXT;
    }
    return context;
}

}  // namespace

Result<std::unique_ptr<HeadlessContext>> HeadlessContext::create() {
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    struct Candidate {
        EGLDisplay display;
        std::string name;
    };
    std::vector<Candidate> candidates;
    if (hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
        candidates.push_back(
            {eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
             "surfaceless"});
    }
    if (hasExtension(clientExtensions, "EGL_EXT_platform_device") &&
        hasExtension(clientExtensions, "EGL_EXT_device_enumeration")) {
        EGLDeviceEXT devices[8];
        EGLint count = 0;
        if (eglQueryDevicesEXT(8, devices, &count)) {
            for (EGLint i = 0; i < count; ++i) {
                candidates.push_back(
                    {eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr),
                     "device " + std::to_string(i)});
            }
        }
    }
    candidates.push_back({eglGetDisplay(EGL_DEFAULT_DISPLAY), "default display"});
    for (const Candidate& c : candidates) {
        if (c.display == EGL_NO_DISPLAY) continue;
        EGLContext context = makeContext(c.display);
        if (context == EGL_NO_CONTEXT) continue;
        std::unique_ptr<HeadlessContext> result(new HeadlessContext());
        result->display_ = c.display;
        result->context_ = context;
        const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        result->description_ = c.name + ": " + (renderer ? renderer : "?");
        return result;
    }
    return makeError(
        ErrorKind::device,
        "no OpenGL 4.5 context through EGL (tried Mesa surfaceless, EGL devices and the default "
        "display); install Mesa's EGL (libegl-mesa0, libgl1-mesa-dri) or a GPU driver");
}

HeadlessContext::~HeadlessContext() {
    if (display_) {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (context_) eglDestroyContext(display_, context_);
        eglTerminate(display_);
    }
}

}  // namespace plimsoll::editor
