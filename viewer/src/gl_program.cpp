#include "gl_program.h"

#include <vector>

#include "incise/viewer/gl_context.h"

namespace incise::viewer::detail {

namespace {

std::string log(GLuint object, bool program) {
  GLint length = 0;
  program ? glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length) : glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> text(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
  program ? glGetProgramInfoLog(object, length, nullptr, text.data())
          : glGetShaderInfoLog(object, length, nullptr, text.data());
  return text.data();
}

GLuint compile(const char* name, GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string text = log(shader, false);
    glDeleteShader(shader);
    throw ViewerError(std::string("the ") + name + (stage == GL_VERTEX_SHADER ? " vertex" : " fragment") +
                      " shader does not compile: " + text);
  }
  return shader;
}

}  // namespace

GLuint buildProgram(const char* name, const char* vertex_source, const char* fragment_source) {
  const GLuint vs = compile(name, GL_VERTEX_SHADER, vertex_source);
  const GLuint fs = compile(name, GL_FRAGMENT_SHADER, fragment_source);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string text = log(program, true);
    glDeleteProgram(program);
    throw ViewerError(std::string("the ") + name + " program does not link: " + text);
  }
  return program;
}

}  // namespace incise::viewer::detail
