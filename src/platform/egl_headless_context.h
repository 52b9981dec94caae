// Headless OpenGL 4.5 core context through EGL, for frame dumping and tests without a display.
//
// Device choice: with a CUDA device requested, the EGL device whose EGL_CUDA_DEVICE_NV equals it
// (EGL enumerates devices in its own order, and CUDA_VISIBLE_DEVICES does not apply to EGL);
// otherwise the first hardware device; then Mesa's software device (llvmpipe) or surfaceless
// platform. Rendering goes to an FBO (render/offscreen_target.h): the context has no surface.
// When nothing works the error says why, attempt by attempt.
#pragma once

#include <memory>
#include <string>

#include "platform_error.h"

namespace corebox {

struct HeadlessContextOptions {
    int cudaDevice = -1;         // >= 0: the EGL device driving this CUDA device, or an error
    bool softwareOnly = false;   // skip hardware devices (reproducible images in tests)
};

class EglHeadlessContext {
public:
    // Creates the context and makes it current on the calling thread. Throws PlatformError.
    explicit EglHeadlessContext(const HeadlessContextOptions& options = {});
    ~EglHeadlessContext();
    EglHeadlessContext(const EglHeadlessContext&) = delete;
    EglHeadlessContext& operator=(const EglHeadlessContext&) = delete;

    // "EGL device 1 (software, llvmpipe (LLVM 15.0.6, 256 bits)), OpenGL 4.5 (Core Profile) Mesa ..."
    const std::string& description() const { return m_description; }
    int cudaDevice() const { return m_cudaDevice; }  // -1 when unknown
    bool software() const { return m_software; }

private:
    struct State;
    std::unique_ptr<State> m_state;
    std::string m_description;
    int m_cudaDevice = -1;
    bool m_software = false;
};

}  // namespace corebox
