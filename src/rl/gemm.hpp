#pragma once
// Single-precision GEMM for the learner's large layers: C = op(A) op(B), column-major.
//
// Why not Eigen's product: on this Zen 4 core Eigen 3.4's float GEMM kernel (48 x 4 register
// tile) reaches ~66-72 % of the measured FMA peak on the 512 x 512 x 256 shapes of a PPO update;
// this 32 x 12 register tile (24 accumulators, the B operand broadcast from memory) reaches
// ~80 %. Used by MlpT<float> for large layers when compiled with AVX-512; elsewhere (small
// layers, float64, no AVX-512) Eigen is used. Results equal Eigen's up to float rounding
// (different summation order).
//
// Blocking: K in blocks of 256; A packed into 32-row panels (fits L2), B into 12-column panels
// (fits L1). Edges are zero-padded in the packed copies and written through a scratch tile.
#include <vector>

#include <Eigen/Core>

namespace codesign::rl {

// Scratch reused across calls (aligned packed panels); owned by the caller, no global state.
struct GemmWorkspace {
  std::vector<float, Eigen::aligned_allocator<float>> packed_a;
  std::vector<float, Eigen::aligned_allocator<float>> packed_b;
};

// True if this build has the fast kernel (AVX-512F).
bool fast_gemm_available();

// C (m x n, leading dimension ldc) = op(A) (m x k) * op(B) (k x n), overwriting C.
// op(A)(i, p) = trans_a ? a[p + i * lda] : a[i + p * lda]; likewise for B.
// Requires fast_gemm_available(); m, n, k >= 1.
void sgemm(bool trans_a, bool trans_b, Eigen::Index m, Eigen::Index n, Eigen::Index k,
           const float* a, Eigen::Index lda, const float* b, Eigen::Index ldb, float* c,
           Eigen::Index ldc, GemmWorkspace& ws);

}  // namespace codesign::rl
