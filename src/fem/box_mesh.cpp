#include "fem/box_mesh.hpp"

#include <Eigen/Dense>

#include <stdexcept>

namespace codesign::fem {

namespace {

Tri oriented(const TetMesh& m, Tri f, const Eigen::Vector3d& outward) {
  const Eigen::Vector3d n = (m.nodes[f[1]] - m.nodes[f[0]]).cross(m.nodes[f[2]] - m.nodes[f[0]]);
  if (n.dot(outward) < 0.0) std::swap(f[1], f[2]);
  return f;
}

}  // namespace

TetMesh make_box_mesh(double length, double width, double height, int nx, int ny, int nz) {
  if (nx < 1 || ny < 1 || nz < 1 || !(length > 0) || !(width > 0) || !(height > 0))
    throw std::invalid_argument("make_box_mesh: sizes and cell counts must be positive");
  TetMesh m;
  auto id = [&](int i, int j, int k) { return (i * (ny + 1) + j) * (nz + 1) + k; };
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= ny; ++j)
      for (int k = 0; k <= nz; ++k)
        m.nodes.emplace_back(length * i / nx, width * (double(j) / ny - 0.5), height * (double(k) / nz - 0.5));
  // Kuhn split of the unit cube along the diagonal 0 → 7: six paths through the axes.
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        for (const auto& p : perms) {
          int c[3] = {i, j, k};
          Tet t;
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          const Eigen::Vector3d& x0 = m.nodes[t[0]];
          const double det = (m.nodes[t[1]] - x0).dot((m.nodes[t[2]] - x0).cross(m.nodes[t[3]] - x0));
          if (det < 0.0) std::swap(t[2], t[3]);
          m.tets.push_back(t);
        }
  for (int j = 0; j < ny; ++j)
    for (int k = 0; k < nz; ++k) {
      for (int side = 0; side < 2; ++side) {
        const int i = side == 0 ? 0 : nx;
        const Eigen::Vector3d out(side == 0 ? -1.0 : 1.0, 0.0, 0.0);
        auto& faces = side == 0 ? m.base_faces : m.tip_faces;
        faces.push_back(oriented(m, {id(i, j, k), id(i, j + 1, k), id(i, j + 1, k + 1)}, out));
        faces.push_back(oriented(m, {id(i, j, k), id(i, j + 1, k + 1), id(i, j, k + 1)}, out));
      }
    }
  return m;
}

}  // namespace codesign::fem
