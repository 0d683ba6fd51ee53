// Pre-packed bf16 operands (pack_bf16, pack_bf16_both, gemm_bf16_packed) against gemm_bf16.
//
// Both routes round the same entries to bf16 and run the same kernel over the same packed
// layout in the same order, so the results must be bit-identical: any difference is a packing
// error (a wrong index, a missed pair, a stale block), not rounding. The accuracy of gemm_bf16
// itself is checked against exact products in gemm_test.cpp.
#include <gtest/gtest.h>

#include "rl/gemm.hpp"
#include "rl/rng.hpp"
#include "random_matrix.hpp"

namespace codesign::rl {
namespace {

using test::random_matrix;

// W is m x k. Checks W * B1 (B1 k x n) and W^T * B2 (B2 m x n) through the packed operands of
// pack_bf16_both, and both again through pack_bf16, against gemm_bf16.
void check_both(Eigen::Index m, Eigen::Index k, Eigen::Index n) {
  Rng rng(static_cast<std::uint64_t>(m * 7919 + k * 31 + n));
  const Eigen::MatrixXf w = random_matrix(m, k, rng);
  const Eigen::MatrixXf b1 = random_matrix(k, n, rng);
  const Eigen::MatrixXf b2 = random_matrix(m, n, rng);
  GemmWorkspace ws;
  Eigen::MatrixXf ref1(m, n), ref2(k, n);
  gemm_bf16(false, false, m, n, k, w.data(), m, b1.data(), k, ref1.data(), m, ws);
  gemm_bf16(true, false, k, n, m, w.data(), m, b2.data(), m, ref2.data(), k, ws);

  PackedBf16 plain, transposed;
  // Pre-fill with garbage so that a block the packer forgets to write shows up.
  plain.data.assign(static_cast<std::size_t>(4 * m * k + 4096), 0x7fc0);
  transposed.data.assign(static_cast<std::size_t>(4 * m * k + 4096), 0x7fc0);
  pack_bf16_both(m, k, w.data(), m, plain, transposed);
  ASSERT_EQ(plain.m, m);
  ASSERT_EQ(plain.k, k);
  ASSERT_EQ(transposed.m, k);
  ASSERT_EQ(transposed.k, m);
  Eigen::MatrixXf c1 = Eigen::MatrixXf::Constant(m, n, 1e30f);
  Eigen::MatrixXf c2 = Eigen::MatrixXf::Constant(k, n, 1e30f);
  gemm_bf16_packed(plain, false, n, b1.data(), k, c1.data(), m, ws);
  gemm_bf16_packed(transposed, false, n, b2.data(), m, c2.data(), k, ws);
  EXPECT_EQ(c1, ref1) << "W B, m " << m << " k " << k << " n " << n;
  EXPECT_EQ(c2, ref2) << "W^T B, m " << m << " k " << k << " n " << n;

  PackedBf16 single;
  pack_bf16(false, m, k, w.data(), m, single);
  Eigen::MatrixXf c3 = Eigen::MatrixXf::Constant(m, n, 1e30f);
  gemm_bf16_packed(single, false, n, b1.data(), k, c3.data(), m, ws);
  EXPECT_EQ(c3, ref1) << "pack_bf16 plain, m " << m << " k " << k;
  pack_bf16(true, k, m, w.data(), m, single);  // reuse: repacking another shape into it
  Eigen::MatrixXf c4 = Eigen::MatrixXf::Constant(k, n, 1e30f);
  gemm_bf16_packed(single, false, n, b2.data(), m, c4.data(), k, ws);
  EXPECT_EQ(c4, ref2) << "pack_bf16 transposed, m " << m << " k " << k;
}

TEST(GemmBf16Packed, BothLayoutsFromOnePassEqualUnpackedProducts) {
  if (!bf16_gemm_available()) GTEST_SKIP() << "built without AVX-512 BF16";
  // One-pass path: m, k multiples of 32 up to 512 (the paper's 512 x 512 hidden layers, and
  // non-square); two-pass path: ragged sizes and sizes beyond one 512 K block.
  const Eigen::Index shapes[][3] = {{512, 512, 256}, {64, 96, 40}, {96, 64, 208},
                                    {40, 70, 33},    {600, 64, 16}, {64, 1030, 24}};
  for (const auto& s : shapes) check_both(s[0], s[1], s[2]);
}

}  // namespace
}  // namespace codesign::rl
