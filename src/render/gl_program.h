// Compiling and linking GLSL programs, with the driver's log in the error so a broken shader names
// itself. A stage may consist of several sources (shared functions live in their own unit).
#pragma once

#include <epoxy/gl.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace corebox {

class RenderError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct ShaderSource {
    GLenum stage;
    const char* text;
    const char* name;  // for messages
};

// Throws RenderError with the compile or link log.
GLuint buildProgram(const std::vector<ShaderSource>& sources, const std::string& programName);

}  // namespace corebox
