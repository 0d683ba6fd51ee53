#include "fem/whisker_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include <gmsh.h>

#include "fem/mesh_ops.hpp"
#include "fem/mesh_quality.hpp"

namespace codesign::fem {
namespace {

// gmsh keeps one global model per process; this lock is the only shared state we add.
std::mutex& gmsh_lock() {
  static std::mutex m;
  return m;
}

// Initialises gmsh quietly and deterministically for one meshing job, finalises on scope exit.
class GmshSession {
 public:
  GmshSession() : lock_(gmsh_lock()) {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 1);
    gmsh::option::setNumber("General.NumThreads", 1);
    gmsh::option::setNumber("Mesh.MaxNumThreads3D", 1);
    gmsh::option::setNumber("Mesh.RandomSeed", 1);
    gmsh::logger::start();
    gmsh::model::add("codesign");
  }
  ~GmshSession() {
    try {
      gmsh::logger::stop();
      gmsh::finalize();
    } catch (...) {
      // finalize must not throw out of a destructor; nothing useful to do here.
    }
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  std::lock_guard<std::mutex> lock_;
};

std::string gmsh_error(const std::string& what) {
  std::string last;
  try {
    gmsh::logger::getLastError(last);
  } catch (...) {
  }
  return "gmsh failed while " + what + (last.empty() ? std::string() : ": " + last);
}

// Runs `body` and turns whatever gmsh throws (it throws std::string in 4.8) into runtime_error.
template <class F>
void guarded(const std::string& what, F&& body) {
  try {
    body();
  } catch (const std::exception& e) {
    throw std::runtime_error(gmsh_error(what) + " (" + e.what() + ")");
  } catch (...) {
    throw std::runtime_error(gmsh_error(what));
  }
}

using SizeField = std::function<double(double x, double y, double z)>;

// Meshes the current OCC model (already synchronised) with the given size field and returns the
// volume mesh without tags.
TetMesh generate_tets(const SizeField& size, double size_min, double size_max, double optimise_threshold) {
  TetMesh m;
  guarded("meshing", [&] {
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
    gmsh::option::setNumber("Mesh.MeshSizeMin", size_min);
    gmsh::option::setNumber("Mesh.MeshSizeMax", size_max);
    // Surface: 2D Delaunay (5); volume: 3D Delaunay (1), then gmsh's tet optimiser on every tet
    // below the quality threshold. HXT (10) gave better tets but differs from run to run even
    // single-threaded, which would break reproducibility; MMG3D (7) filled the cavities.
    gmsh::option::setNumber("Mesh.Algorithm", 5);
    gmsh::option::setNumber("Mesh.Algorithm3D", 1);
    gmsh::option::setNumber("Mesh.Optimize", 1);
    gmsh::option::setNumber("Mesh.OptimizeThreshold", optimise_threshold);
    gmsh::model::mesh::setSizeCallback(
        [size](int, int, double x, double y, double z) { return size(x, y, z); });
    gmsh::model::mesh::generate(3);
    gmsh::model::mesh::removeSizeCallback();

    std::vector<std::size_t> tags;
    std::vector<double> xyz, param;
    gmsh::model::mesh::getNodes(tags, xyz, param, -1, -1, false, false);
    std::unordered_map<std::size_t, int> index;
    m.nodes.reserve(tags.size());
    for (std::size_t i = 0; i < tags.size(); ++i) {
      if (index.emplace(tags[i], static_cast<int>(m.nodes.size())).second) {
        m.nodes.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
      }
    }
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> elem_tags, elem_nodes;
    gmsh::model::mesh::getElements(types, elem_tags, elem_nodes, 3, -1);
    for (std::size_t b = 0; b < types.size(); ++b) {
      if (types[b] != 4) throw std::runtime_error("unexpected 3D element type " + std::to_string(types[b]));
      const auto& en = elem_nodes[b];
      for (std::size_t e = 0; e + 3 < en.size(); e += 4) {
        m.tets.push_back({index.at(en[e]), index.at(en[e + 1]), index.at(en[e + 2]), index.at(en[e + 3])});
      }
    }
  });
  if (m.tets.empty()) throw std::runtime_error(gmsh_error("meshing") + " (no tetrahedra produced)");
  orient_tets_positive(m);
  compact_nodes(m);
  return m;
}

struct SizeSpec {
  SizeField field;
  double min, max;
};

// min over tets of (dihedral / threshold - 1, radius ratio / threshold - 1, …): ≥ 0 ⇔ no sliver.
double worst_shape_margin(const TetMesh& m, const QualityThresholds& th) {
  const QualityReport r = check_mesh(m, th);
  return std::min({r.min_dihedral_deg / th.min_dihedral_deg - 1.0,
                   r.min_radius_ratio / th.min_radius_ratio - 1.0,
                   th.max_dihedral_deg / r.max_dihedral_deg - 1.0});
}

// Delaunay can leave a few slivers whose four nodes all lie on the boundary (across the thin
// septum, whose faces carry near mirror-image meshes, or flat on the skin); gmsh's optimiser
// cannot move boundary nodes. Such slivers depend on the exact node placement, so we remesh
// with a slightly different size (a fixed sequence: deterministic) until none is left, and
// return the best try otherwise (the caller's quality check then reports it).
template <class MakeSize>
TetMesh generate_with_retries(MakeSize&& make_size, double optimise_threshold, const QualityThresholds& th) {
  constexpr double kScales[] = {1.0, 0.96, 1.04, 0.92, 1.08, 0.88, 1.12};
  TetMesh best;
  double best_score = -std::numeric_limits<double>::infinity();
  for (const double scale : kScales) {
    if (scale != kScales[0]) guarded("clearing the mesh", [] { gmsh::model::mesh::clear(); });
    const SizeSpec spec = make_size(scale);
    TetMesh trial = generate_tets(spec.field, spec.min, spec.max, optimise_threshold);
    const double score = worst_shape_margin(trial, th);
    if (score > best_score) {
      best_score = score;
      best = std::move(trial);
    }
    if (score >= 0) break;
  }
  return best;
}

// Which tag a boundary face gets: -1 untagged (outer skin), 0 base, 1 tip, 2 + k chamber k.
using Classifier = std::function<int(const Eigen::Vector3d& centroid)>;

void tag_boundary(TetMesh& m, int chambers, const Classifier& classify) {
  m.base_faces.clear();
  m.tip_faces.clear();
  m.chamber_faces.assign(chambers, {});
  for (const Tri& f : boundary_faces(m)) {
    const Eigen::Vector3d c = (m.nodes[f[0]] + m.nodes[f[1]] + m.nodes[f[2]]) / 3.0;
    const int tag = classify(c);
    if (tag == 0) m.base_faces.push_back(f);
    else if (tag == 1) m.tip_faces.push_back(f);
    else if (tag >= 2) m.chamber_faces.at(tag - 2).push_back(f);
  }
}

double radial(const Eigen::Vector3d& p) { return std::hypot(p.y(), p.z()); }

// Meshes the current gmsh model with one element size everywhere (validation primitives),
// using the default optimiser threshold and quality thresholds.
TetMesh generate_uniform(double size) {
  const MeshOptions defaults;
  return generate_with_retries(
      [size](double scale) {
        const double h = scale * size;
        return SizeSpec{[h](double, double, double) { return h; }, 0.5 * h, h};
      },
      defaults.optimise_threshold, defaults.quality);
}

}  // namespace

TetMesh mesh_whisker(const WhiskerGeometry& g, const MeshOptions& opt) {
  validate(g);
  if (!(opt.max_size_mm > 0 && opt.radius_factor > 0 && opt.wall_factor > 0 && opt.grading >= 0 &&
        opt.optimise_threshold >= 0 && opt.optimise_threshold <= 1)) {
    throw std::invalid_argument("mesh options: sizes and factors must be > 0, grading ≥ 0, threshold in [0, 1]");
  }
  const double L = g.length_mm, x0 = g.chamber_start(), x1 = g.chamber_end();
  const double rc = g.cavity_radius(), w = g.design.wall_mm;
  const int n = g.design.n;
  {
    GmshSession session;
    guarded("building the whisker geometry", [&] {
      namespace occ = gmsh::model::occ;
      const int cone = occ::addCone(0, 0, 0, L, 0, 0, g.base_radius(), g.tip_radius());
      gmsh::vectorpair cavities{{3, occ::addCylinder(x0, 0, 0, x1 - x0, 0, 0, rc)}};
      std::vector<gmsh::vectorpair> map;
      if (n == 2) {
        // Septum: a slab |z| < w/2 longer and wider than the cavity, cut out of the cylinder.
        const int slab = occ::addBox(x0 - 1, -rc - 1, -0.5 * w, x1 - x0 + 2, 2 * rc + 2, w);
        gmsh::vectorpair halves;
        occ::cut(cavities, {{3, slab}}, halves, map);
        cavities = halves;
      }
      gmsh::vectorpair body;
      occ::cut({{3, cone}}, cavities, body, map);
      occ::synchronize();
    });
    TetMesh m = generate_with_retries(
        [&](double scale) {
          const double h_wall = scale * opt.wall_factor * w;
          const double h_max = scale * opt.max_size_mm, k = scale * opt.radius_factor;
          return SizeSpec{[=, &g](double x, double, double) {
                            const double far = std::min(h_max, k * g.outer_radius(x));
                            const double d = x < x0 ? x0 - x : (x > x1 ? x - x1 : 0.0);
                            return std::min(far, h_wall + opt.grading * d);
                          },
                          0.5 * std::min(h_wall, k * g.tip_radius()), h_max};
        },
        opt.optimise_threshold, opt.quality);

    // Geometric classification of boundary faces by centroid. Planar faces lie exactly on their
    // plane (up to round-off); curved-surface facets deviate from the surface by at most the
    // chord sagitta, far below w/2, the gap between cavity and outer skin.
    const double tol = 1e-6 * L;
    tag_boundary(m, n, [&](const Eigen::Vector3d& c) {
      if (std::abs(c.x()) < tol) return 0;
      if (std::abs(c.x() - L) < tol) return 1;
      const bool in_chamber_x = c.x() > x0 - tol && c.x() < x1 + tol;
      if (in_chamber_x && radial(c) < rc + 0.5 * w) return n == 1 ? 2 : (c.z() > 0 ? 2 : 3);
      return -1;
    });
    return m;
  }
}

TetMesh mesh_cylinder(double radius, double length, double size) {
  if (!(radius > 0 && length > 0 && size > 0)) throw std::invalid_argument("mesh_cylinder: sizes must be > 0");
  GmshSession session;
  guarded("building a cylinder", [&] {
    gmsh::model::occ::addCylinder(0, 0, 0, length, 0, 0, radius);
    gmsh::model::occ::synchronize();
  });
  TetMesh m = generate_uniform(size);
  const double tol = 1e-6 * length;
  tag_boundary(m, 0, [&](const Eigen::Vector3d& c) {
    if (std::abs(c.x()) < tol) return 0;
    if (std::abs(c.x() - length) < tol) return 1;
    return -1;
  });
  return m;
}

TetMesh mesh_hollow_cylinder(double r_in, double r_out, double length, double size) {
  if (!(r_in > 0 && r_out > r_in && length > 0 && size > 0)) {
    throw std::invalid_argument("mesh_hollow_cylinder: need 0 < r_in < r_out, length and size > 0");
  }
  GmshSession session;
  guarded("building a hollow cylinder", [&] {
    namespace occ = gmsh::model::occ;
    const int outer = occ::addCylinder(0, 0, 0, length, 0, 0, r_out);
    const int inner = occ::addCylinder(0, 0, 0, length, 0, 0, r_in);
    gmsh::vectorpair out;
    std::vector<gmsh::vectorpair> map;
    occ::cut({{3, outer}}, {{3, inner}}, out, map);
    occ::synchronize();
  });
  TetMesh m = generate_uniform(size);
  const double tol = 1e-6 * length;
  const double mid = 0.5 * (r_in + r_out);
  tag_boundary(m, 1, [&](const Eigen::Vector3d& c) {
    if (std::abs(c.x()) < tol) return 0;
    if (std::abs(c.x() - length) < tol) return 1;
    return radial(c) < mid ? 2 : -1;
  });
  return m;
}

}  // namespace codesign::fem
