#include "io/render/render_osmesa.hpp"

#include <GL/osmesa.h>
#include <GL/gl.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace codesign::io {

struct Renderer::Context {
  OSMesaContext gl = nullptr;
  std::vector<unsigned char> rgba;  // OSMesa's colour buffer: bottom row first
  ~Context() {
    if (gl) OSMesaDestroyContext(gl);
  }
  void make_current(int w, int h) {
    if (!OSMesaMakeCurrent(gl, rgba.data(), GL_UNSIGNED_BYTE, w, h))
      throw std::runtime_error("render: OSMesaMakeCurrent failed");
  }
};

Renderer::Renderer(int width, int height) : ctx_(std::make_unique<Context>()), width_(width), height_(height) {
  if (!render_range::width.contains(width) || !render_range::height.contains(height))
    throw std::invalid_argument("render: image size " + std::to_string(width) + "x" + std::to_string(height) +
                                " outside [64, 4096] x [64, 4096]");
  const int attribs[] = {OSMESA_FORMAT,      OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 0,
                         OSMESA_ACCUM_BITS,  0,           OSMESA_PROFILE,    OSMESA_COMPAT_PROFILE,   0};
  ctx_->gl = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!ctx_->gl) throw std::runtime_error("render: OSMesa could not create an off-screen OpenGL context");
  ctx_->rgba.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4, 0);
  ctx_->make_current(width, height);
}

Renderer::~Renderer() = default;

std::string Renderer::gl_description() {
  ctx_->make_current(width_, height_);
  const auto str = [](GLenum e) {
    const auto* s = reinterpret_cast<const char*>(glGetString(e));
    return std::string(s ? s : "?");
  };
  return str(GL_RENDERER) + " | " + str(GL_VERSION);
}

RgbImage Renderer::render(std::span<const ScenePanel> panels, const ColourScale& strain, const RenderStyle& style) {
  if (panels.empty()) throw std::invalid_argument("render: no panels");
  ctx_->make_current(width_, height_);
  glDisable(GL_SCISSOR_TEST);
  glViewport(0, 0, width_, height_);
  glClearColor(style.background.r / 255.f, style.background.g / 255.f, style.background.b / 255.f, 1.f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const int n = static_cast<int>(panels.size());
  for (int i = 0; i < n; ++i) {
    const PanelLayout layout = panel_layout(i, n, width_, height_);
    const ScenePanel& p = panels[static_cast<std::size_t>(i)];
    draw_scene_gl(p.scene, p.camera, strain, style.scene, layout.scene, height_);
  }
  glFinish();
  // OSMesa's buffer holds the bottom row first: flip into an RGB image, top row first.
  RgbImage img(width_, height_);
  const std::size_t w = static_cast<std::size_t>(width_);
  for (int y = 0; y < height_; ++y) {
    const unsigned char* src = ctx_->rgba.data() + static_cast<std::size_t>(height_ - 1 - y) * w * 4;
    unsigned char* dst = img.pixels.data() + img.offset(0, y);
    for (std::size_t x = 0; x < w; ++x) {
      dst[3 * x] = src[4 * x];
      dst[3 * x + 1] = src[4 * x + 1];
      dst[3 * x + 2] = src[4 * x + 2];
    }
  }
  if (style.overlay)
    for (int i = 0; i < n; ++i) {
      const PanelLayout layout = panel_layout(i, n, width_, height_);
      draw_overlay(img, layout, panels[static_cast<std::size_t>(i)].overlay, strain);
      if (i > 0) img.fill_rect(layout.panel.x0, 0, layout.panel.x0 + layout.scale, height_, Rgb{150, 155, 165});
    }
  return img;
}

}  // namespace codesign::io
