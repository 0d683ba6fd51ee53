#include "rl/gemm.hpp"

#include <algorithm>
#include <stdexcept>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace codesign::rl {

#if defined(__AVX512F__)

namespace {

constexpr Eigen::Index kMr = 32;  // rows of the register tile (two 16-lane vectors)
constexpr Eigen::Index kNr = 12;  // columns of the register tile
constexpr Eigen::Index kKc = 256;

// c_tile (ldc) (=|+=) packed_a (kc x 32, row p contiguous) * packed_b (kc x 12, row p contiguous)
void micro_kernel(Eigen::Index kc, const float* pa, const float* pb, float* c, Eigen::Index ldc,
                  bool accumulate) {
  __m512 c0[kNr], c1[kNr];
#pragma GCC unroll 12  // unrolled, so that GCC keeps the tile in registers instead of memset
  for (int j = 0; j < kNr; ++j) {
    c0[j] = _mm512_setzero_ps();
    c1[j] = _mm512_setzero_ps();
  }
  for (Eigen::Index p = 0; p < kc; ++p) {
    const __m512 a0 = _mm512_load_ps(pa + p * kMr);
    const __m512 a1 = _mm512_load_ps(pa + p * kMr + 16);
    const float* bp = pb + p * kNr;
#pragma GCC unroll 12
    for (int j = 0; j < kNr; ++j) {
      const __m512 bj = _mm512_set1_ps(bp[j]);
      c0[j] = _mm512_fmadd_ps(a0, bj, c0[j]);
      c1[j] = _mm512_fmadd_ps(a1, bj, c1[j]);
    }
  }
#pragma GCC unroll 12
  for (int j = 0; j < kNr; ++j) {
    float* cj = c + j * ldc;
    if (accumulate) {
      c0[j] = _mm512_add_ps(_mm512_loadu_ps(cj), c0[j]);
      c1[j] = _mm512_add_ps(_mm512_loadu_ps(cj + 16), c1[j]);
    }
    _mm512_storeu_ps(cj, c0[j]);
    _mm512_storeu_ps(cj + 16, c1[j]);
  }
}

}  // namespace

bool fast_gemm_available() { return true; }

void sgemm(bool trans_a, bool trans_b, Eigen::Index m, Eigen::Index n, Eigen::Index k,
           const float* a, Eigen::Index lda, const float* b, Eigen::Index ldb, float* c,
           Eigen::Index ldc, GemmWorkspace& ws) {
  if (m < 1 || n < 1 || k < 1) throw std::invalid_argument("sgemm: empty dimension");
  const Eigen::Index m_pad = (m + kMr - 1) / kMr * kMr;
  const Eigen::Index n_pad = (n + kNr - 1) / kNr * kNr;
  // Grow only: shrinking and regrowing would value-initialise (memset) the panels every call.
  const auto need_a = static_cast<std::size_t>(m_pad * std::min(k, kKc));
  const auto need_b = static_cast<std::size_t>(n_pad * std::min(k, kKc));
  if (ws.packed_a.size() < need_a) ws.packed_a.resize(need_a);
  if (ws.packed_b.size() < need_b) ws.packed_b.resize(need_b);
  alignas(64) float tile[kMr * kNr];

  for (Eigen::Index k0 = 0; k0 < k; k0 += kKc) {
    const Eigen::Index kc = std::min(kKc, k - k0);
    const bool accumulate = k0 > 0;
    // Pack A: panel i0 holds rows i0..i0+31, stored p-major (32 contiguous floats per p).
    // Loops run along the contiguous direction of the source (writes stay inside one panel,
    // which fits L1).
    float* pa = ws.packed_a.data();
    for (Eigen::Index i0 = 0; i0 < m_pad; i0 += kMr) {
      float* panel = pa + i0 * kc;
      const Eigen::Index rows = std::min(kMr, m - i0);
      if (!trans_a) {
        for (Eigen::Index p = 0; p < kc; ++p) {
          const float* src = a + i0 + (k0 + p) * lda;
          float* dst = panel + p * kMr;
          for (Eigen::Index i = 0; i < rows; ++i) dst[i] = src[i];
          for (Eigen::Index i = rows; i < kMr; ++i) dst[i] = 0.0f;
        }
      } else {
        for (Eigen::Index i = 0; i < kMr; ++i) {
          if (i < rows) {
            const float* src = a + k0 + (i0 + i) * lda;  // row i of op(A) is contiguous
            for (Eigen::Index p = 0; p < kc; ++p) panel[p * kMr + i] = src[p];
          } else {
            for (Eigen::Index p = 0; p < kc; ++p) panel[p * kMr + i] = 0.0f;
          }
        }
      }
    }
    // Pack B: panel j0 holds columns j0..j0+11, stored p-major (12 contiguous floats per p).
    float* pb = ws.packed_b.data();
    for (Eigen::Index j0 = 0; j0 < n_pad; j0 += kNr) {
      float* panel = pb + j0 * kc;
      const Eigen::Index cols = std::min(kNr, n - j0);
      if (!trans_b) {
        for (Eigen::Index j = 0; j < kNr; ++j) {
          if (j < cols) {
            const float* src = b + k0 + (j0 + j) * ldb;  // column j of op(B) is contiguous
            for (Eigen::Index p = 0; p < kc; ++p) panel[p * kNr + j] = src[p];
          } else {
            for (Eigen::Index p = 0; p < kc; ++p) panel[p * kNr + j] = 0.0f;
          }
        }
      } else {
        for (Eigen::Index p = 0; p < kc; ++p) {
          const float* src = b + j0 + (k0 + p) * ldb;
          float* dst = panel + p * kNr;
          for (Eigen::Index j = 0; j < cols; ++j) dst[j] = src[j];
          for (Eigen::Index j = cols; j < kNr; ++j) dst[j] = 0.0f;
        }
      }
    }
    for (Eigen::Index j0 = 0; j0 < n_pad; j0 += kNr) {
      const Eigen::Index cols = std::min(kNr, n - j0);
      for (Eigen::Index i0 = 0; i0 < m_pad; i0 += kMr) {
        const Eigen::Index rows = std::min(kMr, m - i0);
        float* c_tile = c + i0 + j0 * ldc;
        if (rows == kMr && cols == kNr) {
          micro_kernel(kc, pa + i0 * kc, pb + j0 * kc, c_tile, ldc, accumulate);
        } else {  // edge: compute the full tile into scratch, write back the valid part
          micro_kernel(kc, pa + i0 * kc, pb + j0 * kc, tile, kMr, false);
          for (Eigen::Index j = 0; j < cols; ++j)
            for (Eigen::Index i = 0; i < rows; ++i)
              c_tile[i + j * ldc] = (accumulate ? c_tile[i + j * ldc] : 0.0f) + tile[i + j * kMr];
        }
      }
    }
  }
}

#else  // no AVX-512: callers use Eigen

bool fast_gemm_available() { return false; }

void sgemm(bool, bool, Eigen::Index, Eigen::Index, Eigen::Index, const float*, Eigen::Index,
           const float*, Eigen::Index, float*, Eigen::Index, GemmWorkspace&) {
  throw std::logic_error("sgemm: built without AVX-512; use Eigen");
}

#endif

}  // namespace codesign::rl
