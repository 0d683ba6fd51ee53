#pragma once
// A synthetic scene for the renderer tests: a closed tube (the "whisker") of radius r and
// length L from the origin along R_y(angle) x̂, with per-vertex strain growing linearly from
// strain_base at the clamped end to strain_tip at the far end; a plate 3 mm below the tip.
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "io/render/render_scene.hpp"

namespace codesign::test {

inline io::SceneFrame tube_scene(double angle_rad, double length = 100.0, double radius = 6.0,
                                 double strain_base = 0.0, double strain_tip = 0.04, int rings = 40,
                                 int segments = 24) {
  io::SceneFrame f;
  const Eigen::Vector3d ax(std::cos(angle_rad), 0.0, -std::sin(angle_rad));
  const Eigen::Vector3d u(0.0, 1.0, 0.0);
  const Eigen::Vector3d v = ax.cross(u);
  for (int i = 0; i <= rings; ++i) {
    const double s = static_cast<double>(i) / rings;
    for (int k = 0; k < segments; ++k) {
      const double phi = 2.0 * std::numbers::pi * k / segments;
      f.vertices.push_back((s * length * ax + radius * (std::cos(phi) * u + std::sin(phi) * v)).cast<float>());
      f.strain.push_back(static_cast<float>(strain_base + s * (strain_tip - strain_base)));
    }
  }
  auto id = [&](int i, int k) { return i * segments + (k % segments); };
  for (int i = 0; i < rings; ++i)
    for (int k = 0; k < segments; ++k) {
      f.triangles.push_back({id(i, k), id(i + 1, k), id(i + 1, k + 1)});
      f.triangles.push_back({id(i, k), id(i + 1, k + 1), id(i, k + 1)});
    }
  // End caps (fans around a centre vertex).
  for (int end = 0; end < 2; ++end) {
    const int c = static_cast<int>(f.vertices.size());
    f.vertices.push_back((end * length * ax).cast<float>());
    f.strain.push_back(static_cast<float>(end ? strain_tip : strain_base));
    const int ring = end ? rings : 0;
    for (int k = 0; k < segments; ++k) {
      if (end)
        f.triangles.push_back({c, id(ring, k), id(ring, k + 1)});
      else
        f.triangles.push_back({c, id(ring, k + 1), id(ring, k)});
    }
  }
  const Eigen::Vector3d tip = length * ax;
  f.plate_z_mm = tip.z() - radius - 3.0;
  f.plate_x0_mm = tip.x() - 40.0;
  f.plate_x1_mm = tip.x() + 20.0;
  f.base_angle_rad = angle_rad;
  f.base_radius_mm = radius;
  f.force_point_mm = tip - Eigen::Vector3d(0, 0, radius);
  return f;
}

}  // namespace codesign::test
