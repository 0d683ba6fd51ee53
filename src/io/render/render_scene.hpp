#pragma once
// What a rendered frame shows, as plain data, and how it is drawn with (fixed-function) OpenGL.
//
// World frame and units are the simulator's (fem/scene.hpp): millimetres, z up, the whisker
// clamped at the origin and inclined down along +x, the base turning about the y axis, the
// plate a horizontal plane below the tip. Nothing here knows about the simulator: callers
// fill a SceneFrame from it.
//
// Drawn in the 3-D viewport of a panel:
//   * the whisker's boundary surface at its deformed positions, smooth-shaded (one directional
//     light at the upper left of the viewer plus ambient light, no specular part, so lighting
//     only scales a vertex colour) and coloured by the per-vertex axial strain through the
//     colour map of io/render/colormap.hpp over the StrainScale;
//   * the plate: a grey slab whose top face is the contact plane z = plate_z;
//   * the rotary base: a dark clamp block that turns with the base angle α + θ, in front of a
//     motor drum whose orange index mark turns with it;
//   * the contact force on the whisker: a vertical magenta arrow from its point of application,
//     force_mN · arrow_mm_per_mN long (none when F = 0).
// The 2-D part (text, colour bar) is drawn on the read-back image by io/render/render_overlay.hpp.
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/render/colormap.hpp"
#include "io/formats/image.hpp"

namespace codesign::io {

struct SceneFrame {
  // Whisker boundary surface: world positions [mm], triangles counter-clockwise seen from
  // outside, axial strain per vertex (dimensionless).
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<float> strain;
  // Plate: top face at z = plate_z_mm, spanning [plate_x0_mm, plate_x1_mm] x ±plate_half_width_mm.
  double plate_z_mm = 0.0;
  double plate_x0_mm = 0.0, plate_x1_mm = 0.0, plate_half_width_mm = 25.0;
  // Rotary base: the whisker axis points along R_y(base_angle) x̂ (base_angle = α + θ);
  // base_radius_mm is the radius of the clamped face.
  double base_angle_rad = 0.0;
  double base_radius_mm = 12.0;
  // Contact force on the whisker [mN], vertical (+z), applied at force_point_mm.
  double force_mN = 0.0;
  Eigen::Vector3d force_point_mm = Eigen::Vector3d::Zero();
};

// The text of a panel (drawn by render_overlay).
struct FrameOverlay {
  std::string title;             // e.g. "d*: j21 {1, 28 mm, 2.5 mm}  p = [0.07, 0] kPa"
  double t_s = 0.0;
  double theta_rad = 0.0;
  double force_mN = 0.0;
  double target_mN = 20.0;       // F_t
  double band_fraction = 0.2;    // the band is F_t (1 ± band_fraction)
};

// Perspective camera looking at `target` from distance_mm; azimuth 0 looks along +y (x to the
// right, z up), positive azimuth swings the eye towards +x, positive elevation raises it.
struct Camera {
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  double distance_mm = 300.0;
  double azimuth_deg = -20.0;
  double elevation_deg = 15.0;
  double fov_deg = 30.0;          // vertical field of view

  Eigen::Vector3d eye() const;
  // OpenGL view and projection matrices (column-major, as glLoadMatrixd takes them).
  Eigen::Matrix4d view() const;
  Eigen::Matrix4d projection(double aspect) const;
};

// A pixel rectangle of the image: x0, y0 is the top-left corner (image rows go down).
struct Viewport {
  int x0 = 0, y0 = 0, width = 0, height = 0;
};

// Image coordinates (x right, y down, pixel centres at +0.5) of world point p seen by `camera`
// in `viewport`.
Eigen::Vector2d project_to_pixel(const Camera& camera, const Viewport& viewport, const Eigen::Vector3d& p);

// The camera at the given angles and field of view that fits the whisker, plate and base of
// `frame` into a viewport of the given aspect, with `margin` (≥ 1) around them.
Camera fit_camera(const SceneFrame& frame, double azimuth_deg, double elevation_deg, double fov_deg, double aspect,
                  double margin = 1.08);

struct SceneStyle {
  bool plate = true, base = true, force_arrow = true;
  double arrow_mm_per_mN = 1.0;   // arrow length per mN of contact force
  // false: the whisker is sent vertex by vertex (glBegin/glEnd) instead of by vertex arrays;
  // only the benchmark's baseline uses it.
  bool vertex_arrays = true;
};

// Draws one panel's 3-D scene into the current GL context's `viewport` (rows counted from the
// top of an image of height image_height). Clears that viewport's depth first.
void draw_scene_gl(const SceneFrame& frame, const Camera& camera, const ColourScale& strain, const SceneStyle& style,
                   const Viewport& viewport, int image_height);

// Checks a frame's sizes and indices; throws std::invalid_argument naming the defect.
void check_frame(const SceneFrame& frame);

}  // namespace codesign::io
