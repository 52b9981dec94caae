#include "gl_program.h"

namespace corebox {
namespace {

std::string shaderLog(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    return log;
}

std::string programLog(GLuint program) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    return log;
}

}  // namespace

GLuint buildProgram(const std::vector<ShaderSource>& sources, const std::string& programName) {
    const GLuint program = glCreateProgram();
    std::vector<GLuint> shaders;
    for (const ShaderSource& s : sources) {
        const GLuint shader = glCreateShader(s.stage);
        glShaderSource(shader, 1, &s.text, nullptr);
        glCompileShader(shader);
        GLint ok = 0;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            const std::string log = shaderLog(shader);
            glDeleteShader(shader);
            for (GLuint other : shaders) glDeleteShader(other);
            glDeleteProgram(program);
            throw RenderError("shader " + std::string(s.name) + " failed to compile:\n" + log);
        }
        glAttachShader(program, shader);
        shaders.push_back(shader);
    }
    glLinkProgram(program);
    for (GLuint shader : shaders) glDeleteShader(shader);  // flagged; freed with the program
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        const std::string log = programLog(program);
        glDeleteProgram(program);
        throw RenderError("program " + programName + " failed to link:\n" + log);
    }
    return program;
}

}  // namespace corebox
