#include "incise/viewer/scene_renderer.h"

#include <algorithm>
#include <cmath>
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

// A textured tissue: each face's corners' texture coordinates fetched by its index (3 RG texels a face),
// and its material's layer of the skins' array (layer 0 for a face without one, or past the layers).
const char* const kSurfaceGeometry = R"(#version 330 core
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
uniform samplerBuffer texcoords;
uniform usamplerBuffer materials;
uniform int skin_layers;
in vec3 v_normal[];
in vec3 v_position[];
out vec3 f_normal;
out vec3 f_position;
out vec2 f_uv;
flat out float f_layer;
void main() {
  int material = int(texelFetch(materials, gl_PrimitiveIDIn).r);
  float layer = material < skin_layers ? float(material) : 0.0;
  for (int i = 0; i < 3; ++i) {
    f_normal = v_normal[i];
    f_position = v_position[i];
    f_uv = texelFetch(texcoords, 3 * gl_PrimitiveIDIn + i).rg;
    f_layer = layer;
    gl_PrimitiveID = gl_PrimitiveIDIn;
    gl_Position = gl_in[i].gl_Position;
    EmitVertex();
  }
  EndPrimitive();
})";

// Walls (kind 2) flat from the triangle itself, skin smooth; a headlight with a little specular. The base
// colour is the skin's or the walls' colour, or (TEXTURED, after the geometry stage) their image's texel.
// Compiled after kPlainPrefix or kTexturedPrefix.
const char* const kSurfaceFragment = R"(
uniform usamplerBuffer kinds;
uniform vec3 skin;
uniform vec3 wall;
uniform int wireframe;
#ifdef TEXTURED
uniform sampler2DArray skin_texture;
uniform sampler2D wall_texture;
in vec2 f_uv;
flat in float f_layer;
#endif
in vec3 f_normal;
in vec3 f_position;
out vec4 colour;
void main() {
  uint kind = texelFetch(kinds, gl_PrimitiveID).r;
  vec3 flat_normal = normalize(cross(dFdx(f_position), dFdy(f_position)));
  vec3 n = kind == 2u ? flat_normal : (length(f_normal) > 0.0 ? normalize(f_normal) : flat_normal);
  if (dot(n, -f_position) < 0.0) n = -n;
  vec3 base = kind == 2u ? wall : skin;
#ifdef TEXTURED
  vec3 skin_texel = texture(skin_texture, vec3(f_uv, f_layer)).rgb;  // both sampled: uniform control flow
  vec3 wall_texel = texture(wall_texture, f_uv).rgb;
  base = kind == 2u ? wall_texel : skin_texel;
#endif
  vec3 to_eye = normalize(-f_position);
  vec3 light = normalize(to_eye + vec3(0.25, 0.35, 0.0));
  float diffuse = max(dot(n, light), 0.0);
  float specular = pow(max(dot(n, normalize(light + to_eye)), 0.0), 48.0) * 0.12;
  vec3 c = base * (0.22 + 0.78 * diffuse) + vec3(specular);
  colour = vec4(wireframe == 1 ? c * 0.55 : c, 1.0);
})";
const char* const kPlainPrefix = "#version 330 core\n#define f_normal v_normal\n#define f_position v_position\n";
const char* const kTexturedPrefix = "#version 330 core\n#define TEXTURED\n";

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

// `image` resampled to width x height (bilinear, wrapping like the texture), appended to `out`.
void appendResampled(const RgbImage& image, int width, int height, std::vector<std::uint8_t>& out) {
  if (image.width == width && image.height == height) {
    out.insert(out.end(), image.rgb.begin(), image.rgb.end());
    return;
  }
  const auto texel = [&](int x, int y, int c) {
    x = (x % image.width + image.width) % image.width, y = (y % image.height + image.height) % image.height;
    return static_cast<double>(
        image.rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)) *
                      3 +
                  static_cast<std::size_t>(c)]);
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double sx = (x + 0.5) * image.width / width - 0.5, sy = (y + 0.5) * image.height / height - 0.5;
      const int x0 = static_cast<int>(std::floor(sx)), y0 = static_cast<int>(std::floor(sy));
      const double fx = sx - x0, fy = sy - y0;
      for (int c = 0; c < 3; ++c) {
        const double top = texel(x0, y0, c) * (1 - fx) + texel(x0 + 1, y0, c) * fx;
        const double bottom = texel(x0, y0 + 1, c) * (1 - fx) + texel(x0 + 1, y0 + 1, c) * fx;
        out.push_back(static_cast<std::uint8_t>(std::lround(top * (1 - fy) + bottom * fy)));
      }
    }
}

void mipmappedRepeating(GLenum target) {
  glGenerateMipmap(target);
  glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_REPEAT);
}

// `texture` bound to unit `unit` as `target`, the program's sampler `name` pointed at it.
void bindUnit(GLuint program, int unit, GLenum target, GLuint texture, const char* name) {
  glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
  glBindTexture(target, texture);
  glUniform1i(glGetUniformLocation(program, name), unit);
}

// An image as a mipmapped, repeating 2D texture (8-bit RGB, as the file has it).
void uploadImage(GLuint texture, const RgbImage& image) {
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, image.width, image.height, 0, GL_RGB, GL_UNSIGNED_BYTE, image.rgb.data());
  mipmappedRepeating(GL_TEXTURE_2D);
}

// The images as the layers of a mipmapped, repeating 2D array texture, each resampled (bilinear, texel
// centres kept) to the largest width and height among them: texture coordinates stay where they were.
void uploadLayers(GLuint texture, const std::vector<RgbImage>& images) {
  int width = 1, height = 1;
  for (const RgbImage& image : images) width = std::max(width, image.width), height = std::max(height, image.height);
  std::vector<std::uint8_t> texels;
  texels.reserve(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3 * images.size());
  for (const RgbImage& image : images) appendResampled(image, width, height, texels);
  glBindTexture(GL_TEXTURE_2D_ARRAY, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGB8, width, height, static_cast<GLsizei>(images.size()), 0, GL_RGB,
               GL_UNSIGNED_BYTE, texels.data());
  mipmappedRepeating(GL_TEXTURE_2D_ARRAY);
}

}  // namespace

struct SceneRenderer::Impl {
  GLuint surface_program = 0, textured_program = 0, tool_program = 0;
  GLuint surface_vao = 0, tool_vao = 0, tool_vbo = 0;
  Buffer positions, normals, indices, kinds, texcoords, materials;
  GLuint kinds_texture = 0, texcoords_texture = 0, materials_texture = 0, skin_texture = 0, wall_texture = 0;
  GLint skin_layers = 0;
  GLsizei index_count = 0;
  bool model_textured = false, images = false;
  GLuint fbo = 0, colour_rb = 0, depth_rb = 0;
  int fbo_width = 0, fbo_height = 0;

  Impl();
  ~Impl();
  void uploadAll(const SurfaceModel& model);
  void uploadRuns(const SurfaceModel& model);
  void drawSurface(const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection, const DrawOptions& options);
  void bindTextures(GLuint program);
  void drawTool(const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection, const ToolView& tool);
  void drawTriangles(const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection,
                     const std::vector<float>& triangles);
  void ensureFramebuffer(int width, int height);
};

SceneRenderer::Impl::Impl() {
  surface_program =
      detail::buildProgram("surface", kSurfaceVertex, (kPlainPrefix + std::string(kSurfaceFragment)).c_str());
  textured_program = detail::buildProgram("textured surface", kSurfaceVertex,
                                          (kTexturedPrefix + std::string(kSurfaceFragment)).c_str(), kSurfaceGeometry);
  tool_program = detail::buildProgram("tool", kToolVertex, kToolFragment);
  glGenVertexArrays(1, &surface_vao);
  glGenVertexArrays(1, &tool_vao);
  for (Buffer* b : {&positions, &normals, &indices, &kinds, &texcoords, &materials}) glGenBuffers(1, &b->id);
  glGenBuffers(1, &tool_vbo);
  for (GLuint* t : {&kinds_texture, &texcoords_texture, &materials_texture, &skin_texture, &wall_texture})
    glGenTextures(1, t);
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
  for (Buffer* b : {&positions, &normals, &indices, &kinds, &texcoords, &materials}) glDeleteBuffers(1, &b->id);
  glDeleteBuffers(1, &tool_vbo);
  for (GLuint* t : {&kinds_texture, &texcoords_texture, &materials_texture, &skin_texture, &wall_texture})
    glDeleteTextures(1, t);
  glDeleteVertexArrays(1, &surface_vao);
  glDeleteVertexArrays(1, &tool_vao);
  for (const GLuint program : {surface_program, textured_program, tool_program}) glDeleteProgram(program);
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
  if (!model.textured()) return;
  fill(GL_TEXTURE_BUFFER, texcoords, model.faceTexCoords(), 6);
  glBindTexture(GL_TEXTURE_BUFFER, texcoords_texture);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_RG32F, texcoords.id);
  fill(GL_TEXTURE_BUFFER, materials, model.faceMaterials(), 1);
  glBindTexture(GL_TEXTURE_BUFFER, materials_texture);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_R8UI, materials.id);
}

void SceneRenderer::Impl::uploadRuns(const SurfaceModel& model) {
  const SurfaceModel::Dirty& d = model.dirty();
  runs(GL_ARRAY_BUFFER, positions, model.positions(), 3, d.vertices);
  runs(GL_ARRAY_BUFFER, normals, model.normals(), 3, d.vertices);
  runs(GL_ELEMENT_ARRAY_BUFFER, indices, model.indices(), 3, d.faces);
  runs(GL_TEXTURE_BUFFER, kinds, model.faceKinds(), 1, d.faces);
  if (!model.textured()) return;
  runs(GL_TEXTURE_BUFFER, texcoords, model.faceTexCoords(), 6, d.faces);
  runs(GL_TEXTURE_BUFFER, materials, model.faceMaterials(), 1, d.faces);
}

namespace {

void checkImage(const RgbImage& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw ViewerError("setTextures: an image's pixels do not match its " + std::to_string(image.width) + "x" +
                      std::to_string(image.height) + " RGB size");
}

}  // namespace

SceneRenderer::SceneRenderer() : impl_(std::make_unique<Impl>()) {}
SceneRenderer::~SceneRenderer() = default;

void SceneRenderer::upload(SurfaceModel& model) {
  if (!model.ready()) return;
  glBindVertexArray(impl_->surface_vao);  // the element buffer binding belongs to the VAO
  const bool fits = model.vertexCount() <= impl_->positions.capacity && model.faceCount() <= impl_->kinds.capacity &&
                    (!model.textured() || (model.faceCount() <= impl_->texcoords.capacity &&
                                           model.faceCount() <= impl_->materials.capacity));
  if (model.dirty().all || !fits || model.textured() != impl_->model_textured) {
    impl_->uploadAll(model);
  } else {
    impl_->uploadRuns(model);
  }
  glBindVertexArray(0);
  impl_->index_count = static_cast<GLsizei>(model.indices().size());
  impl_->model_textured = model.textured();
  model.clearDirty();
}

void SceneRenderer::setTextures(const TissueImages& images) {
  if (images.skins.empty()) throw ViewerError("setTextures: no skin image");
  checkImage(images.wall);
  for (const RgbImage& image : images.skins) checkImage(image);
  uploadLayers(impl_->skin_texture, images.skins);
  uploadImage(impl_->wall_texture, images.wall);
  glBindTexture(GL_TEXTURE_2D, 0);
  glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
  impl_->skin_layers = static_cast<GLint>(images.skins.size());
  impl_->images = true;
}

bool SceneRenderer::drawsTextures() const noexcept { return impl_->images && impl_->model_textured; }

void SceneRenderer::Impl::drawSurface(const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection,
                                      const DrawOptions& options) {
  if (index_count == 0) return;
  const GLuint program = images && model_textured ? textured_program : surface_program;
  glUseProgram(program);
  glUniformMatrix4fv(glGetUniformLocation(program, "view"), 1, GL_FALSE, view.data());
  glUniformMatrix4fv(glGetUniformLocation(program, "projection"), 1, GL_FALSE, projection.data());
  glUniform3fv(glGetUniformLocation(program, "skin"), 1, kSkinColour.data());
  glUniform3fv(glGetUniformLocation(program, "wall"), 1, kWallColour.data());
  glUniform1i(glGetUniformLocation(program, "wireframe"), options.wireframe ? 1 : 0);
  if (program == textured_program) bindTextures(program);
  bindUnit(program, 0, GL_TEXTURE_BUFFER, kinds_texture, "kinds");
  glBindVertexArray(surface_vao);
  glPolygonMode(GL_FRONT_AND_BACK, options.wireframe ? GL_LINE : GL_FILL);
  glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glBindVertexArray(0);
}

// Units 1-4: the texture coordinates' buffer, the skins' array and the walls' image, the materials' buffer.
void SceneRenderer::Impl::bindTextures(GLuint program) {
  bindUnit(program, 1, GL_TEXTURE_BUFFER, texcoords_texture, "texcoords");
  bindUnit(program, 2, GL_TEXTURE_2D_ARRAY, skin_texture, "skin_texture");
  bindUnit(program, 3, GL_TEXTURE_2D, wall_texture, "wall_texture");
  bindUnit(program, 4, GL_TEXTURE_BUFFER, materials_texture, "materials");
  glUniform1i(glGetUniformLocation(program, "skin_layers"), skin_layers);
  glActiveTexture(GL_TEXTURE0);
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
