#include "egl_headless_context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace corebox {
namespace {

struct DeviceInfo {
    EGLDeviceEXT device = nullptr;
    int index = 0;
    int cudaDevice = -1;
    bool software = false;
    std::string drmFile;
};

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const std::string all = std::string(" ") + list + " ";
    return all.find(std::string(" ") + name + " ") != std::string::npos;
}

std::vector<DeviceInfo> enumerateDevices(std::string& why) {
    std::vector<DeviceInfo> out;
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!clientExtensions) {
        why = "EGL could not be loaded or has no vendor library (libegl1 missing, or no EGL vendor: on NVIDIA check "
              "that __EGL_VENDOR_LIBRARY_FILENAMES names the NVIDIA EGL vendor file, e.g. 10_nvidia.json; with Mesa "
              "install libegl-mesa0)";
        return out;
    }
    if (!hasExtension(clientExtensions, "EGL_EXT_device_enumeration") && !hasExtension(clientExtensions, "EGL_EXT_device_base")) {
        why = "EGL has no device enumeration (EGL_EXT_device_enumeration)";
        return out;
    }
    EGLint count = 0;
    if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) {
        why = "EGL reports no devices";
        return out;
    }
    std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
    eglQueryDevicesEXT(count, devices.data(), &count);
    for (EGLint i = 0; i < count; ++i) {
        DeviceInfo info;
        info.device = devices[size_t(i)];
        info.index = int(i);
        const char* ext = eglQueryDeviceStringEXT(info.device, EGL_EXTENSIONS);
        info.software = hasExtension(ext, "EGL_MESA_device_software");
        if (hasExtension(ext, "EGL_NV_device_cuda")) {
            EGLAttrib cuda = -1;
            if (eglQueryDeviceAttribEXT(info.device, EGL_CUDA_DEVICE_NV, &cuda)) info.cudaDevice = int(cuda);
        }
        if (hasExtension(ext, "EGL_EXT_device_drm")) {
            const char* file = eglQueryDeviceStringEXT(info.device, EGL_DRM_DEVICE_FILE_EXT);
            if (file) info.drmFile = file;
        }
        out.push_back(info);
    }
    return out;
}

std::string describe(const DeviceInfo& d) {
    std::string s = "EGL device " + std::to_string(d.index) + " (";
    s += d.software ? "software" : "hardware";
    if (d.cudaDevice >= 0) s += ", CUDA device " + std::to_string(d.cudaDevice);
    if (!d.drmFile.empty()) s += ", " + d.drmFile;
    return s + ")";
}

}  // namespace

struct EglHeadlessContext::State {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
};

namespace {

// Initialises `display` and makes a GL 4.5 core context current on it; "" on success, else why not.
std::string makeCurrent(EGLDisplay display, EGLContext* context) {
    if (display == EGL_NO_DISPLAY) return "no display";
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) return "eglInitialize failed (0x" + std::to_string(eglGetError()) + ")";
    if (!eglBindAPI(EGL_OPENGL_API)) return "desktop OpenGL not supported by this EGL display";
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!eglChooseConfig(display, configAttribs, &config, 1, &configs) || configs == 0) {
        // Surfaceless contexts need no config on displays with EGL_KHR_no_config_context.
        config = EGL_NO_CONFIG_KHR;
    }
    const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    *context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
    if (*context == EGL_NO_CONTEXT) {
        eglTerminate(display);
        return "no OpenGL 4.5 core context (0x" + std::to_string(eglGetError()) + ")";
    }
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, *context)) {
        eglDestroyContext(display, *context);
        eglTerminate(display);
        *context = EGL_NO_CONTEXT;
        return "surfaceless eglMakeCurrent failed (0x" + std::to_string(eglGetError()) + ")";
    }
    if (epoxy_gl_version() < 45) {
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display, *context);
        eglTerminate(display);
        *context = EGL_NO_CONTEXT;
        return "OpenGL " + std::to_string(epoxy_gl_version()) + " is below the 4.5 needed";
    }
    return "";
}

}  // namespace

EglHeadlessContext::EglHeadlessContext(const HeadlessContextOptions& options) : m_state(std::make_unique<State>()) {
    std::string why;
    const std::vector<DeviceInfo> devices = enumerateDevices(why);
    std::string attempts;
    auto tryDisplay = [&](EGLDisplay display, const std::string& what, const DeviceInfo* device) {
        const std::string failure = makeCurrent(display, &m_state->context);
        if (failure.empty()) {
            m_state->display = display;
            m_description = what + ", " + reinterpret_cast<const char*>(glGetString(GL_RENDERER)) + ", OpenGL " +
                            reinterpret_cast<const char*>(glGetString(GL_VERSION));
            if (device) {
                m_cudaDevice = device->cudaDevice;
                m_software = device->software;
            }
            return true;
        }
        attempts += "\n  " + what + ": " + failure;
        return false;
    };
    auto deviceDisplay = [](const DeviceInfo& d) { return eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, d.device, nullptr); };

    if (options.cudaDevice >= 0) {
        std::string found;
        for (const DeviceInfo& d : devices) {
            found += "\n  " + describe(d);
            if (d.cudaDevice == options.cudaDevice && tryDisplay(deviceDisplay(d), describe(d), &d)) return;
        }
        throw PlatformError("no EGL device drives CUDA device " + std::to_string(options.cudaDevice) +
                            (devices.empty() ? ": " + why : "; EGL devices found:" + found) + attempts);
    }
    if (!options.softwareOnly) {
        for (const DeviceInfo& d : devices) {
            if (!d.software && tryDisplay(deviceDisplay(d), describe(d), &d)) return;
        }
    }
    for (const DeviceInfo& d : devices) {
        if (d.software && tryDisplay(deviceDisplay(d), describe(d), &d)) return;
    }
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
        DeviceInfo surfaceless;
        surfaceless.software = true;
        if (tryDisplay(eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                       "Mesa surfaceless platform", &surfaceless)) {
            return;
        }
    }
    throw PlatformError("no usable EGL device for headless OpenGL 4.5" + (why.empty() ? std::string() : ": " + why) +
                        (attempts.empty() ? std::string() : "; tried:" + attempts) +
                        "\n  check that an EGL vendor is installed: with NVIDIA, the driver's EGL vendor file (10_nvidia.json, "
                        "named by __EGL_VENDOR_LIBRARY_FILENAMES if it is not in /usr/share/glvnd/egl_vendor.d); without a GPU, "
                        "Mesa's libegl-mesa0 and libgl1-mesa-dri");
}

EglHeadlessContext::~EglHeadlessContext() {
    if (m_state->display != EGL_NO_DISPLAY) {
        eglMakeCurrent(m_state->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (m_state->context != EGL_NO_CONTEXT) eglDestroyContext(m_state->display, m_state->context);
        eglTerminate(m_state->display);
    }
}

}  // namespace corebox
