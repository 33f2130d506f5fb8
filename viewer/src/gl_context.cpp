#include "incise/viewer/gl_context.h"

#include <cstdlib>
#include <string>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace incise::viewer {

namespace {

std::string glfwLastError() {
  const char* text = nullptr;
  const int code = glfwGetError(&text);
  return code == GLFW_NO_ERROR ? std::string("no GLFW error") : std::string(text ? text : "unknown GLFW error");
}

std::string glString(GLenum name) {
  const auto* s = reinterpret_cast<const char*>(glGetString(name));
  return s ? s : "?";
}

// What the driver offers when it refuses a 3.3 core context: a context with no version asked for.
std::string offeredVersion() {
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  GLFWwindow* w = glfwCreateWindow(64, 64, "incise: probe", nullptr, nullptr);
  if (!w) return "no OpenGL context at all (" + glfwLastError() + ")";
  glfwMakeContextCurrent(w);
  const std::string offered = "OpenGL " + glString(GL_VERSION) + " on " + glString(GL_RENDERER);
  glfwMakeContextCurrent(nullptr);
  glfwDestroyWindow(w);
  return offered;
}

const char* const kNoDisplay =
    "no display: neither DISPLAY nor WAYLAND_DISPLAY is set, so no window can open. For pictures without a "
    "display use `incise render SCENARIO --out FILE.png`; to watch a run on a machine without a screen use "
    "`xvfb-run -a incise view ...`";

// DISPLAY or WAYLAND_DISPLAY is set, but no server there accepted the connection.
std::string displayRefused() {
  const char* x = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  const std::string named =
      x && *x ? "DISPLAY=" + std::string(x) : "WAYLAND_DISPLAY=" + std::string(wayland ? wayland : "");
  return "cannot open the display " + named + " (" + glfwLastError() +
         "): no server answers there, or it refused the connection (an Xvfb resetting after its last client "
         "left does: start it with -noreset). For pictures without a display unset it and use `incise render "
         "SCENARIO --out FILE.png`; to watch a run on a machine without a screen use `xvfb-run -a incise view ...`";
}

}  // namespace

bool displayAvailable() noexcept {
  const char* x = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (wayland && *wayland);
}

struct GlContext::Impl {
  GLFWwindow* window = nullptr;
  bool glfw = false;
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;

  void openWindow(ContextKind kind, int width, int height, const std::string& title);
  void openEgl();
  ~Impl();
};

void GlContext::Impl::openWindow(ContextKind kind, int width, int height, const std::string& title) {
  if (!glfwInit()) throw ViewerError(displayRefused());
  glfw = true;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, kind == ContextKind::Window ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_SAMPLES, 0);
  window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window) {
    const std::string why = glfwLastError();
    throw ViewerError("OpenGL 3.3 core profile is not available (" + why + "); the driver offers " + offeredVersion());
  }
  glfwMakeContextCurrent(window);
  if (epoxy_gl_version() < 33)
    throw ViewerError("OpenGL 3.3 core profile is not available; the driver offers OpenGL " + glString(GL_VERSION) +
                      " on " + glString(GL_RENDERER));
}

void GlContext::Impl::openEgl() {
  const auto fail = [](const std::string& what) {
    return ViewerError(std::string(kNoDisplay) + "; and no EGL either: " + what);
  };
  if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
    throw fail("EGL_MESA_platform_surfaceless is missing (install Mesa's libegl-mesa0 and libgl1-mesa-dri)");
  display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor)) throw fail("eglInitialize failed");
  if (!eglBindAPI(EGL_OPENGL_API)) throw fail("this EGL has no desktop OpenGL");
  const EGLint config_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  if (!eglChooseConfig(display, config_attributes, &config, 1, &configs) || configs < 1)
    throw fail("no EGL configuration for desktop OpenGL");
  const EGLint context_attributes[] = {
      EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
  if (context == EGL_NO_CONTEXT) {  // what is there instead: a context of no particular version
    const EGLContext any = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
    std::string offered = "no desktop OpenGL context at all";
    if (any != EGL_NO_CONTEXT && eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, any)) {
      offered = "OpenGL " + glString(GL_VERSION) + " on " + glString(GL_RENDERER);
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    if (any != EGL_NO_CONTEXT) eglDestroyContext(display, any);
    throw ViewerError("OpenGL 3.3 core profile is not available through EGL; the driver offers " + offered);
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) throw fail("eglMakeCurrent failed");
  if (epoxy_gl_version() < 33)
    throw ViewerError("OpenGL 3.3 core profile is not available; the driver offers OpenGL " + glString(GL_VERSION));
}

GlContext::Impl::~Impl() {
  if (window) glfwDestroyWindow(window);
  if (glfw) glfwTerminate();
  if (context != EGL_NO_CONTEXT) {
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
  }
  if (display != EGL_NO_DISPLAY) eglTerminate(display);
}

GlContext::GlContext(ContextKind kind, int width, int height, const std::string& title)
    : impl_(std::make_unique<Impl>()) {
  if (kind == ContextKind::Window && !displayAvailable()) throw ViewerError(kNoDisplay);
  if (displayAvailable()) {
    impl_->openWindow(kind, width, height, title);
  } else {
    impl_->openEgl();
  }
}

GlContext::~GlContext() = default;

void* GlContext::window() const noexcept { return impl_->window; }
bool GlContext::egl() const noexcept { return impl_->context != EGL_NO_CONTEXT; }
std::string GlContext::description() const { return glString(GL_VERSION) + " / " + glString(GL_RENDERER); }

}  // namespace incise::viewer
