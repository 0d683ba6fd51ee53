// The renderer against geometry: silhouettes where the camera projects the surface, the colour
// bar's ends where strain is extreme, the force arrow as long as F says, the band chip.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "io/render/render_osmesa.hpp"
#include "render_test_scene.hpp"

using namespace codesign;

namespace {

constexpr int kW = 640, kH = 360;

bool is_background(io::Rgb c, io::Rgb bg) {
  return std::abs(c.r - bg.r) + std::abs(c.g - bg.g) + std::abs(c.b - bg.b) <= 6;
}

struct Box {
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  void add(double x, double y) {
    x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  }
};

// Bounding box of the non-background pixels inside a viewport.
Box silhouette(const io::RgbImage& img, const io::Viewport& vp, io::Rgb bg) {
  Box b;
  for (int y = vp.y0; y < vp.y0 + vp.height; ++y)
    for (int x = vp.x0; x < vp.x0 + vp.width; ++x)
      if (!is_background(img.at(x, y), bg)) b.add(x + 0.5, y + 0.5);
  return b;
}

Box projected(const io::SceneFrame& f, const io::Camera& cam, const io::Viewport& vp) {
  Box b;
  for (const auto& v : f.vertices) {
    const Eigen::Vector2d p = io::project_to_pixel(cam, vp, v.cast<double>());
    b.add(p.x(), p.y());
  }
  return b;
}

io::RenderStyle whisker_only() {
  io::RenderStyle s;
  s.scene.plate = s.scene.base = s.scene.force_arrow = false;
  s.overlay = false;
  return s;
}

// Chromaticity: colour divided by its sum. Lighting here only scales colours (ambient + diffuse,
// no specular, sum ≤ 1 so nothing saturates), which leaves it unchanged up to 8-bit rounding.
Eigen::Vector3d chroma(io::Rgb c) {
  const double s = std::max(1.0, static_cast<double>(c.r) + c.g + c.b);
  return {c.r / s, c.g / s, c.b / s};
}

}  // namespace

TEST(RenderScene, SilhouetteMatchesTheProjectedSurfaceAndMovesWithIt) {
  io::Renderer r(kW, kH);
  const io::PanelLayout layout = io::panel_layout(0, 1, kW, kH);
  const double aspect = static_cast<double>(layout.scene.width) / layout.scene.height;
  const io::SceneFrame f0 = test::tube_scene(0.5);
  const io::Camera cam = io::fit_camera(f0, -20.0, 15.0, 30.0, aspect);
  const io::RenderStyle style = whisker_only();
  Box first;
  for (double angle : {0.5, 0.3}) {  // the tube swings up by 0.2 rad: its far end rises
    io::ScenePanel p{test::tube_scene(angle), {}, cam};
    const io::RgbImage img = r.render({&p, 1}, {0.0, 0.04}, style);
    const Box s = silhouette(img, layout.scene, style.background);
    const Box e = projected(p.scene, cam, layout.scene);
    // Rasterised edges lie within one pixel of the projected outline (pixel centres are sampled;
    // the smooth tube's polygonal outline is inside the vertex hull), so 1.5 px.
    EXPECT_NEAR(s.x0, e.x0, 1.5);
    EXPECT_NEAR(s.x1, e.x1, 1.5);
    EXPECT_NEAR(s.y0, e.y0, 1.5);
    EXPECT_NEAR(s.y1, e.y1, 1.5);
    if (angle == 0.5) {
      first = s;
    } else {
      EXPECT_LT(s.y1, first.y1 - 20.0) << "the lowest pixel (far end) rises on screen";
    }
  }
}

TEST(RenderScene, ColourBarEndsAppearWhereStrainIsExtreme) {
  io::Renderer r(kW, kH);
  const io::PanelLayout layout = io::panel_layout(0, 1, kW, kH);
  const double aspect = static_cast<double>(layout.scene.width) / layout.scene.height;
  for (bool reversed : {false, true}) {
    io::ScenePanel p{test::tube_scene(0.5, 100.0, 6.0, reversed ? 0.04 : 0.0, reversed ? 0.0 : 0.04), {}, {}};
    p.camera = io::fit_camera(p.scene, -20.0, 15.0, 30.0, aspect);
    io::RenderStyle style;
    style.scene.plate = style.scene.base = style.scene.force_arrow = false;
    const io::RgbImage img = r.render({&p, 1}, {0.0, 0.04}, style);
    // Ends of the colour bar, read from the image itself.
    const int bx = layout.bar.x0 + layout.bar.width / 2;
    const Eigen::Vector3d top = chroma(img.at(bx, layout.bar.y0));
    const Eigen::Vector3d bottom = chroma(img.at(bx, layout.bar.y0 + layout.bar.height - 1));
    // The whisker pixels closest in chromaticity to each end, and where the ends project.
    Eigen::Vector2d at_top(0, 0), at_bottom(0, 0);
    int n_top = 0, n_bottom = 0;
    for (int y = layout.scene.y0; y < layout.scene.y0 + layout.scene.height; ++y)
      for (int x = layout.scene.x0; x < layout.scene.x0 + layout.scene.width; ++x) {
        const io::Rgb c = img.at(x, y);
        if (is_background(c, style.background)) continue;
        const Eigen::Vector3d q = chroma(c);
        // 0.03 in chromaticity: far below the 0.2–0.4 between the map's ends, above 8-bit rounding
        // of dark shaded pixels (1/(r+g+b) with r+g+b ≥ ~60).
        if ((q - top).norm() < 0.03) at_top += Eigen::Vector2d(x, y), ++n_top;
        if ((q - bottom).norm() < 0.03) at_bottom += Eigen::Vector2d(x, y), ++n_bottom;
      }
    ASSERT_GT(n_top, 20);
    ASSERT_GT(n_bottom, 20);
    at_top /= n_top;
    at_bottom /= n_bottom;
    const Eigen::Vector3d ax(std::cos(0.5), 0.0, -std::sin(0.5));
    const Eigen::Vector2d base = io::project_to_pixel(p.camera, layout.scene, Eigen::Vector3d::Zero());
    const Eigen::Vector2d tip = io::project_to_pixel(p.camera, layout.scene, 100.0 * ax);
    const Eigen::Vector2d hi_end = reversed ? base : tip, lo_end = reversed ? tip : base;
    // Only the last/first ~1/30 of the map is within 0.03 of an end colour, so the matching
    // pixels sit within a tenth of the projected length of the right end.
    const double tol = 0.1 * (tip - base).norm();
    EXPECT_LT((at_top - hi_end).norm(), tol) << "reversed " << reversed;
    EXPECT_LT((at_bottom - lo_end).norm(), tol) << "reversed " << reversed;
  }
}

TEST(RenderScene, ForceArrowIsAsLongAsTheForce) {
  io::Renderer r(kW, kH);
  const io::PanelLayout layout = io::panel_layout(0, 1, kW, kH);
  const double aspect = static_cast<double>(layout.scene.width) / layout.scene.height;
  io::ScenePanel p{test::tube_scene(0.5), {}, {}};
  p.camera = io::fit_camera(p.scene, 0.0, 0.0, 30.0, aspect);  // side view: the arrow is vertical on screen
  p.scene.force_mN = 25.0;
  io::RenderStyle style;
  style.overlay = false;
  style.scene.arrow_mm_per_mN = 1.0;
  const io::RgbImage img = r.render({&p, 1}, {0.0, 0.04}, style);
  // The arrow is the only magenta object: red and blue well above green.
  double top = 1e9;
  for (int y = layout.scene.y0; y < layout.scene.y0 + layout.scene.height; ++y)
    for (int x = layout.scene.x0; x < layout.scene.x0 + layout.scene.width; ++x) {
      const io::Rgb c = img.at(x, y);
      if (c.r > 2 * c.g + 20 && c.b > 2 * c.g + 20) top = std::min(top, y + 0.5);
    }
  const Eigen::Vector3d tip = p.scene.force_point_mm + Eigen::Vector3d(0, 0, 25.0);
  EXPECT_NEAR(top, io::project_to_pixel(p.camera, layout.scene, tip).y(), 2.0);
}

TEST(RenderScene, BandChipShowsTheForceState) {
  io::Renderer r(kW, kH);
  io::ScenePanel p{test::tube_scene(0.5), {}, {}};
  const io::PanelLayout layout = io::panel_layout(0, 1, kW, kH);
  p.camera = io::fit_camera(p.scene, -20, 15, 30, static_cast<double>(layout.scene.width) / layout.scene.height);
  auto count = [&](double force, io::Rgb colour) {
    p.overlay.force_mN = force;
    const io::RgbImage img = r.render({&p, 1}, {0.0, 0.04}, io::RenderStyle{});
    int n = 0;
    for (int y = 0; y < layout.scene.y0; ++y)
      for (int x = 0; x < kW; ++x) n += img.at(x, y) == colour;
    return n;
  };
  const io::Rgb green{40, 150, 60}, orange{225, 120, 20}, red{200, 40, 40};
  EXPECT_GT(count(21.0, green), 50);
  EXPECT_EQ(count(21.0, orange), 0);
  EXPECT_GT(count(15.0, orange), 50);
  EXPECT_GT(count(25.0, orange), 50);
  EXPECT_GT(count(0.0, red), 50);
  EXPECT_EQ(io::band_state(16.1, 20.0, 0.2), io::BandState::In);
  EXPECT_EQ(io::band_state(15.9, 20.0, 0.2), io::BandState::Below);
  EXPECT_EQ(io::band_state(24.1, 20.0, 0.2), io::BandState::Above);
  EXPECT_EQ(io::band_state(0.0, 20.0, 0.2), io::BandState::NoContact);
}

TEST(RenderScene, SideBySidePanelsEachShowTheirScene) {
  io::Renderer r(kW, kH);
  io::ScenePanel panels[2] = {{test::tube_scene(0.5), {}, {}}, {test::tube_scene(0.2), {}, {}}};
  for (int i = 0; i < 2; ++i) {
    const io::PanelLayout l = io::panel_layout(i, 2, kW, kH);
    panels[i].camera = io::fit_camera(panels[0].scene, -20, 15, 30, static_cast<double>(l.scene.width) / l.scene.height);
  }
  const io::RenderStyle style = whisker_only();
  const io::RgbImage img = r.render(panels, {0.0, 0.04}, style);
  for (int i = 0; i < 2; ++i) {
    const io::PanelLayout l = io::panel_layout(i, 2, kW, kH);
    const Box s = silhouette(img, l.scene, style.background);
    const Box e = projected(panels[i].scene, panels[i].camera, l.scene);
    EXPECT_NEAR(s.y1, e.y1, 1.5) << "panel " << i;
    EXPECT_NEAR(s.x1, e.x1, 1.5) << "panel " << i;
  }
}

TEST(RenderScene, BadInputIsRejected) {
  EXPECT_THROW(io::Renderer(32, 720), std::invalid_argument);
  io::Renderer r(kW, kH);
  io::ScenePanel p{test::tube_scene(0.5), {}, {}};
  p.scene.strain.pop_back();
  EXPECT_THROW(r.render({&p, 1}, {0.0, 0.04}, io::RenderStyle{}), std::invalid_argument);
  p.scene = test::tube_scene(0.5);
  p.scene.triangles.push_back({0, 1, 100000});
  EXPECT_THROW(r.render({&p, 1}, {0.0, 0.04}, io::RenderStyle{}), std::invalid_argument);
}
