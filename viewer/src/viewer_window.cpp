#include "incise/viewer/viewer_window.h"

#include <chrono>
#include <cmath>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "hud_panel.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/viewer/gl_context.h"
#include "incise/viewer/picture.h"
#include "incise/viewer/plan_overlay.h"
#include "incise/viewer/png_file.h"
#include "incise/viewer/scene_renderer.h"
#include "incise/viewer/skin_embedding.h"
#include "incise/viewer/surface_model.h"

namespace incise::viewer {

namespace {

std::int64_t nowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Keys and the wheel arrive through GLFW callbacks (chained by ImGui's backend): kept until frame() reads.
struct CursorEvent {
  double x_px, y_px;
  bool left;
  double time_s;
};

struct Input {
  double scroll = 0.0;
  // The scalpel's cursor events (incise train): recorded when `clock` is set, taken by frame().
  const std::function<double()>* clock = nullptr;
  std::vector<CursorEvent> cursor;
  bool pause = false, restart = false, wireframe = false, screenshot = false, reset = false, close = false,
       tets = false;
};

void onKey(GLFWwindow* window, int key, int, int action, int) {
  if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
  auto* in = static_cast<Input*>(glfwGetWindowUserPointer(window));
  switch (key) {
    case GLFW_KEY_SPACE:
    case GLFW_KEY_P:
      in->pause = true;
      break;
    case GLFW_KEY_R:
      in->restart = true;
      break;
    case GLFW_KEY_W:
      in->wireframe = true;
      break;
    case GLFW_KEY_T:
      in->tets = true;
      break;
    case GLFW_KEY_S:
    case GLFW_KEY_F12:
      in->screenshot = true;
      break;
    case GLFW_KEY_C:
    case GLFW_KEY_HOME:
      in->reset = true;
      break;
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q:
      in->close = true;
      break;
    default:
      break;
  }
}

void recordCursor(GLFWwindow* window) {
  auto* in = static_cast<Input*>(glfwGetWindowUserPointer(window));
  if (!in->clock || !*in->clock || ImGui::GetIO().WantCaptureMouse) return;
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(window, &x, &y);
  in->cursor.push_back({x, y, glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS, (*in->clock)()});
}
void onCursor(GLFWwindow* window, double, double) { recordCursor(window); }
void onButton(GLFWwindow* window, int, int, int) { recordCursor(window); }

void onScroll(GLFWwindow* window, double, double dy) {
  if (ImGui::GetIO().WantCaptureMouse) return;
  static_cast<Input*>(glfwGetWindowUserPointer(window))->scroll += dy;
}

}  // namespace

struct ViewerWindow::Impl {
  ViewerWindowOptions options;
  GlContext context;
  GLFWwindow* window;
  std::unique_ptr<SceneRenderer> renderer;
  sim::GeometryMirror mirror;
  MouseScalpel scalpel;
  std::vector<float> plan_triangles;
  // The surface at rest; the tets' boundary (rebuilt whole, a few times a second) or, for a simulated
  // tissue, the surface as simulated (rebuilt whole at every physics step).
  SurfaceModel model, tet_model;
  SkinEmbedding skin;      // a simulated tissue's surface in its tets, embedded here
  bool skin_dirty = true;  // the surface changed since skin.update() last took it
  std::uint64_t skin_tets_version = 0;
  bool show_tets = false, drew_tets = false;
  std::int64_t last_tets_ns = 0;
  std::unique_ptr<HudModel> hud;
  ViewerFeed feed;
  sim::Snapshot snapshot;
  Camera camera;
  bool framed = false, wireframe = false;
  Input input;
  double last_x = 0.0, last_y = 0.0;
  int screenshots = 0;
  std::int64_t display_frames = 0, last_figures_ns = 0;
  HudFigures figures;
  std::vector<float> plot;
  std::string status;

  explicit Impl(const ViewerWindowOptions& o)
      : options(o),
        context(ContextKind::Window, o.size.width, o.size.height, o.title),
        window(static_cast<GLFWwindow*>(context.window())) {
    glfwSetWindowUserPointer(window, &input);
    glfwSetKeyCallback(window, onKey);
    glfwSetScrollCallback(window, onScroll);
    glfwSetCursorPosCallback(window, onCursor);
    glfwSetMouseButtonCallback(window, onButton);
    glfwSwapInterval(1);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left behind
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);  // chains to the callbacks above
    ImGui_ImplOpenGL3_Init("#version 330 core");
    renderer = std::make_unique<SceneRenderer>();
  }
  ~Impl() {
    renderer.reset();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }

  void mouse(int height);
  void follow();
  void cutWithMouse();
  DrawOptions drawOptions() const {
    DrawOptions draw;
    draw.wireframe = wireframe;
    draw.overlay = plan_triangles;
    return draw;
  }
  std::string trainingLine() const;
  void toggleTets();
  ToolView tool() const;
  void screenshot(int width, int height);
  void hudFrame();
};

void ViewerWindow::Impl::mouse(int height) {
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(window, &x, &y);
  const double dx = x - last_x, dy = y - last_y;
  last_x = x, last_y = y;
  if (ImGui::GetIO().WantCaptureMouse) return;
  const bool cutting = feed.scalpel != nullptr;  // the left button is the blade's: the right one orbits
  const bool left = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  const bool right = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  const bool shift = glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS;
  const bool ctrl = glfwGetKey(window, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS;
  const bool middle = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
  const bool pan = middle || (cutting ? right && shift : right || (left && shift));
  const bool orbit = cutting ? right : left;
  if (pan)
    camera.pan(dx, dy, height);
  else if (orbit)
    camera.orbit(dx, dy, height);
  if (input.scroll != 0.0) {
    if (cutting && !ctrl)
      scalpel.scroll(input.scroll);  // the wheel sets the blade's depth
    else
      camera.zoom(input.scroll);
    input.scroll = 0.0;
  }
}

void ViewerWindow::Impl::follow() {
  if (feed.geometry) mirror.pull(*feed.geometry);
  model.update(mirror);
  skin_dirty = skin_dirty || mirror.rebuilt() || !mirror.changedVertices().empty() || !mirror.changedFaces().empty();
  mirror.clearChanges();
  if (show_tets) {
    const sim::PhysicsState* state = feed.physics_state ? feed.physics_state() : nullptr;
    const std::int64_t now = nowNs();
    if (state != nullptr) {  // as simulated: the surface embedded in the tets, at every physics step's positions
      const sim::TetMirror& tets = mirror.tets();
      if ((skin_dirty || tets.version() != skin_tets_version) && mirror.complete() && tets.complete()) {
        skin.update(mirror);
        skin_dirty = false, skin_tets_version = tets.version();
      }
      tet_model.update(mirror, skin, *state);
    } else if (now - last_tets_ns > 200'000'000 && tet_model.update(mirror.tets())) {
      last_tets_ns = now;
    }
  }
  // The tets once their boundary is there (a simulated tissue's first frames: the skin meanwhile).
  const bool tets = show_tets && tet_model.ready();
  if (tets != drew_tets) (tets ? tet_model : model).markAllDirty();  // the renderer drew the other one
  drew_tets = tets;
  renderer->upload(tets ? tet_model : model);
  sim::Snapshot s;
  while (feed.take_snapshot && feed.take_snapshot(s)) {
    snapshot = s;
    hud->add(s);
  }
  sim::FrameTimes t;
  while (feed.times && feed.times->tryPop(t)) hud->add(t);
  if (!framed && model.ready()) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    camera = defaultCamera(model, feed.stroke_points_m, static_cast<double>(w) / std::max(h, 1), options.camera);
    framed = true;
  }
}

// T: the tets' boundary (a simulated tissue: the surface as simulated) instead of the surface at rest, and
// back (a scenario without tets: says so).
void ViewerWindow::Impl::toggleTets() {
  if (!show_tets && !mirror.tets().present()) {
    status = "no tets in this scenario (\"tets\" in its tissue)";
    return;
  }
  show_tets = !show_tets;  // follow() marks the model it switches to for a whole upload
  last_tets_ns = 0;
}

// Every cursor event since the last frame becomes a pose for the simulation (once the tissue is drawn).
void ViewerWindow::Impl::cutWithMouse() {
  if (!feed.scalpel || !model.ready()) {
    input.cursor.clear();
    return;
  }
  int w = 0, h = 0;
  glfwGetWindowSize(window, &w, &h);
  for (const CursorEvent& e : input.cursor) {
    const MouseScalpel::Poses p =
        scalpel.poses(camera, model, {e.x_px, e.y_px, std::max(w, 1), std::max(h, 1), e.left, e.time_s});
    for (int i = 0; i < p.count; ++i) feed.scalpel->push(p.pose[static_cast<std::size_t>(i)]);
  }
  input.cursor.clear();
}

// The trainee's numbers: the wheel's depth, the blade's depth in the tissue, the groove's floor where it cuts
// now, the lateral error against the plan where the blade enters, the force and the session's time.
std::string ViewerWindow::Impl::trainingLine() const {
  if (!feed.scalpel && !feed.plan) return {};
  char line[256];
  const sim::HapticState& s = snapshot.haptic;
  std::string lateral = "-";
  if (feed.plan && s.contact) {
    char value[32];
    std::snprintf(value, sizeof value, "%+.1f mm", 1e3 * sim::locate(*feed.plan, s.contact_m).lateral_m);
    lateral = value;
  }
  std::snprintf(line, sizeof line, "depth: wheel %.1f, blade %.1f, groove %.1f mm | lateral %s | %.2f N | t %.1f s",
                1e3 * scalpel.depthM(), s.contact ? 1e3 * s.penetration_m : 0.0, 1e3 * snapshot.groove_depth_m,
                lateral.c_str(), s.force_N.norm(), snapshot.t_s);
  return line;
}

ToolView ViewerWindow::Impl::tool() const {
  ToolView t;
  t.show = snapshot.frame >= 0;
  t.tip_m = snapshot.haptic.tip_m;
  t.orientation = snapshot.haptic.orientation;
  t.blade_length_m = feed.blade_length_m;
  t.contact = snapshot.haptic.contact;
  t.contact_m = snapshot.haptic.contact_m;
  if (feed.physics_state && drew_tets) {  // the tissue as simulated: the tool where the device holds it
    const sim::HapticState& h = snapshot.haptic;
    t.tip_m = h.world_tip_m;
    t.orientation = h.world_orientation;
    t.contact_m = h.world_tip_m + h.penetration_m * h.normal;  // the skin's point above the tip, about
  }
  t.force_N = snapshot.haptic.force_N;
  return t;
}

void ViewerWindow::Impl::screenshot(int width, int height) {
  const std::filesystem::path path = options.screenshot_dir / ("incise-view-" + std::to_string(++screenshots) + ".png");
  try {
    const DrawOptions draw = drawOptions();
    writePng(path, {width, height, renderer->renderPixels(camera, width, height, tool(), draw)});
    status = "wrote " + path.string();
  } catch (const std::exception& e) {
    status = std::string("screenshot failed: ") + e.what();
  }
}

void ViewerWindow::Impl::hudFrame() {
  const std::int64_t now = nowNs();
  if (now - last_figures_ns > 250'000'000) {  // a few times a second: the percentiles sort the window
    figures = hud->figures();
    plot = hud->plot(240);
    last_figures_ns = now;
  }
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  detail::HudText text;
  text.scenario = feed.scenario;
  text.gl = context.description();
  text.status = status;
  text.training = trainingLine();
  text.wireframe = wireframe;
  text.drawn = !drew_tets ? (feed.physics_state ? ", at rest" : "")
                          : (feed.physics_state ? ", as simulated" : ", the tets' boundary");
  const SurfaceModel& shown = drew_tets ? tet_model : model;
  text.triangles = shown.liveFaces();
  text.wall_triangles = shown.wallFaces();
  text.display_frames = display_frames;
  const PoseSourceStatus source = feed.source ? feed.source->status(snapshot) : PoseSourceStatus{"none", "-"};
  text.paused = source.state == "paused";
  detail::drawHudPanel(figures, source, plot, text);
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

ViewerWindow::ViewerWindow(const ViewerWindowOptions& options) : impl_(std::make_unique<Impl>(options)) {}
ViewerWindow::~ViewerWindow() = default;

void ViewerWindow::follow(const ViewerFeed& feed, sim::GeometryMirror seeded) {
  impl_->feed = feed;
  impl_->mirror = std::move(seeded);  // a default one asks the new stream for a full copy at the first pull
  impl_->model = SurfaceModel();
  impl_->tet_model = SurfaceModel();
  impl_->skin = SkinEmbedding();
  impl_->skin_dirty = true;
  impl_->skin_tets_version = 0;
  impl_->scalpel = MouseScalpel(feed.scalpel_options);
  impl_->plan_triangles = feed.plan ? planTriangles(*feed.plan) : std::vector<float>{};
  if (feed.textures) impl_->renderer->setTextures(*feed.textures);
  impl_->input.clock = feed.scalpel ? &impl_->feed.clock_s : nullptr;
  impl_->input.cursor.clear();
  impl_->show_tets = static_cast<bool>(feed.physics_state);  // a simulated tissue: as simulated
  impl_->drew_tets = false;
  impl_->hud = std::make_unique<HudModel>(feed.period_us, feed.cut_budget_us);
  impl_->snapshot = sim::Snapshot();
  impl_->framed = false;
}

ViewerRequests ViewerWindow::frame() {
  Impl& m = *impl_;
  glfwPollEvents();
  int width = 0, height = 0;
  glfwGetFramebufferSize(m.window, &width, &height);
  m.mouse(height);
  m.follow();
  m.cutWithMouse();
  ViewerRequests requests;
  requests.close = m.input.close || glfwWindowShouldClose(m.window);
  requests.restart = std::exchange(m.input.restart, false);
  requests.pause_toggled = std::exchange(m.input.pause, false);
  if (std::exchange(m.input.wireframe, false)) m.wireframe = !m.wireframe;
  if (std::exchange(m.input.tets, false)) m.toggleTets();
  if (std::exchange(m.input.reset, false)) m.camera.reset();
  const bool drawn = width > 0 && height > 0;
  if (drawn) {
    if (std::exchange(m.input.screenshot, false)) m.screenshot(width, height);
    m.renderer->draw(m.camera, width, height, m.tool(), m.drawOptions());
    m.hudFrame();
  }
  glfwSwapBuffers(m.window);
  glFinish();  // the frame is on screen (llvmpipe draws at the flush): the latency below is honest
  ++m.display_frames;
  if (drawn) m.hud->displayed(m.snapshot.frame_start_ns, nowNs());  // a snapshot counts once, when first shown
  return requests;
}

HudFigures ViewerWindow::figures() const { return impl_->hud ? impl_->hud->figures() : HudFigures{}; }
std::int64_t ViewerWindow::displayFrames() const noexcept { return impl_->display_frames; }
std::string ViewerWindow::glDescription() const { return impl_->context.description(); }

std::optional<Eigen::Vector2d> ViewerWindow::pixelOf(const Eigen::Vector3d& x_m) const {
  if (!impl_->framed) return std::nullopt;
  int w = 0, h = 0;
  glfwGetWindowSize(impl_->window, &w, &h);
  return impl_->camera.project(x_m, std::max(w, 1), std::max(h, 1));
}

}  // namespace incise::viewer
