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
    const char* kind = stage == GL_VERTEX_SHADER ? " vertex" : stage == GL_GEOMETRY_SHADER ? " geometry" : " fragment";
    throw ViewerError(std::string("the ") + name + kind + " shader does not compile: " + text);
  }
  return shader;
}

}  // namespace

GLuint buildProgram(const char* name, const char* vertex_source, const char* fragment_source,
                    const char* geometry_source) {
  std::vector<GLuint> shaders;
  try {
    shaders.push_back(compile(name, GL_VERTEX_SHADER, vertex_source));
    shaders.push_back(compile(name, GL_FRAGMENT_SHADER, fragment_source));
    if (geometry_source) shaders.push_back(compile(name, GL_GEOMETRY_SHADER, geometry_source));
  } catch (const ViewerError&) {
    for (const GLuint shader : shaders) glDeleteShader(shader);
    throw;
  }
  const GLuint program = glCreateProgram();
  for (const GLuint shader : shaders) glAttachShader(program, shader);
  glLinkProgram(program);
  for (const GLuint shader : shaders) glDeleteShader(shader);
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
