#include "fem/mesh_ops.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Dense>

namespace codesign::fem {
namespace {

// Local faces of a positively oriented tet, each listed so that its normal points away from the
// node it omits (checked on the unit tet: face {1,2,3} has normal (1,1,1)).
constexpr int kTetFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

using FaceKey = std::array<int, 3>;

FaceKey sorted_key(const Tri& f) {
  FaceKey k{f[0], f[1], f[2]};
  std::sort(k.begin(), k.end());
  return k;
}

struct FaceRecord {
  FaceKey key;
  int tet;
  int local;
};

// All tet faces, sorted by key, so equal faces are adjacent.
std::vector<FaceRecord> all_faces(const TetMesh& m) {
  std::vector<FaceRecord> recs;
  recs.reserve(m.tets.size() * 4);
  for (int t = 0; t < static_cast<int>(m.tets.size()); ++t) {
    const Tet& tet = m.tets[t];
    for (int f = 0; f < 4; ++f) {
      recs.push_back({sorted_key({tet[kTetFace[f][0]], tet[kTetFace[f][1]], tet[kTetFace[f][2]]}), t, f});
    }
  }
  std::stable_sort(recs.begin(), recs.end(),
                   [](const FaceRecord& a, const FaceRecord& b) { return a.key < b.key; });
  return recs;
}

Tri outward_face(const TetMesh& m, int t, int f) {
  const Tet& tet = m.tets[t];
  Tri tri{tet[kTetFace[f][0]], tet[kTetFace[f][1]], tet[kTetFace[f][2]]};
  if (tet_volume(m, t) < 0) std::swap(tri[1], tri[2]);
  return tri;
}

using EdgeKey = std::pair<int, int>;

std::map<EdgeKey, int> edge_use(const std::vector<Tri>& faces) {
  std::map<EdgeKey, int> use;
  for (const Tri& f : faces) {
    for (int e = 0; e < 3; ++e) {
      const int a = f[e], b = f[(e + 1) % 3];
      ++use[{std::min(a, b), std::max(a, b)}];
    }
  }
  return use;
}

}  // namespace

double signed_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                     const Eigen::Vector3d& d) {
  return (b - a).cross(c - a).dot(d - a) / 6.0;
}

double tet_volume(const TetMesh& m, int t) {
  const Tet& k = m.tets[t];
  return signed_volume(m.nodes[k[0]], m.nodes[k[1]], m.nodes[k[2]], m.nodes[k[3]]);
}

double total_volume(const TetMesh& m) {
  double v = 0;
  for (int t = 0; t < static_cast<int>(m.tets.size()); ++t) v += tet_volume(m, t);
  return v;
}

std::vector<Tri> boundary_faces(const TetMesh& m) {
  const std::vector<FaceRecord> recs = all_faces(m);
  std::vector<std::pair<int, int>> singles;  // (tet, local face)
  for (std::size_t i = 0; i < recs.size();) {
    std::size_t j = i;
    while (j < recs.size() && recs[j].key == recs[i].key) ++j;
    if (j - i == 1) singles.emplace_back(recs[i].tet, recs[i].local);
    i = j;
  }
  std::sort(singles.begin(), singles.end());
  std::vector<Tri> out;
  out.reserve(singles.size());
  for (const auto& [t, f] : singles) out.push_back(outward_face(m, t, f));
  return out;
}

int count_overshared_faces(const TetMesh& m) {
  const std::vector<FaceRecord> recs = all_faces(m);
  int bad = 0;
  for (std::size_t i = 0; i < recs.size();) {
    std::size_t j = i;
    while (j < recs.size() && recs[j].key == recs[i].key) ++j;
    if (j - i > 2) ++bad;
    i = j;
  }
  return bad;
}

std::vector<int> face_nodes(const std::vector<Tri>& faces) {
  std::vector<int> n;
  n.reserve(faces.size() * 3);
  for (const Tri& f : faces) n.insert(n.end(), f.begin(), f.end());
  std::sort(n.begin(), n.end());
  n.erase(std::unique(n.begin(), n.end()), n.end());
  return n;
}

Eigen::Vector3d vector_area(const TetMesh& m, const std::vector<Tri>& faces) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (const Tri& f : faces) {
    s += 0.5 * (m.nodes[f[1]] - m.nodes[f[0]]).cross(m.nodes[f[2]] - m.nodes[f[0]]);
  }
  return s;
}

double surface_area(const TetMesh& m, const std::vector<Tri>& faces) {
  double a = 0;
  for (const Tri& f : faces) {
    a += 0.5 * (m.nodes[f[1]] - m.nodes[f[0]]).cross(m.nodes[f[2]] - m.nodes[f[0]]).norm();
  }
  return a;
}

int count_open_edges(const std::vector<Tri>& faces) {
  int n = 0;
  for (const auto& [e, c] : edge_use(faces)) n += (c == 1);
  return n;
}

int count_overshared_edges(const std::vector<Tri>& faces) {
  int n = 0;
  for (const auto& [e, c] : edge_use(faces)) n += (c > 2);
  return n;
}

int count_tet_components(const TetMesh& m) {
  const int nt = static_cast<int>(m.tets.size());
  std::vector<int> parent(nt);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  const std::vector<FaceRecord> recs = all_faces(m);
  for (std::size_t i = 1; i < recs.size(); ++i) {
    if (recs[i].key == recs[i - 1].key) parent[find(recs[i].tet)] = find(recs[i - 1].tet);
  }
  int comps = 0;
  for (int t = 0; t < nt; ++t) comps += (find(t) == t);
  return comps;
}

int orient_tets_positive(TetMesh& m) {
  int flipped = 0;
  for (int t = 0; t < static_cast<int>(m.tets.size()); ++t) {
    if (tet_volume(m, t) < 0) {
      std::swap(m.tets[t][2], m.tets[t][3]);
      ++flipped;
    }
  }
  return flipped;
}

void orient_tagged_faces(TetMesh& m) {
  std::map<FaceKey, Tri> outward;
  for (const Tri& f : boundary_faces(m)) outward.emplace(sorted_key(f), f);
  auto fix = [&](std::vector<Tri>& faces, const std::string& name) {
    for (Tri& f : faces) {
      const auto it = outward.find(sorted_key(f));
      if (it == outward.end()) {
        throw std::invalid_argument("tagged face of '" + name + "' (nodes " + std::to_string(f[0]) +
                                    " " + std::to_string(f[1]) + " " + std::to_string(f[2]) +
                                    ") is not a boundary face of the tetrahedra");
      }
      f = it->second;
    }
  };
  fix(m.base_faces, "base");
  fix(m.tip_faces, "tip");
  for (std::size_t c = 0; c < m.chamber_faces.size(); ++c) {
    fix(m.chamber_faces[c], "chamber_" + std::to_string(c + 1));
  }
}

void compact_nodes(TetMesh& m) {
  std::vector<int> map(m.nodes.size(), -1);
  for (const Tet& t : m.tets) {
    for (int v : t) map.at(v) = 0;
  }
  std::vector<Eigen::Vector3d> nodes;
  for (std::size_t i = 0; i < map.size(); ++i) {
    if (map[i] == 0) {
      map[i] = static_cast<int>(nodes.size());
      nodes.push_back(m.nodes[i]);
    }
  }
  for (Tet& t : m.tets) {
    for (int& v : t) v = map[v];
  }
  auto remap = [&](std::vector<Tri>& faces) {
    for (Tri& f : faces) {
      for (int& v : f) {
        if (v < 0 || v >= static_cast<int>(map.size()) || map[v] < 0) {
          throw std::invalid_argument("tagged face refers to node " + std::to_string(v) +
                                      " that no tetrahedron uses");
        }
        v = map[v];
      }
    }
  };
  remap(m.base_faces);
  remap(m.tip_faces);
  for (auto& c : m.chamber_faces) remap(c);
  m.nodes = std::move(nodes);
}

Eigen::Vector4d barycentric(const TetMesh& m, int t, const Eigen::Vector3d& p) {
  const Tet& k = m.tets[t];
  const Eigen::Vector3d& x0 = m.nodes[k[0]];
  Eigen::Matrix3d d;
  d << m.nodes[k[1]] - x0, m.nodes[k[2]] - x0, m.nodes[k[3]] - x0;
  const Eigen::Vector3d l = d.partialPivLu().solve(p - x0);
  return {1.0 - l.sum(), l[0], l[1], l[2]};
}

TetLocator::TetLocator(const TetMesh& m, double tets_per_cell) : mesh_(&m) {
  if (m.tets.empty()) throw std::invalid_argument("TetLocator: mesh has no tetrahedra");
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : m.nodes) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d ext = (hi - lo).cwiseMax(1e-12);
  const double cells = std::max(1.0, static_cast<double>(m.tets.size()) / tets_per_cell);
  const double edge = std::cbrt(ext.prod() / cells);
  for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, static_cast<int>(std::ceil(ext[a] / edge)));
  lo_ = lo;
  cell_ = ext.cwiseQuotient(dims_.cast<double>());

  const int ncell = dims_.prod();
  std::vector<std::vector<int>> bins(ncell);
  for (int t = 0; t < static_cast<int>(m.tets.size()); ++t) {
    Eigen::Vector3d tlo = m.nodes[m.tets[t][0]], thi = tlo;
    for (int v : m.tets[t]) {
      tlo = tlo.cwiseMin(m.nodes[v]);
      thi = thi.cwiseMax(m.nodes[v]);
    }
    const Eigen::Vector3i a = cell_of(tlo), b = cell_of(thi);
    for (int i = a.x(); i <= b.x(); ++i)
      for (int j = a.y(); j <= b.y(); ++j)
        for (int k = a.z(); k <= b.z(); ++k) bins[(k * dims_.y() + j) * dims_.x() + i].push_back(t);
  }
  start_.assign(ncell + 1, 0);
  for (int c = 0; c < ncell; ++c) start_[c + 1] = start_[c] + static_cast<int>(bins[c].size());
  items_.reserve(start_.back());
  for (const auto& b : bins) items_.insert(items_.end(), b.begin(), b.end());
}

Eigen::Vector3i TetLocator::cell_of(const Eigen::Vector3d& p) const {
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a) {
    const int i = static_cast<int>(std::floor((p[a] - lo_[a]) / cell_[a]));
    c[a] = std::clamp(i, 0, dims_[a] - 1);
  }
  return c;
}

int TetLocator::locate(const Eigen::Vector3d& p, double tol) const {
  const Eigen::Vector3i c = cell_of(p);
  const int cell = (c.z() * dims_.y() + c.y()) * dims_.x() + c.x();
  int best = -1;
  double best_min = 0;
  // Tets are stored in increasing id per cell, so a strict '>' keeps the lowest id on ties.
  for (int i = start_[cell]; i < start_[cell + 1]; ++i) {
    const int t = items_[i];
    const double wmin = barycentric(*mesh_, t, p).minCoeff();
    if (wmin < -tol) continue;
    if (best < 0 || wmin > best_min) {
      best = t;
      best_min = wmin;
    }
  }
  return best;
}

}  // namespace codesign::fem
