// Private: compiling and linking a GLSL program, with the driver's log in the error.
#pragma once

#include <string>

#include <epoxy/gl.h>

namespace incise::viewer::detail {

// Throws ViewerError naming `name` and quoting the compiler's or linker's log. The caller deletes it.
// `geometry_source` null: no geometry stage.
GLuint buildProgram(const char* name, const char* vertex_source, const char* fragment_source,
                    const char* geometry_source = nullptr);

}  // namespace incise::viewer::detail
