#pragma once
// Mesh-test helpers (used by tests/fem, tests/io and tests/apps, which sit above fem): a
// scratch directory per test process, and the area bounds of a meshed disc.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "fem/mesh.hpp"

#include <unistd.h>

namespace codesign::test {

inline std::filesystem::path scratch_dir() {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("codesign_mesh_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

// Bounds of the area of a flat disc of radius r meshed by `faces` whose rim nodes lie on the
// circle: the rim is an inscribed polygon with chords ≤ e (the longest rim edge), each chord
// spanning φ_i ≤ φ = 2 asin(e / 2r); its area ½ r² Σ sin φ_i (Σ φ_i = 2π) is therefore within
// [π r² sin(φ)/φ, π r²].
inline std::pair<double, double> disc_area_bounds(const fem::TetMesh& m, const std::vector<fem::Tri>& faces, double r) {
  std::map<std::pair<int, int>, int> use;
  for (const auto& f : faces)
    for (int k = 0; k < 3; ++k) ++use[{std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])}];
  double e = 0;
  for (const auto& [edge, n] : use)
    if (n == 1) e = std::max(e, (m.nodes[edge.first] - m.nodes[edge.second]).norm());
  const double phi = 2 * std::asin(std::min(1.0, e / (2 * r)));
  const double full = std::numbers::pi * r * r;
  return {full * std::sin(phi) / phi * (1 - 1e-12), full * (1 + 1e-12)};  // 1e-12: round-off
}

}  // namespace codesign::test
