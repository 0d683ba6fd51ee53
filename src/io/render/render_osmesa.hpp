#pragma once
// Off-screen OpenGL through Mesa's OSMesa (software rasteriser: no display, no GPU).
//
// A Renderer owns one OSMesa context with an RGBA colour buffer and a 24-bit depth buffer of
// the image size, and turns panels (scene + overlay + camera) into an RgbImage: the panels side
// by side (io/render_overlay's panel_layout), each with its 3-D view drawn by
// io/render_scene's draw_scene_gl and its text and colour bar drawn on the read-back pixels.
// The context is made current in the calling thread at every render(); one Renderer must not
// be used by two threads at once. Mesa's llvmpipe may use extra rasteriser threads
// (LP_NUM_THREADS; `codesign bench render` sets it to 1 to measure one core).
#include <memory>
#include <span>

#include "base/range.hpp"
#include "io/render/colormap.hpp"
#include "io/formats/image.hpp"
#include "io/render/render_overlay.hpp"
#include "io/render/render_scene.hpp"

namespace codesign::io {

namespace render_range {
inline constexpr Range<int> width{64, 4096};
inline constexpr Range<int> height{64, 4096};
}  // namespace render_range

struct ScenePanel {
  SceneFrame scene;
  FrameOverlay overlay;
  Camera camera;
};

struct RenderStyle {
  SceneStyle scene;
  bool overlay = true;             // text and colour bar
  Rgb background{236, 239, 244};
};

class Renderer {
 public:
  // Throws std::runtime_error if OSMesa cannot create the context, std::invalid_argument for a
  // size outside render_range.
  Renderer(int width, int height);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  // "llvmpipe (LLVM 15.0.6, 256 bits) | 4.5 (Compatibility Profile) Mesa 22.3.6"
  std::string gl_description();

  RgbImage render(std::span<const ScenePanel> panels, const ColourScale& strain, const RenderStyle& style);

 private:
  struct Context;
  std::unique_ptr<Context> ctx_;
  int width_, height_;
};

}  // namespace codesign::io
