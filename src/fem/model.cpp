#include "fem/model.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

namespace codesign::fem {

namespace {

std::vector<int> nodes_of(const std::vector<Tri>& faces) {
  std::set<int> s;
  for (const Tri& f : faces) s.insert(f.begin(), f.end());
  return {s.begin(), s.end()};
}

// Nodes on the boundary: nodes of faces that belong to exactly one tet.
std::vector<char> surface_flags(const TetMesh& m) {
  std::map<std::array<int, 3>, int> count;
  static const int faces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  for (const Tet& t : m.tets)
    for (const auto& f : faces) {
      std::array<int, 3> k{t[f[0]], t[f[1]], t[f[2]]};
      std::sort(k.begin(), k.end());
      ++count[k];
    }
  std::vector<char> flag(m.nodes.size(), 0);
  for (const auto& [k, c] : count)
    if (c == 1)
      for (int n : k) flag[n] = 1;
  return flag;
}

}  // namespace

std::shared_ptr<const Model> build_model(TetMesh mesh, const ModelOptions& options) {
  if (mesh.tets.empty()) throw std::invalid_argument("build_model: mesh has no tetrahedra");
  if (mesh.base_faces.empty()) throw std::invalid_argument("build_model: mesh has no base (clamped) faces");
  if (mesh.tip_faces.empty()) throw std::invalid_argument("build_model: mesh has no tip faces");
  auto m = std::make_shared<Model>();
  m->material = options.material;
  const int n = static_cast<int>(mesh.nodes.size());
  m->rest_positions.resize(3 * n);
  for (int i = 0; i < n; ++i) m->rest_positions.segment<3>(3 * i) = mesh.nodes[i];
  m->rest.reserve(mesh.tets.size());
  Eigen::VectorXd node_volume = Eigen::VectorXd::Zero(n);
  for (const Tet& t : mesh.tets) {
    for (int a : t)
      if (a < 0 || a >= n) throw std::invalid_argument("build_model: tet refers to a missing node");
    m->rest.push_back(make_tet_rest({mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]], mesh.nodes[t[3]]}));
    m->volume_mm3 += m->rest.back().volume;
    for (int a : t) node_volume[a] += 0.25 * m->rest.back().volume;
  }
  m->lumped_mass = node_volume * (m->material.total_mass_g / m->volume_mm3);
  for (int i = 0; i < n; ++i)
    if (!(m->lumped_mass[i] > 0.0)) throw std::invalid_argument("build_model: node not attached to any tet");
  m->length_mm = -1e300;
  for (const auto& x : mesh.nodes) m->length_mm = std::max(m->length_mm, x.x());
  m->base_nodes = nodes_of(mesh.base_faces);
  m->tip_nodes = nodes_of(mesh.tip_faces);
  m->is_base.assign(n, 0);
  for (int b : m->base_nodes) m->is_base[b] = 1;
  const std::vector<char> surf = surface_flags(mesh);
  for (int i = 0; i < n; ++i)
    if (surf[i] && !m->is_base[i] && mesh.nodes[i].x() >= m->length_mm - options.tip_region_mm)
      m->contact_nodes.push_back(i);
  // Chamber sensing region.
  if (!mesh.chamber_faces.empty()) {
    double lo = 1e300, hi = -1e300;
    for (const auto& ch : mesh.chamber_faces)
      for (const Tri& f : ch)
        for (int a : f) lo = std::min(lo, mesh.nodes[a].x()), hi = std::max(hi, mesh.nodes[a].x());
    m->chamber_x0 = lo;
    m->chamber_x1 = hi;
  }
  if (!(m->chamber_x1 > m->chamber_x0)) {
    m->chamber_x0 = 0.0;
    m->chamber_x1 = m->length_mm;
  }
  for (int e = 0; e < static_cast<int>(mesh.tets.size()); ++e) {
    const Tet& t = mesh.tets[e];
    const double cx = 0.25 * (mesh.nodes[t[0]].x() + mesh.nodes[t[1]].x() + mesh.nodes[t[2]].x() + mesh.nodes[t[3]].x());
    if (cx >= m->chamber_x0 && cx <= m->chamber_x1) {
      m->chamber_tets.push_back(e);
      m->chamber_volume_mm3 += m->rest[e].volume;
    }
  }
  m->fibres = make_fibre_springs(mesh, options.fibre_polylines, options.fibre_axial_stiffness_uN);
  for (const auto& chain : options.fibre_chains)
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
      for (const EmbeddedPoint* p : {&chain[i], &chain[i + 1]})
        if (p->tet < 0 || p->tet >= static_cast<int>(mesh.tets.size()))
          throw std::invalid_argument("build_model: fibre point embedded in a missing tet");
      const double len = (embedded_position(mesh, chain[i], m->rest_positions) -
                          embedded_position(mesh, chain[i + 1], m->rest_positions)).norm();
      if (!(len > 1e-9)) continue;
      m->fibres.push_back({chain[i], chain[i + 1], len, options.fibre_axial_stiffness_uN / len});
    }
  if (!(options.fibre_axial_stiffness_uN > 0.0)) m->fibres.clear();
  m->fibres_tension_only = options.fibres_tension_only;
  m->mesh = std::move(mesh);
  return m;
}

}  // namespace codesign::fem
