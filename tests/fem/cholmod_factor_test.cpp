// CholmodFactor: the 3×3 block triangular solves (dofs_per_node = 3) against a dense
// solution, against CHOLMOD's own solve, and the fallback where a matrix lacks dense node blocks.
//
// Tolerance: a backward-stable solve has a forward error of at most about c·n·κ·ε with ε = 2.2e-16;
// the test matrices are made well conditioned (κ is computed below, under 100), and c·n is
// taken as 1e3, giving bounds of about 1e-11 relative. An error in one index or one block
// value gives an O(1) error.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "fem/box_mesh.hpp"
#include "fem/cholmod_factor.hpp"

namespace codesign::fem {
namespace {

struct Upper {
  int n = 0;
  std::vector<int> colptr, rowind;
  std::vector<double> values;
};

// Upper triangle (sorted rows per column) of a dense symmetric matrix's nonzeros.
Upper upper_of(const Eigen::MatrixXd& A) {
  Upper u;
  u.n = static_cast<int>(A.rows());
  u.colptr.push_back(0);
  for (int j = 0; j < u.n; ++j) {
    for (int i = 0; i <= j; ++i)
      if (A(i, j) != 0.0) u.rowind.push_back(i), u.values.push_back(A(i, j));
    u.colptr.push_back(static_cast<int>(u.rowind.size()));
  }
  return u;
}

// A symmetric positive definite matrix with the node-block sparsity of a tetrahedral mesh:
// per element a random 12×12 Gram matrix, plus a diagonal shift that bounds the condition number.
Eigen::MatrixXd mesh_matrix(const TetMesh& mesh, std::mt19937& rng) {
  const int n = 3 * static_cast<int>(mesh.nodes.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  std::normal_distribution<double> g(0.0, 1.0);
  for (const Tet& t : mesh.tets) {
    Eigen::MatrixXd G(12, 12);
    for (int i = 0; i < 144; ++i) G(i) = g(rng);
    const Eigen::MatrixXd K = G * G.transpose() / 12.0;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) A.block<3, 3>(3 * t[a], 3 * t[b]) += K.block<3, 3>(3 * a, 3 * b);
  }
  A += 10.0 * Eigen::MatrixXd::Identity(n, n);
  return A;
}

double condition(const Eigen::MatrixXd& A) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  return es.eigenvalues().maxCoeff() / es.eigenvalues().minCoeff();
}

TEST(CholmodFactor, BlockSolvesMatchADenseSolveAndCholmodsOwn) {
  std::mt19937 rng(7);
  const TetMesh mesh = make_box_mesh(4.0, 1.0, 1.0, 4, 2, 2);
  const Eigen::MatrixXd A = mesh_matrix(mesh, rng);
  const double kappa = condition(A);
  ASSERT_LT(kappa, 100.0);
  const double bound = 1e3 * kappa * 2.2e-16;
  const Upper u = upper_of(A);
  Eigen::VectorXd b(u.n);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int i = 0; i < u.n; ++i) b[i] = g(rng);
  const Eigen::VectorXd x_dense = A.ldlt().solve(b);

  CholmodFactor blocked, scalar;
  blocked.analyse(u.n, u.colptr, u.rowind, 3);
  scalar.analyse(u.n, u.colptr, u.rowind);
  ASSERT_TRUE(blocked.factorise(u.values));
  ASSERT_TRUE(scalar.factorise(u.values));
  EXPECT_TRUE(blocked.block_solves());
  EXPECT_FALSE(scalar.block_solves());
  Eigen::VectorXd xb(u.n), xs(u.n);
  blocked.solve(b.data(), xb.data());
  scalar.solve(b.data(), xs.data());
  EXPECT_LT((xb - x_dense).norm(), bound * x_dense.norm());
  EXPECT_LT((xs - x_dense).norm(), bound * x_dense.norm());

  // Several right-hand sides at once, and a second factorisation with new values.
  Eigen::MatrixXd B(u.n, 3), X;
  for (int i = 0; i < B.size(); ++i) B(i) = g(rng);
  blocked.solve(B, X);
  EXPECT_LT((X - A.ldlt().solve(B)).norm(), bound * X.norm());
  const Eigen::MatrixXd A2 = mesh_matrix(mesh, rng);
  const Upper u2 = upper_of(A2);
  ASSERT_EQ(u2.rowind, u.rowind);
  ASSERT_TRUE(blocked.factorise(u2.values));
  EXPECT_TRUE(blocked.block_solves());
  blocked.solve(b.data(), xb.data());
  const Eigen::VectorXd x2 = A2.ldlt().solve(b);
  EXPECT_LT((xb - x2).norm(), 1e3 * condition(A2) * 2.2e-16 * x2.norm());
}

TEST(CholmodFactor, FallsBackToCholmodsSolveWithoutDenseNodeBlocks) {
  // A diagonal matrix has no 3×3 node blocks: the factor is solved by CHOLMOD itself.
  const int n = 9;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) A(i, i) = 1.0 + i;
  const Upper u = upper_of(A);
  CholmodFactor f;
  f.analyse(n, u.colptr, u.rowind, 3);
  ASSERT_TRUE(f.factorise(u.values));
  EXPECT_FALSE(f.block_solves());
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, 1.0, 9.0), x(n);
  f.solve(b.data(), x.data());
  for (int i = 0; i < n; ++i) EXPECT_NEAR(x[i], b[i] / (1.0 + i), 1e-15);
}

TEST(CholmodFactor, ReportsAnIndefiniteMatrix) {
  std::mt19937 rng(8);
  const TetMesh mesh = make_box_mesh(2.0, 1.0, 1.0, 2, 1, 1);
  Eigen::MatrixXd A = mesh_matrix(mesh, rng);
  A(4, 4) = -1.0;
  const Upper u = upper_of(A);
  CholmodFactor f;
  f.analyse(u.n, u.colptr, u.rowind, 3);
  EXPECT_FALSE(f.factorise(u.values));
  EXPECT_FALSE(f.block_solves());
}

}  // namespace
}  // namespace codesign::fem
