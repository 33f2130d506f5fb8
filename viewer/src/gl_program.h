// Private: compiling and linking a GLSL program, with the driver's log in the error.
#pragma once

#include <string>

#include <epoxy/gl.h>

namespace incise::viewer::detail {

// Throws ViewerError naming `name` and quoting the compiler's or linker's log. The caller deletes it.
GLuint buildProgram(const char* name, const char* vertex_source, const char* fragment_source);

}  // namespace incise::viewer::detail
