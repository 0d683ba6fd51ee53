#include "fem/mesh_quality.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <Eigen/Dense>

#include "fem/mesh_ops.hpp"

namespace codesign::fem {
namespace {

struct TetShape {
  double min_dihedral, max_dihedral;  // radians
  double radius_ratio;
  double edge_ratio;
};

constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

TetShape shape(const std::array<Eigen::Vector3d, 4>& x) {
  // Outward face normals (unnormalised area vectors) opposite each node.
  std::array<Eigen::Vector3d, 4> n;
  n[0] = (x[2] - x[1]).cross(x[3] - x[1]);
  n[1] = (x[3] - x[0]).cross(x[2] - x[0]);
  n[2] = (x[1] - x[0]).cross(x[3] - x[0]);
  n[3] = (x[2] - x[0]).cross(x[1] - x[0]);
  TetShape s{1e9, 0, 0, 0};
  // The dihedral angle at the edge shared by faces i and j: π - angle(n_i, n_j).
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      const double c = std::clamp(n[i].dot(n[j]) / (n[i].norm() * n[j].norm()), -1.0, 1.0);
      const double a = std::numbers::pi - std::acos(c);
      s.min_dihedral = std::min(s.min_dihedral, a);
      s.max_dihedral = std::max(s.max_dihedral, a);
    }
  }
  double emin = 1e300, emax = 0;
  for (const auto& e : kEdges) {
    const double len = (x[e[0]] - x[e[1]]).norm();
    emin = std::min(emin, len);
    emax = std::max(emax, len);
  }
  s.edge_ratio = emax / std::max(emin, 1e-300);
  // r_in = 3V / A_total; r_circ from the circumsphere solve.
  const double vol = signed_volume(x[0], x[1], x[2], x[3]);
  double area = 0;
  for (const auto& v : n) area += 0.5 * v.norm();
  const double r_in = 3.0 * std::abs(vol) / area;
  Eigen::Matrix3d a;
  Eigen::Vector3d b;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d d = x[k + 1] - x[0];
    a.row(k) = 2.0 * d.transpose();
    b[k] = d.squaredNorm();
  }
  const double r_circ = std::abs(vol) > 0 ? a.fullPivLu().solve(b).norm() : 1e300;
  s.radius_ratio = 3.0 * r_in / r_circ;
  return s;
}

void add(std::vector<std::string>& problems, const char* fmt, double a, double b = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  problems.emplace_back(buf);
}

}  // namespace

QualityReport check_mesh(const TetMesh& m, const QualityThresholds& th) {
  QualityReport r;
  r.nodes = static_cast<int>(m.nodes.size());
  r.tets = static_cast<int>(m.tets.size());
  if (m.tets.empty()) {
    r.problems.emplace_back("mesh has no tetrahedra");
    return r;
  }
  constexpr double deg = 180.0 / std::numbers::pi;
  r.min_volume = 1e300;
  r.max_volume = -1e300;
  r.min_dihedral_deg = 180;
  r.max_dihedral_deg = 0;
  r.min_radius_ratio = 1;
  for (int t = 0; t < r.tets; ++t) {
    const Tet& k = m.tets[t];
    const double v = tet_volume(m, t);
    r.total_volume += v;
    r.min_volume = std::min(r.min_volume, v);
    r.max_volume = std::max(r.max_volume, v);
    if (!(v > 0)) ++r.inverted;
    const TetShape s = shape({m.nodes[k[0]], m.nodes[k[1]], m.nodes[k[2]], m.nodes[k[3]]});
    r.min_dihedral_deg = std::min(r.min_dihedral_deg, s.min_dihedral * deg);
    r.max_dihedral_deg = std::max(r.max_dihedral_deg, s.max_dihedral * deg);
    r.min_radius_ratio = std::min(r.min_radius_ratio, s.radius_ratio);
    r.max_edge_ratio = std::max(r.max_edge_ratio, s.edge_ratio);
  }
  std::vector<bool> used(m.nodes.size(), false);
  for (const Tet& k : m.tets) {
    for (int v : k) used[v] = true;
  }
  const auto unused = std::count(used.begin(), used.end(), false);
  r.components = count_tet_components(m);
  r.overshared_faces = count_overshared_faces(m);
  const std::vector<Tri> boundary = boundary_faces(m);
  r.boundary_open_edges = count_open_edges(boundary) + count_overshared_edges(boundary);
  r.base_faces = static_cast<int>(m.base_faces.size());
  r.tip_faces = static_cast<int>(m.tip_faces.size());
  for (const auto& c : m.chamber_faces) {
    r.chamber_faces.push_back(static_cast<int>(c.size()));
    r.chamber_open_edges.push_back(count_open_edges(c) + count_overshared_edges(c));
  }

  auto& p = r.problems;
  if (r.inverted > 0) add(p, "%.0f inverted or flat tets (volume <= 0)", r.inverted);
  if (r.min_dihedral_deg < th.min_dihedral_deg) {
    add(p, "min dihedral angle %.2f deg below %.2f deg", r.min_dihedral_deg, th.min_dihedral_deg);
  }
  if (r.max_dihedral_deg > th.max_dihedral_deg) {
    add(p, "max dihedral angle %.2f deg above %.2f deg", r.max_dihedral_deg, th.max_dihedral_deg);
  }
  if (r.min_radius_ratio < th.min_radius_ratio) {
    add(p, "min radius ratio %.3f below %.3f", r.min_radius_ratio, th.min_radius_ratio);
  }
  if (unused > 0) add(p, "%.0f nodes used by no tet", static_cast<double>(unused));
  if (r.components != 1) add(p, "%.0f connected components (expected 1)", r.components);
  if (r.overshared_faces > 0) add(p, "%.0f faces shared by more than two tets", r.overshared_faces);
  if (r.boundary_open_edges > 0) add(p, "boundary surface not closed (%.0f bad edges)", r.boundary_open_edges);
  if (r.base_faces == 0) p.emplace_back("no base faces tagged");
  if (r.tip_faces == 0) p.emplace_back("no tip faces tagged");
  for (std::size_t c = 0; c < r.chamber_faces.size(); ++c) {
    if (r.chamber_faces[c] == 0) add(p, "chamber %.0f has no faces", static_cast<double>(c + 1));
  }
  return r;
}

QualityReport check_whisker_mesh(const TetMesh& m, const WhiskerGeometry& g, const QualityThresholds& th) {
  QualityReport r = check_mesh(m, th);
  if (r.tets == 0) return r;
  auto& p = r.problems;
  if (static_cast<int>(m.chamber_faces.size()) != g.design.n) {
    add(p, "%.0f chamber surfaces, design has %.0f", static_cast<double>(m.chamber_faces.size()), g.design.n);
  }
  for (std::size_t c = 0; c < r.chamber_open_edges.size(); ++c) {
    if (r.chamber_open_edges[c] > 0) {
      add(p, "chamber %.0f surface not watertight (%.0f open edges)", static_cast<double>(c + 1),
          r.chamber_open_edges[c]);
    }
  }
  r.has_reference = true;
  r.reference_volume = solid_volume(g);
  r.volume_error = r.total_volume - r.reference_volume;
  r.volume_tolerance = faceting_volume_bound(m, boundary_faces(m));
  if (std::abs(r.volume_error) > r.volume_tolerance) {
    add(p, "volume error %.3f mm^3 exceeds the faceting bound %.3f mm^3", r.volume_error, r.volume_tolerance);
  }
  return r;
}

double faceting_volume_bound(const TetMesh& m, const std::vector<Tri>& boundary) {
  double bound = 0;
  for (const Tri& f : boundary) {
    const Eigen::Vector3d& a = m.nodes[f[0]];
    const Eigen::Vector3d& b = m.nodes[f[1]];
    const Eigen::Vector3d& c = m.nodes[f[2]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double area = 0.5 * n.norm();
    if (area <= 0) continue;
    const Eigen::Vector3d u = n.normalized();
    if (std::abs(u.x()) > 1 - 1e-9 || std::abs(u.z()) > 1 - 1e-9) continue;  // planar faces
    // Angular span of the face about the x axis and the largest node radius.
    const std::array<double, 3> ang{std::atan2(a.z(), a.y()), std::atan2(b.z(), b.y()), std::atan2(c.z(), c.y())};
    double span = 0;
    for (int i = 0; i < 3; ++i) {
      for (int j = i + 1; j < 3; ++j) {
        double d = std::abs(ang[i] - ang[j]);
        if (d > std::numbers::pi) d = 2 * std::numbers::pi - d;
        span = std::max(span, d);
      }
    }
    const double r = std::max({std::hypot(a.y(), a.z()), std::hypot(b.y(), b.z()), std::hypot(c.y(), c.z())});
    const double half = 0.5 * span;
    bound += area * r * (1.0 - std::cos(half));
  }
  return bound;
}

std::string summary(const QualityReport& r) {
  char buf[320];
  if (r.has_reference) {
    std::snprintf(buf, sizeof buf,
                  "nodes %d, tets %d, volume %.1f mm^3 (CAD %.1f, error %+.2f%%, bound %.2f%%), "
                  "min dihedral %.1f deg, min radius ratio %.3f: %s",
                  r.nodes, r.tets, r.total_volume, r.reference_volume,
                  100.0 * r.volume_error / r.reference_volume, 100.0 * r.volume_tolerance / r.reference_volume,
                  r.min_dihedral_deg, r.min_radius_ratio, r.ok() ? "PASS" : "FAIL");
  } else {
    std::snprintf(buf, sizeof buf, "nodes %d, tets %d, volume %.1f mm^3, min dihedral %.1f deg, min radius ratio %.3f: %s",
                  r.nodes, r.tets, r.total_volume, r.min_dihedral_deg, r.min_radius_ratio,
                  r.ok() ? "PASS" : "FAIL");
  }
  std::string s = buf;
  for (const auto& p : r.problems) s += "; " + p;
  return s;
}

}  // namespace codesign::fem
