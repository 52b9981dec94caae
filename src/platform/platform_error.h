// PlatformError: the window system or the GL context could not be had (no display, no EGL device,
// GL below 4.5, a toolkit that failed to start). Its own header so that the frame loops and the
// error report can name it without pulling in EGL or GLFW; the command line reports it as a device
// error (exit code 4).
#pragma once

#include <stdexcept>

namespace corebox {

class PlatformError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace corebox
