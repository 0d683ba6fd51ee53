#include "rl/gemm.hpp"

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "rl/mlp.hpp"
#include "rl/rng.hpp"
#include "random_matrix.hpp"

namespace codesign::rl {
namespace {

using test::random_matrix;

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

// ---------------------------------------------------------------------------------------------
// Mixed precision: gemm_bf16 (operands rounded to bfloat16, sums in float32).
// ---------------------------------------------------------------------------------------------

constexpr double kU16 = 0x1p-8;   // unit roundoff of bfloat16 (8 significant bits, nearest even)
constexpr double kU32 = 0x1p-24;  // unit roundoff of float32
constexpr double kU64 = 0x1p-53;  // unit roundoff of float64

// Higham's gamma_n = n u / (1 - n u): bound on the relative error of n rounding factors.
double gamma_n(double n, double u) { return n * u / (1 - n * u); }

// A column-major matrix with leading dimension rows + pad; the pad rows hold NaN, so a read
// outside the matrix turns the affected entries of the result into NaN (and fails the bound).
struct Strided {
  Eigen::MatrixXf storage;
  Eigen::Index rows, pad;
  Strided(Eigen::Index r, Eigen::Index c, Eigen::Index p, Rng& rng)
      : storage(Eigen::MatrixXf::Constant(r + p, c, std::numeric_limits<float>::quiet_NaN())),
        rows(r), pad(p) {
    storage.topRows(r) = random_matrix(r, c, rng);
  }
  const float* data() const { return storage.data(); }
  Eigen::Index ld() const { return rows + pad; }
  Eigen::MatrixXd as_double() const { return storage.topRows(rows).cast<double>(); }
};

// Every entry of X rounded to bfloat16 by the scalar conversion (checked in Bf16Conversion).
Eigen::MatrixXd bf16_rounded(const Eigen::MatrixXd& x) {
  return x.unaryExpr([](double v) {
    return static_cast<double>(bf16_to_float(float_to_bf16(static_cast<float>(v))));
  });
}

// Two bounds per entry of C = gemm_bf16(op(A), op(B)), op(A) m x k, op(B) k x n:
//
// (1) Against the exact product of the ORIGINAL float inputs (the contract in gemm.hpp):
//       |C - A B| <= (2 u16 + u16^2 + gamma_{k+1} (1 + u16)^2) (|A| |B|)_ij.
//     Each operand entry is rounded to bf16 with relative error <= u16, so a product of two
//     rounded entries is a b (1 + t), |t| <= (1 + u16)^2 - 1 = 2 u16 + u16^2; that product of two
//     8-bit significands has 16 bits and is exact in float32 (vdpbf16ps does not round it); the
//     float32 sums of the k products, in whatever order and blocking (pairs inside vdpbf16ps,
//     lanes, K blocks of 512 added through C or the scratch tile), add at most gamma_{k-1} of the
//     sum of their magnitudes (Higham, Lemma 3.4), and those magnitudes are <= (1 + u16)^2 |a b|;
//     gamma_{k+1} leaves room for the final accumulate/store.
// (2) Against the exact product of the bf16-ROUNDED inputs (A^, B^ by float_to_bf16):
//       |C - A^ B^| <= gamma_{k+1} (|A^| |B^|)_ij <= gamma_{k+1} (1 + u16)^2 (|A| |B|)_ij,
//     the same argument without the operand rounding. This bound is ~2^16 times tighter than (1):
//     it fails if the kernel drops, duplicates or misplaces a single product, or rounds an operand
//     differently from round-to-nearest-even (e.g. truncates), which (1) alone might not see.
// The references are computed in double: products of floats (24-bit significands) are exact in
// double, and the double sums add at most gamma_k(u64) (|A| |B|) (~6e-14 relative for k = 514),
// added to both bounds as 2 gamma_k(u64) |A||B| (error of the reference plus of |A||B| itself).
// Denormals: vcvtne2ps2bf16 and vdpbf16ps treat denormal inputs/outputs as zero, which the bound
// does not model; the inputs are N(0, 1) floats (|x| > 1e-30 with overwhelming probability, far
// above FLT_MIN ~ 1.2e-38) and products/sums of such numbers stay far from the denormal range
// except through exact cancellation, whose flush error (< 2^-126) is negligible against the bound.
void check_bf16_shape(bool ta, bool tb, Eigen::Index m, Eigen::Index n, Eigen::Index k) {
  Rng rng(static_cast<std::uint64_t>(m * 1000003 + n * 1009 + k * 7 + ta * 2 + tb + 555));
  // Leading dimensions larger than the row count (pads 3, 5, 2): the kernel must honour lda,
  // ldb, ldc and neither read nor write outside the matrices.
  const Strided a = ta ? Strided(k, m, 3, rng) : Strided(m, k, 3, rng);
  const Strided b = tb ? Strided(n, k, 5, rng) : Strided(k, n, 5, rng);
  const Eigen::Index ldc = m + 2;
  Eigen::MatrixXf c_store = Eigen::MatrixXf::Constant(ldc, n, -7.0f);  // pad rows: sentinel
  c_store.topRows(m).setConstant(1e30f);                                 // must be overwritten
  GemmWorkspace ws;
  gemm_bf16(ta, tb, m, n, k, a.data(), a.ld(), b.data(), b.ld(), c_store.data(), ldc, ws);

  const Eigen::MatrixXd ad = ta ? Eigen::MatrixXd(a.as_double().transpose()) : a.as_double();
  const Eigen::MatrixXd bd = tb ? Eigen::MatrixXd(b.as_double().transpose()) : b.as_double();
  const Eigen::MatrixXd exact = ad * bd;
  const Eigen::MatrixXd exact_rounded = bf16_rounded(ad) * bf16_rounded(bd);
  const Eigen::MatrixXd magnitude = ad.cwiseAbs() * bd.cwiseAbs();
  const double g = gamma_n(static_cast<double>(k + 1), kU32);
  const double ref = 2 * gamma_n(static_cast<double>(k), kU64);
  const double c_vs_exact = 2 * kU16 + kU16 * kU16 + g * (1 + kU16) * (1 + kU16) + ref;
  const double c_vs_rounded = g * (1 + kU16) * (1 + kU16) + ref;
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < m; ++i) {
      const double cij = c_store(i, j);
      ASSERT_LE(std::abs(cij - exact(i, j)), c_vs_exact * magnitude(i, j))
          << "vs exact: ta " << ta << " tb " << tb << " m " << m << " n " << n << " k " << k
          << " at (" << i << ", " << j << ")";
      ASSERT_LE(std::abs(cij - exact_rounded(i, j)), c_vs_rounded * magnitude(i, j))
          << "vs bf16-rounded operands: ta " << ta << " tb " << tb << " m " << m << " n " << n
          << " k " << k << " at (" << i << ", " << j << ")";
    }
    for (Eigen::Index i = m; i < ldc; ++i)
      ASSERT_EQ(c_store(i, j), -7.0f) << "write outside C: ta " << ta << " tb " << tb << " m " << m
                                      << " n " << n << " k " << k << " at (" << i << ", " << j
                                      << ")";
  }
}

TEST(GemmBf16, MatchesExactProductWithinBf16RoundingBound) {
  if (!bf16_gemm_available()) GTEST_SKIP() << "built without AVX-512 BF16";
  // Register tile 32 rows x 8 columns; K in blocks of 512; the vectorised packers need full
  // panels and k % 32 == 0 (transposing paths) or k even (the others):
  //   {512, 256, 512} {64, 48, 32} {96, 40, 64} {64, 208, 512}: full tiles, all vectorised packers;
  //   {37, 13, 5} {1, 1, 1}: odd k, tiny: generic packers, scratch tile for every entry;
  //   {100, 50, 300}: k even but not a multiple of 32: vectorised non-transposing packers on the
  //                   full panels, generic on the others, ragged row and column edges;
  //   {33, 25, 514}: two K blocks (512 + 2), the second accumulated into C (full tile) and
  //                  through the scratch tile (edges);
  //   {64, 16, 1056}: three K blocks (512 + 512 + 32), every block on the vectorised packers.
  const Eigen::Index shapes[][3] = {{512, 256, 512}, {64, 48, 32}, {37, 13, 5},
                                    {100, 50, 300},  {1, 1, 1},    {33, 25, 514},
                                    {96, 40, 64},    {64, 208, 512}, {64, 16, 1056}};
  for (const auto& s : shapes)
    for (bool ta : {false, true})
      for (bool tb : {false, true}) check_bf16_shape(ta, tb, s[0], s[1], s[2]);
}

// A float32 product passed off as bf16 would satisfy the bound above; these values tell them
// apart exactly. 1 + 2^-10 rounds to 1 in bf16 (below half an ulp, 2^-8); 1 + 2^-8 + 2^-10 rounds
// UP to 1 + 2^-7 (above the halfway point 1 + 2^-8), which also rules out truncation. Every
// product and partial sum below has at most 19 significant bits, so float32 computes them exactly
// and the expected results are exact equalities.
TEST(GemmBf16, ActuallyRoundsToBf16) {
  if (!bf16_gemm_available() || !fast_gemm_available())
    GTEST_SKIP() << "built without AVX-512 BF16";
  const float below_half = 1.0f + 0x1p-10f;           // -> 1 in bf16
  const float above_half = 1.0f + 0x1p-8f + 0x1p-10f;  // -> 1 + 2^-7 in bf16
  GemmWorkspace ws;
  {  // 1 x 2 times 2 x 1: odd sizes, generic packers and the scratch tile.
    const float a[2] = {below_half, above_half};
    const float b[2] = {1.0f, 1.0f};
    for (bool ta : {false, true})
      for (bool tb : {false, true}) {
        // op(A) is 1 x 2: lda 1 plain, 2 transposed; op(B) is 2 x 1: ldb 2 plain, 1 transposed.
        float c = 1e30f;
        gemm_bf16(ta, tb, 1, 1, 2, a, ta ? 2 : 1, b, tb ? 1 : 2, &c, 1, ws);
        EXPECT_EQ(c, 1.0f + (1.0f + 0x1p-7f)) << "ta " << ta << " tb " << tb;
        c = 1e30f;
        sgemm(ta, tb, 1, 1, 2, a, ta ? 2 : 1, b, tb ? 1 : 2, &c, 1, ws);
        EXPECT_EQ(c, below_half + above_half) << "ta " << ta << " tb " << tb;
      }
  }
  // One full 32 x 8 tile with k = 32: the vectorised packers of every transpose. The rounded
  // operand is A in the first case and B in the second; the other holds small integers and
  // powers of two (exact in bf16), so a misplaced entry changes the result too.
  const Eigen::Index m = 32, n = 8, k = 32;
  for (int inexact_b = 0; inexact_b < 2; ++inexact_b) {
    Eigen::MatrixXf a(m, k), b(k, n);  // op(A), op(B)
    Eigen::MatrixXd want_bf16(m, n), want_f32(m, n);
    for (Eigen::Index p = 0; p < k; ++p)
      for (Eigen::Index i = 0; i < m; ++i)
        a(i, p) = inexact_b ? float(i % 5 + 1) : std::ldexp(above_half, int(i % 3));
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index p = 0; p < k; ++p)
        b(p, j) = inexact_b ? std::ldexp(above_half, int(j % 4)) : float(j + 1);
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index i = 0; i < m; ++i) {
        const double ai = a(i, 0), bj = b(0, j);
        const double ai16 = bf16_to_float(float_to_bf16(a(i, 0)));
        const double bj16 = bf16_to_float(float_to_bf16(b(0, j)));
        want_f32(i, j) = double(k) * ai * bj;
        want_bf16(i, j) = double(k) * ai16 * bj16;
      }
    // The bf16 values are known in closed form; check the scalar conversion agrees with it.
    ASSERT_EQ(bf16_to_float(float_to_bf16(above_half)), 1.0f + 0x1p-7f);
    for (bool ta : {false, true})
      for (bool tb : {false, true}) {
        const Eigen::MatrixXf sa = ta ? Eigen::MatrixXf(a.transpose()) : a;
        const Eigen::MatrixXf sb = tb ? Eigen::MatrixXf(b.transpose()) : b;
        Eigen::MatrixXf c = Eigen::MatrixXf::Constant(m, n, 1e30f);
        gemm_bf16(ta, tb, m, n, k, sa.data(), sa.rows(), sb.data(), sb.rows(), c.data(), m, ws);
        EXPECT_EQ(c.cast<double>(), want_bf16) << "gemm_bf16 inexact " << (inexact_b ? "B" : "A")
                                               << " ta " << ta << " tb " << tb << "\n"
                                               << c;
        c.setConstant(1e30f);
        sgemm(ta, tb, m, n, k, sa.data(), sa.rows(), sb.data(), sb.rows(), c.data(), m, ws);
        EXPECT_EQ(c.cast<double>(), want_f32) << "sgemm inexact " << (inexact_b ? "B" : "A")
                                              << " ta " << ta << " tb " << tb;
      }
  }
}

TEST(Bf16Conversion, RoundsToNearestEven) {
  const auto round_trip = [](float x) { return bf16_to_float(float_to_bf16(x)); };
  EXPECT_EQ(float_to_bf16(1.0f), 0x3f80);
  EXPECT_EQ(bf16_to_float(0x3f80), 1.0f);
  // bf16 spacing in [1, 2) is 2^-7; halfway cases go to the even significand.
  EXPECT_EQ(round_trip(1.0f + 0x1p-8f), 1.0f);                      // tie, down to even 1
  EXPECT_EQ(round_trip(1.0f + 3 * 0x1p-8f), 1.0f + 0x1p-6f);       // tie, up to even 1 + 2^-6
  EXPECT_EQ(round_trip(1.0f + 0x1p-8f + 0x1p-20f), 1.0f + 0x1p-7f);  // above halfway: up
  EXPECT_EQ(round_trip(1.0f + 0x1p-8f - 0x1p-20f), 1.0f);            // below halfway: down
  EXPECT_EQ(round_trip(-1.0f - 0x1p-8f - 0x1p-20f), -1.0f - 0x1p-7f);  // symmetric in sign
  EXPECT_EQ(round_trip(-2.5f), -2.5f);                              // exact
  EXPECT_EQ(float_to_bf16(-2.5f), 0xc020);
  // Carry out of the significand into the exponent: 2 - 2^-9 (just above the largest bf16 below
  // 2, 2 - 2^-7, by more than half an ulp) rounds to 2.
  EXPECT_EQ(round_trip(2.0f - 0x1p-9f), 2.0f);
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(float_to_bf16(inf), 0x7f80);
  EXPECT_EQ(float_to_bf16(-inf), 0xff80);
  EXPECT_EQ(round_trip(inf), inf);
  EXPECT_TRUE(std::isnan(round_trip(std::numeric_limits<float>::quiet_NaN())));
  // A NaN whose payload lies only in the dropped 16 bits: rounding the bits would give inf.
  EXPECT_TRUE(std::isnan(round_trip(std::bit_cast<float>(0x7f800001u))));
  EXPECT_TRUE(std::isnan(round_trip(std::bit_cast<float>(0xff800001u))));
  // Overflow under round to nearest: FLT_MAX is above the largest bf16 (2^128 - 2^120) by more
  // than half its ulp, so it rounds to infinity.
  EXPECT_EQ(round_trip(FLT_MAX), inf);
  EXPECT_EQ(round_trip(-FLT_MAX), -inf);
  EXPECT_EQ(round_trip(0.0f), 0.0f);
  EXPECT_TRUE(std::signbit(round_trip(-0.0f)));

  // Random floats over 60 decades (all normal in float32): round to nearest in an 8-bit
  // significand has relative error <= 2^-8 = u16 (|x - fl(x)| <= ulp/2 <= 2^-8 |x|).
  Rng rng(2024);
  for (int t = 0; t < 100000; ++t) {
    const float x = static_cast<float>(rng.normal() * std::pow(10.0, 60.0 * rng.uniform() - 30.0));
    const double err = std::abs(static_cast<double>(round_trip(x)) - static_cast<double>(x));
    ASSERT_LE(err, kU16 * std::abs(static_cast<double>(x))) << "x = " << x;
  }
}

// Eigen's float32 tanh (a 13/6 rational approximation, documented "accurate up to a couple of
// ulps", clamped to +-1 beyond |x| ~ 8) against std::tanh in double. The allowance used below,
// |tanh_f(x) - tanh(x)| <= 4 u32 |tanh(x)| + 4 u32, is 2 ulp (ulp <= 2 u32 |y|) plus the clamp
// error 1 - tanh(7.9988) = 2.25e-7 < 4 u32 = 2.4e-7. This sweep checks the allowance on the
// inputs that matter (one float in every 2^10 between 1e-6 and 10, both signs; the reference
// std::tanh in double is within 2 ulp of float64, ~1e-9 of the allowance), so the MLP bound does
// not rest on an unverified assumption about Eigen.
double tanh_allowance(double y) { return 4 * kU32 * std::abs(y) + 4 * kU32; }

TEST(GemmBf16, BfloatMlpForwardWithinPropagatedBound) {
  if (!bf16_gemm_available()) GTEST_SKIP() << "built without AVX-512 BF16";
  {
    std::vector<float> xs;
    for (std::uint32_t bits = std::bit_cast<std::uint32_t>(1e-6f);
         bits <= std::bit_cast<std::uint32_t>(10.0f); bits += 1024) {
      xs.push_back(std::bit_cast<float>(bits));
      xs.push_back(-std::bit_cast<float>(bits));
    }
    const Eigen::Map<const Eigen::ArrayXf> x(xs.data(), static_cast<Eigen::Index>(xs.size()));
    const Eigen::ArrayXf y = x.tanh();
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      const double exact = std::tanh(static_cast<double>(x(i)));
      ASSERT_LE(std::abs(y(i) - exact), tanh_allowance(exact)) << "Eigen tanh at x = " << x(i);
    }
  }

  Rng rng(8);
  MlpT<double> md({6, 96, 80, 1});
  md.init_orthogonal(1.0, rng);
  // The same parameters in both: round the double ones to float first, so the comparison sees
  // only the arithmetic, not a rounding of the weights.
  md.params() = md.params().cast<float>().cast<double>();
  Mlp mf({6, 96, 80, 1});
  mf.params() = md.params().cast<float>();
  mf.set_matmul_precision(MatmulPrecision::BFloat16);
  const Eigen::MatrixXf x = random_matrix(6, 40, rng);
  Mlp::Cache cf;
  const Eigen::MatrixXd yf = mf.forward(x, cf).cast<double>();

  // Layer shapes (out x in, batch 40) and where they run (fast_product in mlp.cpp needs m >= 64,
  // n >= 32, k >= 32): 96 x 6 -> Eigen float32 (k = 6); 80 x 96 -> gemm_bf16; 1 x 80 -> Eigen
  // float32 (m = 1).
  //
  // Error bound E_l (elementwise, float/bf16 network vs double network) propagated alongside the
  // double forward. For a layer z = W a + b with |a^ - a| <= E (E_0 = 0, same input):
  //   c^ = product of W and a^ with |c^ - W a^| <= c_k |W| |a^|,
  //        c_k = 2 u16 + u16^2 + gamma_{k+1}(u32) (1 + u16)^2 on gemm_bf16 (bound (1) above),
  //        c_k = gamma_{k+1}(u32) on Eigen float32 (k products and sums, any order, FMA or not);
  //   |W a^ - W a| <= |W| E, and |a^| <= |a| + E, so before the bias add
  //        |c^ + b - z| <= P := |W| E + c_k |W| (|a| + E);
  //   the float bias add rounds once: |fl(c^ + b) - (c^ + b)| <= u32 |c^ + b| <= u32 (|z| + P);
  //   the double reference has its own error <= gamma_{k+1}(u64) (|W| |a| + |b|) (+ what the
  //   earlier layers put into a, which is inside E through the same recursion); so
  //        E_z = (1 + u32) P + u32 |z| + gamma_{k+1}(u64) (|W| (|a| + E) + |b|).
  //   tanh is 1-Lipschitz: |tanh_f(z^) - tanh(z)| <= |tanh_f(z^) - tanh(z^)| + E_z, and the
  //   evaluation error is at most tanh_allowance (checked above) <= 8 u32 since |tanh| <= 1;
  //   the double tanh (glibc, <= 2 ulp) adds <= 4 u64:   E_a = E_z + 8 u32 + 4 u64.
  Eigen::MatrixXd a = x.cast<double>();
  Eigen::MatrixXd e = Eigen::MatrixXd::Zero(a.rows(), a.cols());
  const int L = md.num_layers();
  for (int l = 1; l <= L; ++l) {
    const Eigen::MatrixXd w = md.weight(l);
    const Eigen::VectorXd bias = md.bias(l);
    const Eigen::Index k = w.cols();
    const bool on_bf16 = w.rows() >= 64 && a.cols() >= 32 && k >= 32;
    ASSERT_EQ(on_bf16, l == 2) << "layer " << l;  // the shapes chosen to have exactly one
    const double g32 = gamma_n(static_cast<double>(k + 1), kU32);
    const double ck = on_bf16 ? 2 * kU16 + kU16 * kU16 + g32 * (1 + kU16) * (1 + kU16) : g32;
    const double g64 = gamma_n(static_cast<double>(k + 1), kU64);
    Eigen::MatrixXd z = w * a;
    z.colwise() += bias;
    const Eigen::MatrixXd wabs = w.cwiseAbs();
    const Eigen::MatrixXd a_plus_e = a.cwiseAbs() + e;
    const Eigen::MatrixXd p = wabs * e + ck * (wabs * a_plus_e);
    Eigen::MatrixXd ez = (1 + kU32) * p + kU32 * z.cwiseAbs() + g64 * (wabs * a_plus_e);
    ez.colwise() += g64 * bias.cwiseAbs();
    if (l < L) {
      a = z.array().tanh().matrix();
      e = (ez.array() + 8 * kU32 + 4 * kU64).matrix();
    } else {
      a = z;
      e = ez;
    }
  }
  // (a is the double forward of md, written out above so that z is at hand; MlpT<double>
  // computes the same sums, possibly in another order.)
  const Eigen::MatrixXd& yd = a;
  const Eigen::MatrixXd err = (yf - yd).cwiseAbs();
  for (Eigen::Index j = 0; j < yf.cols(); ++j)
    EXPECT_LE(err(0, j), e(0, j)) << "sample " << j << ": output " << yd(0, j);
  // Not vacuous? This worst-case bound assumes every one of the 96 x 80 operand roundings of the
  // bf16 layer pushes the same way and is then summed through |W_3| (80 terms): with this seed it
  // is 0.66 of max |y| (the largest sample: bound 0.185 for y = 0.352), while the actual error is
  // ~0.6 % of max |y| (1.6 % of the bound). 10 % of max |y| is out of reach of a worst-case
  // bound here: it grows with the sums of magnitudes |W_2| |a_1| and |W_3| E_2, many times the
  // signed sums z_2 and y that they bound (the 0.66 above IS that bound; no other seed or
  // threshold makes it honest to assert 10 %). What it does guarantee, and what is asserted:
  // the bound is below the largest output, so a zero, a
  // sign flip or a missing layer on that sample fails. The bound depends only on the seed and the
  // double network, not on the code under test, so this cannot start failing through a change
  // of summation order. The precise check of the bf16 layer is the per-layer one below.
  Eigen::Index imax = 0, jmax = 0;
  const double ymax = yd.cwiseAbs().maxCoeff(&imax, &jmax);
  EXPECT_LT(e(imax, jmax), ymax) << "end-to-end bound vacuous on the largest output";

  // Per layer, from the float network's own input to that layer (cf.a[l - 1], known exactly), the
  // bf16 rounding is no longer an error to bound but part of the reference: z_ref = W^ a^ + b with
  // W^, a^ rounded to bf16 by float_to_bf16 on the gemm_bf16 layer, W and a unrounded on the
  // float32 ones, all in double (products exact). The float network may then differ only by
  // float32 sums and the bias add, and by the tanh evaluation:
  //   |z^ - z_ref| <= E_z = (1 + u32) gamma_{k+1}(u32) M + u32 |z_ref| + gamma_{k+1}(u64) (M + |b|),
  //   M = |W^| |a^| (float sums of k exact products, Lemma 3.4; the rounded bias add; the double
  //   reference's own sums), and after tanh |a_l - tanh(z_ref)| <= E_z + 4 u32 (|tanh(z_ref)| +
  //   E_z) + 4 u32 + 4 u64 (the tanh allowance at tanh(z^), 1-Lipschitz, plus the double tanh).
  // That is ~k u32 ~ 1e-5 relative: ~1000 times tighter than the bf16 rounding itself, so it
  // fails if a layer used float32 operands where it should use bf16 or the other way round
  // (asserted below: the float32 product of layer 2 violates it).
  for (int l = 1; l <= L; ++l) {
    const bool on_bf16 = l == 2;
    const Eigen::MatrixXd in = cf.a[static_cast<std::size_t>(l - 1)].cast<double>();
    const Eigen::MatrixXd out = cf.a[static_cast<std::size_t>(l)].cast<double>();
    const Eigen::MatrixXd w = md.weight(l);
    const Eigen::VectorXd bias = md.bias(l);
    const Eigen::MatrixXd w_op = on_bf16 ? bf16_rounded(w) : w;
    const Eigen::MatrixXd in_op = on_bf16 ? bf16_rounded(in) : in;
    const Eigen::Index k = w.cols();
    const double g32 = gamma_n(static_cast<double>(k + 1), kU32);
    const double g64 = gamma_n(static_cast<double>(k + 1), kU64);
    Eigen::MatrixXd z = w_op * in_op;
    z.colwise() += bias;
    const Eigen::MatrixXd mag = w_op.cwiseAbs() * in_op.cwiseAbs();
    Eigen::MatrixXd ez = (1 + kU32) * g32 * mag + kU32 * z.cwiseAbs() + g64 * mag;
    ez.colwise() += g64 * bias.cwiseAbs();
    Eigen::MatrixXd want = z, bound = ez;
    if (l < L) {
      want = z.array().tanh().matrix();
      bound = (ez.array() + 4 * kU32 * (want.array().abs() + ez.array()) + 4 * kU32 + 4 * kU64)
                  .matrix();
    }
    const Eigen::MatrixXd diff = (out - want).cwiseAbs();
    for (Eigen::Index j = 0; j < out.cols(); ++j)
      for (Eigen::Index i = 0; i < out.rows(); ++i)
        ASSERT_LE(diff(i, j), bound(i, j)) << "layer " << l << " (" << (on_bf16 ? "bf16" : "float32")
                                           << ") at (" << i << ", " << j << ")";
    if (on_bf16) {
      // The same layer with float32 operands (no bf16 rounding) would fail the check above on
      // most entries: the check does see which arithmetic the layer used.
      Eigen::MatrixXd z32 = w * in;
      z32.colwise() += bias;
      const Eigen::ArrayXXd miss = (z32.array().tanh() - want.array()).abs();
      EXPECT_GT((miss > bound.array()).count(), out.size() / 2);
    }
  }
}

}  // namespace
}  // namespace codesign::rl
