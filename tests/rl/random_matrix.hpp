#pragma once
// Test helper: a float matrix of independent N(0, 1) entries from the project's Rng.
#include <Eigen/Core>

#include "rl/rng.hpp"

namespace codesign::rl::test {

inline Eigen::MatrixXf random_matrix(Eigen::Index rows, Eigen::Index cols, Rng& rng) {
  Eigen::MatrixXf m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) m(i) = static_cast<float>(rng.normal());
  return m;
}

}  // namespace codesign::rl::test
