#include "cluster/mesh_messages.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "fem/design.hpp"

namespace codesign::cluster {

namespace {

template <std::size_t K>
void put_indices(std::vector<double>& v, const std::vector<std::array<int, K>>& items) {
  for (const auto& item : items)
    for (int a : item) v.push_back(static_cast<double>(a));
}

// Reads v from `at` on, refusing to run past its end.
struct Reader {
  const std::vector<double>& v;
  std::size_t at = 0;
  double next() {
    if (at >= v.size()) throw std::invalid_argument("unpack_meshes: the message ends inside a mesh");
    return v[at++];
  }
  // A non-negative integer below `bound`.
  std::size_t index(double bound, const char* what) {
    const double x = next();
    if (!(x >= 0.0 && x < bound) || std::floor(x) != x)
      throw std::invalid_argument(std::string("unpack_meshes: ") + what + " is not an integer of its range");
    return static_cast<std::size_t>(x);
  }
  // A count whose items of `width` numbers each fit in what is left of the message.
  std::size_t count(std::size_t width, const char* what) {
    const std::size_t left = v.size() - at;
    return index(static_cast<double>(left / width + 1), what);
  }
  template <std::size_t K>
  void indices(std::vector<std::array<int, K>>& items, std::size_t n, std::size_t nodes, const char* what) {
    items.resize(n);
    for (auto& item : items)
      for (int& a : item) a = static_cast<int>(index(static_cast<double>(nodes), what));
  }
};

}  // namespace

std::vector<double> pack_meshes(const std::vector<int>& designs, const std::vector<const fem::TetMesh*>& meshes) {
  if (designs.size() != meshes.size()) throw std::invalid_argument("pack_meshes: one mesh per design");
  std::vector<double> v{static_cast<double>(designs.size())};
  for (std::size_t k = 0; k < designs.size(); ++k) {
    if (!meshes[k]) throw std::invalid_argument("pack_meshes: no mesh");
    const fem::TetMesh& m = *meshes[k];
    v.insert(v.end(), {static_cast<double>(designs[k]), static_cast<double>(m.nodes.size()),
                       static_cast<double>(m.tets.size()), static_cast<double>(m.base_faces.size()),
                       static_cast<double>(m.tip_faces.size()), static_cast<double>(m.chamber_faces.size())});
    for (const auto& c : m.chamber_faces) v.push_back(static_cast<double>(c.size()));
    for (const Eigen::Vector3d& x : m.nodes) v.insert(v.end(), {x.x(), x.y(), x.z()});
    put_indices(v, m.tets);
    put_indices(v, m.base_faces);
    put_indices(v, m.tip_faces);
    for (const auto& c : m.chamber_faces) put_indices(v, c);
  }
  return v;
}

std::vector<DesignMesh> unpack_meshes(const std::vector<double>& v) {
  Reader r{v};
  const std::size_t n = r.count(6, "the number of meshes");  // a mesh takes at least 6 numbers
  std::vector<DesignMesh> out(n);
  for (DesignMesh& d : out) {
    d.design = static_cast<int>(r.index(fem::kDesignCount, "a design"));
    const std::size_t nodes = r.count(3, "a node count"), tets = r.count(4, "a tet count"),
                      base = r.count(3, "a base face count"), tip = r.count(3, "a tip face count"),
                      chambers = r.count(1, "a chamber count");
    std::vector<std::size_t> chamber_faces(chambers);
    for (std::size_t& c : chamber_faces) c = r.count(3, "a chamber's face count");
    d.mesh.nodes.resize(nodes);
    for (Eigen::Vector3d& x : d.mesh.nodes) {
      const double a = r.next(), b = r.next(), c = r.next();
      x = {a, b, c};
    }
    r.indices(d.mesh.tets, tets, nodes, "a tet's node");
    r.indices(d.mesh.base_faces, base, nodes, "a base face's node");
    r.indices(d.mesh.tip_faces, tip, nodes, "a tip face's node");
    d.mesh.chamber_faces.resize(chambers);
    for (std::size_t c = 0; c < chambers; ++c)
      r.indices(d.mesh.chamber_faces[c], chamber_faces[c], nodes, "a chamber face's node");
  }
  if (r.at != v.size()) throw std::invalid_argument("unpack_meshes: numbers after the last mesh");
  return out;
}

}  // namespace codesign::cluster
