#include "incise/viewer/scene_renderer.h"

#include <algorithm>
#include <string>

#include <epoxy/gl.h>

#include "gl_program.h"
#include "incise/viewer/gl_context.h"
#include "incise/viewer/tool_mesh.h"

namespace incise::viewer {

namespace {

const char* const kSurfaceVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 view;
uniform mat4 projection;
out vec3 v_normal;
out vec3 v_position;
void main() {
  vec4 p = view * vec4(position, 1.0);
  v_position = p.xyz;
  v_normal = mat3(view) * normal;
  gl_Position = projection * p;
})";

// Walls (kind 2) flat from the triangle itself, skin smooth; a headlight with a little specular.
const char* const kSurfaceFragment = R"(#version 330 core
uniform usamplerBuffer kinds;
uniform vec3 skin;
uniform vec3 wall;
uniform int wireframe;
in vec3 v_normal;
in vec3 v_position;
out vec4 colour;
void main() {
  uint kind = texelFetch(kinds, gl_PrimitiveID).r;
  vec3 flat_normal = normalize(cross(dFdx(v_position), dFdy(v_position)));
  vec3 n = kind == 2u ? flat_normal : (length(v_normal) > 0.0 ? normalize(v_normal) : flat_normal);
  if (dot(n, -v_position) < 0.0) n = -n;
  vec3 base = kind == 2u ? wall : skin;
  vec3 to_eye = normalize(-v_position);
  vec3 light = normalize(to_eye + vec3(0.25, 0.35, 0.0));
  float diffuse = max(dot(n, light), 0.0);
  float specular = pow(max(dot(n, normalize(light + to_eye)), 0.0), 48.0) * 0.12;
  vec3 c = base * (0.22 + 0.78 * diffuse) + vec3(specular);
  colour = vec4(wireframe == 1 ? c * 0.55 : c, 1.0);
})";

const char* const kToolVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 rgb;
uniform mat4 view;
uniform mat4 projection;
out vec3 v_normal;
out vec3 v_rgb;
void main() {
  v_normal = mat3(view) * normal;
  v_rgb = rgb;
  gl_Position = projection * view * vec4(position, 1.0);
})";

const char* const kToolFragment = R"(#version 330 core
in vec3 v_normal;
in vec3 v_rgb;
out vec4 colour;
void main() {
  float d = abs(normalize(v_normal).z);
  colour = vec4(v_rgb * (0.35 + 0.65 * d), 1.0);
})";

struct Buffer {
  GLuint id = 0;
  std::size_t capacity = 0;  // elements
};

}  // namespace

struct SceneRenderer::Impl {
  GLuint surface_program = 0, tool_program = 0;
  GLuint surface_vao = 0, tool_vao = 0, tool_vbo = 0;
  Buffer positions, normals, indices, kinds;
  GLuint kinds_texture = 0;
  GLsizei index_count = 0;
  GLuint fbo = 0, colour_rb = 0, depth_rb = 0;
  int fbo_width = 0, fbo_height = 0;

  Impl();
  ~Impl();
  void uploadAll(const SurfaceModel& model);
  void uploadRuns(const SurfaceModel& model);
  void drawSurface(const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection, const DrawOptions& options);
  void drawTool(const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection, const ToolView& tool);
  void drawTriangles(const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection,
                     const std::vector<float>& triangles);
  void ensureFramebuffer(int width, int height);
};

SceneRenderer::Impl::Impl() {
  surface_program = detail::buildProgram("surface", kSurfaceVertex, kSurfaceFragment);
  tool_program = detail::buildProgram("tool", kToolVertex, kToolFragment);
  glGenVertexArrays(1, &surface_vao);
  glGenVertexArrays(1, &tool_vao);
  for (Buffer* b : {&positions, &normals, &indices, &kinds}) glGenBuffers(1, &b->id);
  glGenBuffers(1, &tool_vbo);
  glGenTextures(1, &kinds_texture);
  glBindVertexArray(surface_vao);
  glBindBuffer(GL_ARRAY_BUFFER, positions.id);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindBuffer(GL_ARRAY_BUFFER, normals.id);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices.id);
  glBindVertexArray(tool_vao);
  glBindBuffer(GL_ARRAY_BUFFER, tool_vbo);
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, 3, GL_FLOAT, GL_FALSE, 9 * sizeof(float), reinterpret_cast<void*>(3 * a * sizeof(float)));
  }
  glBindVertexArray(0);
}

SceneRenderer::Impl::~Impl() {
  for (Buffer* b : {&positions, &normals, &indices, &kinds}) glDeleteBuffers(1, &b->id);
  glDeleteBuffers(1, &tool_vbo);
  glDeleteTextures(1, &kinds_texture);
  glDeleteVertexArrays(1, &surface_vao);
  glDeleteVertexArrays(1, &tool_vao);
  glDeleteProgram(surface_program);
  glDeleteProgram(tool_program);
  if (fbo) glDeleteFramebuffers(1, &fbo), glDeleteRenderbuffers(1, &colour_rb), glDeleteRenderbuffers(1, &depth_rb);
}

namespace {

// The whole array into `b`, growing it by half again when it no longer fits.
template <typename T>
void fill(GLenum target, Buffer& b, const std::vector<T>& data, std::size_t per_element) {
  const std::size_t elements = data.size() / per_element;
  glBindBuffer(target, b.id);
  if (elements > b.capacity) {
    b.capacity = elements + elements / 2 + 1024;
    glBufferData(target, static_cast<GLsizeiptr>(b.capacity * per_element * sizeof(T)), nullptr, GL_DYNAMIC_DRAW);
  }
  glBufferSubData(target, 0, static_cast<GLsizeiptr>(data.size() * sizeof(T)), data.data());
}

// Runs of consecutive indices in `sorted`, each uploaded with one glBufferSubData.
template <typename T>
void runs(GLenum target, const Buffer& b, const std::vector<T>& data, std::size_t per_element,
          const std::vector<std::uint32_t>& sorted) {
  glBindBuffer(target, b.id);
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i + 1;
    while (j < sorted.size() && sorted[j] <= sorted[j - 1] + 8) ++j;  // small gaps are cheaper sent than split
    const std::size_t first = sorted[i], last = sorted[j - 1] + 1;
    glBufferSubData(target, static_cast<GLintptr>(first * per_element * sizeof(T)),
                    static_cast<GLsizeiptr>((last - first) * per_element * sizeof(T)),
                    data.data() + first * per_element);
    i = j;
  }
}

}  // namespace

void SceneRenderer::Impl::uploadAll(const SurfaceModel& model) {
  fill(GL_ARRAY_BUFFER, positions, model.positions(), 3);
  fill(GL_ARRAY_BUFFER, normals, model.normals(), 3);
  fill(GL_ELEMENT_ARRAY_BUFFER, indices, model.indices(), 3);
  fill(GL_TEXTURE_BUFFER, kinds, model.faceKinds(), 1);
  glBindTexture(GL_TEXTURE_BUFFER, kinds_texture);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_R8UI, kinds.id);
}

void SceneRenderer::Impl::uploadRuns(const SurfaceModel& model) {
  const SurfaceModel::Dirty& d = model.dirty();
  runs(GL_ARRAY_BUFFER, positions, model.positions(), 3, d.vertices);
  runs(GL_ARRAY_BUFFER, normals, model.normals(), 3, d.vertices);
  runs(GL_ELEMENT_ARRAY_BUFFER, indices, model.indices(), 3, d.faces);
  runs(GL_TEXTURE_BUFFER, kinds, model.faceKinds(), 1, d.faces);
}

SceneRenderer::SceneRenderer() : impl_(std::make_unique<Impl>()) {}
SceneRenderer::~SceneRenderer() = default;

void SceneRenderer::upload(SurfaceModel& model) {
  if (!model.ready()) return;
  glBindVertexArray(impl_->surface_vao);  // the element buffer binding belongs to the VAO
  const bool fits = model.vertexCount() <= impl_->positions.capacity && model.faceCount() <= impl_->kinds.capacity;
  if (model.dirty().all || !fits) {
    impl_->uploadAll(model);
  } else {
    impl_->uploadRuns(model);
  }
  glBindVertexArray(0);
  impl_->index_count = static_cast<GLsizei>(model.indices().size());
  model.clearDirty();
}

void SceneRenderer::Impl::drawSurface(const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection,
                                      const DrawOptions& options) {
  if (index_count == 0) return;
  glUseProgram(surface_program);
  glUniformMatrix4fv(glGetUniformLocation(surface_program, "view"), 1, GL_FALSE, view.data());
  glUniformMatrix4fv(glGetUniformLocation(surface_program, "projection"), 1, GL_FALSE, projection.data());
  glUniform3fv(glGetUniformLocation(surface_program, "skin"), 1, kSkinColour.data());
  glUniform3fv(glGetUniformLocation(surface_program, "wall"), 1, kWallColour.data());
  glUniform1i(glGetUniformLocation(surface_program, "wireframe"), options.wireframe ? 1 : 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_BUFFER, kinds_texture);
  glUniform1i(glGetUniformLocation(surface_program, "kinds"), 0);
  glBindVertexArray(surface_vao);
  glPolygonMode(GL_FRONT_AND_BACK, options.wireframe ? GL_LINE : GL_FILL);
  glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glBindVertexArray(0);
}

void SceneRenderer::Impl::drawTool(const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection,
                                   const ToolView& tool) {
  drawTriangles(view, projection, toolTriangles(tool));
}

// Lit triangles with their own colours (the tool program's layout: position, normal, RGB per vertex).
void SceneRenderer::Impl::drawTriangles(const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection,
                                        const std::vector<float>& triangles) {
  if (triangles.empty()) return;
  glUseProgram(tool_program);
  glUniformMatrix4fv(glGetUniformLocation(tool_program, "view"), 1, GL_FALSE, view.data());
  glUniformMatrix4fv(glGetUniformLocation(tool_program, "projection"), 1, GL_FALSE, projection.data());
  glBindVertexArray(tool_vao);
  glBindBuffer(GL_ARRAY_BUFFER, tool_vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(triangles.size() * sizeof(float)), triangles.data(),
               GL_STREAM_DRAW);
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles.size() / 9));
  glBindVertexArray(0);
}

void SceneRenderer::draw(const Camera& camera, int width, int height, const ToolView& tool,
                         const DrawOptions& options) {
  glViewport(0, 0, width, height);
  glClearColor(kBackground[0], kBackground[1], kBackground[2], 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  const Eigen::Matrix4f view = camera.view();
  const Eigen::Matrix4f projection = camera.projection(static_cast<double>(width) / std::max(height, 1));
  impl_->drawSurface(view, projection, options);
  impl_->drawTriangles(view, projection, options.overlay);
  impl_->drawTool(view, projection, tool);
}

void SceneRenderer::Impl::ensureFramebuffer(int width, int height) {
  if (fbo && fbo_width == width && fbo_height == height) return;
  if (!fbo) glGenFramebuffers(1, &fbo), glGenRenderbuffers(1, &colour_rb), glGenRenderbuffers(1, &depth_rb);
  glBindRenderbuffer(GL_RENDERBUFFER, colour_rb);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_rb);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_rb);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw ViewerError("the off-screen framebuffer (" + std::to_string(width) + "x" + std::to_string(height) +
                      ") is incomplete: status 0x" + std::to_string(status));
  fbo_width = width, fbo_height = height;
}

std::vector<std::uint8_t> SceneRenderer::renderPixels(const Camera& camera, int width, int height, const ToolView& tool,
                                                      const DrawOptions& options) {
  impl_->ensureFramebuffer(width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, impl_->fbo);
  draw(camera, width, height, tool, options);
  std::vector<std::uint8_t> rows(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  // OpenGL's rows go bottom to top; a picture's top to bottom.
  const std::size_t stride = static_cast<std::size_t>(width) * 3;
  for (int y = 0; y < height / 2; ++y)
    std::swap_ranges(rows.begin() + static_cast<std::ptrdiff_t>(y * stride),
                     rows.begin() + static_cast<std::ptrdiff_t>((y + 1) * stride),
                     rows.begin() + static_cast<std::ptrdiff_t>((height - 1 - y) * stride));
  return rows;
}

}  // namespace incise::viewer
