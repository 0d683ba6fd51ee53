#pragma once
// Matrix products for the learner's large layers, C = op(A) op(B), column-major:
//   * sgemm: float32 (AVX-512 FMA), a 32 x 12 register tile;
//   * gemm_bf16 / gemm_bf16_packed: operands rounded to bfloat16, sums in float32 (AVX-512 BF16
//     vdpbf16ps), a 32 x 8 tile, with an optional per-tile epilogue (gemm_bf16.cpp).
//
// Why not Eigen's product: on an AVX-512 core Eigen 3.4's float GEMM kernel (48 x 4 register
// tile) reaches ~66-72 % of the measured FMA peak on the 512 x 512 x 256 shapes of a PPO update;
// sgemm's tile (24 accumulators, the B operand broadcast from memory) reaches ~85-90 %, and
// gemm_bf16 ~90 % of the twice higher bf16 peak (measured: docs/journal/rl.md, "The GEMM
// kernels"). Used by MlpT<float> for large layers when compiled with AVX-512 (BF16); elsewhere
// (small layers, float64, no AVX-512) Eigen is used.
//
// sgemm blocking: K in blocks of 256; A packed into 32-row panels (fits L2), B into 12-column
// panels (fits L1). Edges are zero-padded in the packed copies and written through a scratch
// tile.
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

namespace codesign::rl {

// Arithmetic of the large matrix products of the learner (MlpT): plain float32 (sgemm), or
// bfloat16 operands with float32 sums (gemm_bf16). Everything else is float32 either way.
enum class MatmulPrecision { Float32, BFloat16 };

// Scratch reused across calls (aligned packed panels); owned by the caller, no global state.
struct GemmWorkspace {
  std::vector<float, Eigen::aligned_allocator<float>> packed_a;
  std::vector<float, Eigen::aligned_allocator<float>> packed_b;
  std::vector<std::uint16_t, Eigen::aligned_allocator<std::uint16_t>> packed_a16;  // gemm_bf16
  std::vector<std::uint16_t, Eigen::aligned_allocator<std::uint16_t>> packed_b16;
};

// True if this build has the fast kernel (AVX-512F).
bool fast_gemm_available();

// C (m x n, leading dimension ldc) = op(A) (m x k) * op(B) (k x n), overwriting C.
// op(A)(i, p) = trans_a ? a[p + i * lda] : a[i + p * lda]; likewise for B.
// Requires fast_gemm_available(); m, n, k >= 1.
void sgemm(bool trans_a, bool trans_b, Eigen::Index m, Eigen::Index n, Eigen::Index k,
           const float* a, Eigen::Index lda, const float* b, Eigen::Index ldb, float* c,
           Eigen::Index ldc, GemmWorkspace& ws);

// Mixed precision (gemm_bf16.cpp): the same product with every entry of op(A) and op(B) rounded
// to bfloat16 (8 significant bits, round to nearest even) and all sums carried in float32, as
// PyTorch's bf16 autocast does for matrix products. Per entry,
//   |C_bf16 - A B| <= (2 u16 + u16^2 + gamma_{k+1} (1 + u16)^2) (|A| |B|),  u16 = 2^-8,
// since a product of two bf16 numbers is exact in float32. Twice the multiply-adds per
// instruction of sgemm (AVX-512 BF16 `vdpbf16ps`).
bool bf16_gemm_available();  // true if built with AVX-512 BF16 (e.g. -march=native on such a CPU)

// Work done on each finished tile of C while it is in L1, in this order (all optional):
//   c += bias (per row);  c = tanh(c);  c *= 1 - t^2 (t: a matrix like C);
//   *sum_squares += sum of c^2;  row_sums[i] += sum over the columns of row i of c.
// The MLP uses it for bias + tanh in the forward pass, the tanh derivative and the bias
// gradient in the backward pass, and the gradient norm.
struct GemmEpilogue {
  const float* bias = nullptr;
  bool tanh = false;
  const float* tanh_of_input = nullptr;
  Eigen::Index ld_tanh = 0;
  double* sum_squares = nullptr;
  float* row_sums = nullptr;
};

void gemm_bf16(bool trans_a, bool trans_b, Eigen::Index m, Eigen::Index n, Eigen::Index k,
               const float* a, Eigen::Index lda, const float* b, Eigen::Index ldb, float* c,
               Eigen::Index ldc, GemmWorkspace& ws, const GemmEpilogue* epilogue = nullptr);

// Operand A of gemm_bf16 converted and packed once, for reuse by several products (a weight
// matrix between optimiser steps). op(A) is m x k; the layout is private to gemm_bf16.cpp.
struct PackedBf16 {
  Eigen::Index m = 0, k = 0;
  std::vector<std::uint16_t, Eigen::aligned_allocator<std::uint16_t>> data;
};
// Packs op(A) (m x k).
void pack_bf16(bool trans_a, Eigen::Index m, Eigen::Index k, const float* a, Eigen::Index lda,
               PackedBf16& out);
// Packs W (m x k) as `plain` (op = W) and as `transposed` (op = W^T) in one pass over W where
// m and k are multiples of 32 up to 512 (two passes otherwise): a layer's weight is used as W in
// the forward pass and as W^T for the input gradient.
// If before_columns is given it is called with [c0, c1) before those columns of W are read
// (consecutive ranges covering all k columns), so that a caller can finish writing W just in time
// (the learner's deferred optimiser step; the columns are then still in cache).
using ColumnHook = std::function<void(Eigen::Index c0, Eigen::Index c1)>;
void pack_bf16_both(Eigen::Index m, Eigen::Index k, const float* w, Eigen::Index ldw,
                    PackedBf16& plain, PackedBf16& transposed,
                    const ColumnHook* before_columns = nullptr);
// C (a.m x n) = op(A) op(B) with A packed; same arithmetic as gemm_bf16.
void gemm_bf16_packed(const PackedBf16& a, bool trans_b, Eigen::Index n, const float* b,
                      Eigen::Index ldb, float* c, Eigen::Index ldc, GemmWorkspace& ws,
                      const GemmEpilogue* epilogue = nullptr);

// bfloat16 conversions used by the packing (round to nearest even; NaN stays NaN).
std::uint16_t float_to_bf16(float x);
float bf16_to_float(std::uint16_t h);

}  // namespace codesign::rl
