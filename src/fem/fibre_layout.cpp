#include "fem/fibre_layout.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "fem/mesh_ops.hpp"

namespace codesign::fem {

std::vector<std::vector<Eigen::Vector3d>> fibre_polylines(const WhiskerGeometry& g, const FibreLayoutOptions& opt) {
  if (opt.count < 0 || !(opt.pitch_mm > 0) || !(opt.points_per_turn > 0)) {
    throw std::invalid_argument("fibre layout: need count ≥ 0, pitch_mm > 0, points_per_turn > 0");
  }
  if (!(opt.radial_inset_mm > 0 && opt.radial_inset_mm < g.design.wall_mm)) {
    throw std::invalid_argument("fibre layout: radial_inset_mm must lie in (0, w = " +
                                std::to_string(g.design.wall_mm) + " mm)");
  }
  const double x0 = g.chamber_start(), x1 = g.chamber_end();
  const double turns = (x1 - x0) / opt.pitch_mm;
  const int segments = std::max(1, static_cast<int>(std::ceil(turns * opt.points_per_turn - 1e-9)));
  constexpr double two_pi = 2.0 * std::numbers::pi;
  std::vector<std::vector<Eigen::Vector3d>> lines(opt.count);
  for (int k = 0; k < opt.count; ++k) {
    const double sense = (k % 2 == 0) ? 1.0 : -1.0;
    const double phase = two_pi * k / opt.count;
    lines[k].reserve(segments + 1);
    for (int i = 0; i <= segments; ++i) {
      const double x = x0 + (x1 - x0) * i / segments;
      const double r = g.outer_radius(x) - opt.radial_inset_mm;
      const double phi = phase + sense * two_pi * (x - x0) / opt.pitch_mm;
      lines[k].emplace_back(x, r * std::cos(phi), r * std::sin(phi));
    }
  }
  return lines;
}

std::vector<FibreChain> embed_polylines(const TetMesh& m, const std::vector<std::vector<Eigen::Vector3d>>& lines) {
  std::vector<FibreChain> chains;
  if (lines.empty()) return chains;
  const TetLocator locator(m);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    FibreChain c;
    for (std::size_t i = 0; i < lines[k].size(); ++i) {
      const Eigen::Vector3d& p = lines[k][i];
      const int t = locator.locate(p);
      if (t < 0) {
        throw std::runtime_error("fibre " + std::to_string(k) + " point " + std::to_string(i) + " at (" +
                                 std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " + std::to_string(p.z()) +
                                 ") lies outside the mesh; increase fibres.radial_inset_mm");
      }
      Eigen::Vector4d w = barycentric(m, t, p);
      w /= w.sum();
      c.points.push_back(EmbeddedPoint{t, w});
    }
    chains.push_back(std::move(c));
  }
  return chains;
}

std::vector<FibreChain> layout_fibres(const TetMesh& m, const WhiskerGeometry& g, const FibreLayoutOptions& opt) {
  return embed_polylines(m, fibre_polylines(g, opt));
}

}  // namespace codesign::fem
