#include "rl/gemm.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "rl/mlp.hpp"
#include "rl/rng.hpp"

namespace codesign::rl {
namespace {

Eigen::MatrixXf random_matrix(Eigen::Index r, Eigen::Index c, Rng& rng) {
  Eigen::MatrixXf m(r, c);
  for (Eigen::Index i = 0; i < m.size(); ++i) m(i) = static_cast<float>(rng.normal());
  return m;
}

// Float GEMM error bound (Higham, Thm 3.5 with the final rounding): every entry satisfies
//   |fl(C) - C| <= gamma_{k+1} (|A| |B|),  gamma_n = n u / (1 - n u),  u = 2^-24,
// whatever the summation order, so it holds for the blocked kernel and for Eigen alike.
void check_shape(bool ta, bool tb, Eigen::Index m, Eigen::Index n, Eigen::Index k) {
  Rng rng(static_cast<std::uint64_t>(m * 1000003 + n * 1009 + k * 7 + ta * 2 + tb));
  const Eigen::MatrixXf a = ta ? random_matrix(k, m, rng) : random_matrix(m, k, rng);
  const Eigen::MatrixXf b = tb ? random_matrix(n, k, rng) : random_matrix(k, n, rng);
  Eigen::MatrixXf c = Eigen::MatrixXf::Constant(m, n, 1e30f);  // must be overwritten
  GemmWorkspace ws;
  sgemm(ta, tb, m, n, k, a.data(), a.rows(), b.data(), b.rows(), c.data(), m, ws);
  const Eigen::MatrixXd ad = ta ? Eigen::MatrixXd(a.cast<double>().transpose()) : a.cast<double>();
  const Eigen::MatrixXd bd = tb ? Eigen::MatrixXd(b.cast<double>().transpose()) : b.cast<double>();
  const Eigen::MatrixXd exact = ad * bd;
  const Eigen::MatrixXd magnitude = ad.cwiseAbs() * bd.cwiseAbs();
  const double u = std::ldexp(1.0, -24);
  const double gamma = (k + 1) * u / (1 - (k + 1) * u);
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < m; ++i)
      ASSERT_LE(std::abs(c(i, j) - exact(i, j)), gamma * magnitude(i, j))
          << "ta " << ta << " tb " << tb << " m " << m << " n " << n << " k " << k << " at (" << i
          << ", " << j << ")";
}

TEST(Sgemm, MatchesExactProductWithinRoundingBoundForAllTransposesAndEdges) {
  if (!fast_gemm_available()) GTEST_SKIP() << "built without AVX-512";
  // Multiples of the 32 x 12 tile, ragged edges, and K beyond one 256 block.
  const Eigen::Index shapes[][3] = {{64, 48, 32}, {512, 256, 512}, {37, 13, 5},
                                    {100, 50, 300}, {1, 1, 1},     {33, 25, 257}};
  for (const auto& s : shapes)
    for (bool ta : {false, true})
      for (bool tb : {false, true}) check_shape(ta, tb, s[0], s[1], s[2]);
}

TEST(Sgemm, FloatMlpOnTheFastPathAgreesWithDoubleMlp) {
  // Layer shapes large enough for the fast GEMM in forward, weight gradient and input gradient.
  Rng rng(8);
  MlpT<double> md({6, 96, 80, 1});
  md.init_orthogonal(1.0, rng);
  Mlp mf({6, 96, 80, 1});
  mf.params() = md.params().cast<float>();
  const Eigen::MatrixXf x = random_matrix(6, 40, rng);
  const Eigen::MatrixXf d_out = random_matrix(1, 40, rng);
  MlpT<double>::Cache cd;
  Mlp::Cache cf;
  md.forward(x.cast<double>(), cd);
  mf.forward(x, cf);
  Eigen::VectorXd gd(md.num_params());
  Eigen::VectorXf gf(mf.num_params());
  md.backward(cd, d_out.cast<double>(), gd);
  mf.backward(cf, d_out, gf);
  // float32 rounding through three layers of ~100-term sums: ~100 * 6e-8 relative per GEMM;
  // 1e-4 of the largest entry bounds it with a wide margin, a wrong index does not pass.
  EXPECT_LT((cf.a.back().cast<double>() - cd.a.back()).cwiseAbs().maxCoeff(),
            1e-4 * cd.a.back().cwiseAbs().maxCoeff());
  EXPECT_LT((gf.cast<double>() - gd).cwiseAbs().maxCoeff(), 1e-4 * gd.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace codesign::rl
