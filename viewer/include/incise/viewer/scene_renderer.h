// Draws the scene with OpenGL 3.3 core: the tissue (SurfaceModel: smooth-shaded skin, the wound's walls
// flat-shaded in their own colour, optionally as a wireframe), the scalpel from the tool's pose, the contact
// point and the force vector; and renders it into an off-screen framebuffer to read the pixels back.
//
// The tissue's buffers are updated from SurfaceModel::dirty(): runs of changed vertices and faces are
// uploaded (glBufferSubData), a whole buffer only after a reset or when it must grow. The face kinds are a
// buffer texture read by gl_PrimitiveID, so one draw call colours walls and skin apart. A textured model
// (SurfaceModel::textured()) with images set (setTextures) is drawn through a second program: a geometry
// stage fetches each face's corners' texture coordinates (3 RG texels a face) and its material from two
// more buffer textures, and the skin (its material's layer of an array texture) and the walls take their
// images' texels (mipmapped, repeating) instead of the plain colours;
// it costs 11-32% of the frame rate on Mesa's llvmpipe (docs/benchmarks.md).
// Colours (linear RGB, also what the pixel tests look for): kSkinColour, kWallColour, kBackground.
// Threads: the thread whose context is current (GlContext). Cost: upload O(changed elements), draw O(F) on
// the GPU. Failure: ViewerError for a shader that does not compile or link (with the driver's log) and an
// incomplete framebuffer; otherwise nothing throws but std::bad_alloc.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/viewer/camera.h"
#include "incise/viewer/png_file.h"
#include "incise/viewer/surface_model.h"

namespace incise::viewer {

inline constexpr std::array<float, 3> kSkinColour = {0.93f, 0.72f, 0.62f};
inline constexpr std::array<float, 3> kWallColour = {0.80f, 0.08f, 0.10f};
inline constexpr std::array<float, 3> kBackground = {0.13f, 0.14f, 0.17f};

// The tool as drawn: the blade points along the tool's local -z from the handle to the tip (the pose's
// position), its edge facing local +x (as sim::World uses it).
struct ToolView {
  bool show = true;
  Eigen::Vector3d tip_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  double blade_length_m = 0.03;
  bool contact = false;
  Eigen::Vector3d contact_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_N = Eigen::Vector3d::Zero();
  double metres_per_newton = 0.004;  // the force vector's drawn length
};

// The images a textured tissue is drawn with: its skin's, one per material (skins[i] on the faces of the
// tissue's material i; skins[0] also on faces without one), and its walls'.
struct TissueImages {
  std::vector<RgbImage> skins;
  RgbImage wall;
};

struct DrawOptions {
  bool wireframe = false;
  // Triangles drawn over the tissue, 9 floats per vertex (position m, normal, linear RGB): a training plan
  // (plan_overlay.h). Empty: none.
  std::vector<float> overlay;
};

class SceneRenderer {
 public:
  SceneRenderer();  // a current GL 3.3 core context is needed
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  // Uploads what changed in `model` since its last clearDirty(), then clears it.
  void upload(SurfaceModel& model);
  // The skins' and the walls' images (8-bit RGB, any size: the skins are resampled to the largest among
  // them, as layers of one array; mipmaps made here), drawn on a model with texture coordinates; until
  // then, and on a model without them, the plain colours are. O(pixels). ViewerError for no skin image or
  // an image whose pixels do not match its size.
  void setTextures(const TissueImages& images);
  // Whether the model last uploaded is drawn with the images.
  bool drawsTextures() const noexcept;
  // Clears and draws into the bound framebuffer's `width` x `height` viewport.
  void draw(const Camera& camera, int width, int height, const ToolView& tool, const DrawOptions& options);
  // Draws into an off-screen framebuffer of that size and returns its pixels: RGB, 8 bits each, rows top
  // to bottom. The window's framebuffer is bound again afterwards.
  std::vector<std::uint8_t> renderPixels(const Camera& camera, int width, int height, const ToolView& tool,
                                         const DrawOptions& options);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace incise::viewer
