// An OpenGL 3.3 core context for the viewer: a visible GLFW window (incise view), or a hidden one for
// off-screen pictures (incise render, replay --png, the pixel tests; under Xvfb or any X display), or, with
// no display at all, a surfaceless EGL context on Mesa (llvmpipe renders without any display server).
// GL functions are loaded by libepoxy.
//
// Threads: create, use and destroy on one thread (GLFW wants the main thread for windows). Cost: creation
// tens of milliseconds. Failure: ViewerError with a message for the user: no display (and, for pictures,
// no EGL either) naming `incise render` and `xvfb-run`; no OpenGL 3.3 core, with what the driver offers.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

namespace incise::viewer {

struct ViewerError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class ContextKind {
  Window,    // a visible window: needs a display
  Offscreen  // a hidden window on the display if there is one, else EGL without any display
};

class GlContext {
 public:
  GlContext(ContextKind kind, int width, int height, const std::string& title);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // The GLFWwindow* (nullptr for EGL), as an opaque pointer: GLFW stays out of this header.
  void* window() const noexcept;
  bool egl() const noexcept;
  // GL_VERSION and GL_RENDERER, e.g. "4.5 (Core Profile) Mesa 22.3.6 / llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// True when an X11 or Wayland display is named in the environment (DISPLAY, WAYLAND_DISPLAY).
bool displayAvailable() noexcept;

}  // namespace incise::viewer
