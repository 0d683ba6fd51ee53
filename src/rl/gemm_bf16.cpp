// Mixed-precision GEMM: operands rounded to bfloat16, products summed in float32 (gemm.hpp).
//
// Kernel: AVX-512 BF16 `vdpbf16ps` multiplies pairs of bf16 numbers and adds both products to
// one float32 lane, so every instruction does 32 multiply-adds where an fp32 FMA does 16. The
// register tile is 32 rows x 8 columns (16 accumulators); per step of two k values it loads two
// vectors of A (16 rows x 2 k each) and broadcasts one (k, k+1) pair of B per column.
//
// Packed layouts (k padded to even with zeros, edges padded with zeros):
//   A panel (32 rows): pair q, rows 0..15 then 16..31, each row as (k=2q, k=2q+1)
//                      -> element (i, p) at q*64 + (i/16)*32 + (i%16)*2 + p%2;
//   B panel (8 cols):  pair q, columns 0..7, each as (k=2q, k=2q+1)
//                      -> element (p, j) at q*16 + j*2 + p%2.
// All of K is one block up to kKc = 512 (a 32-row A panel is then 32 KB, a B panel 8 KB: B
// stays in L1 while the A panels stream from L2). 8 columns rather than 12: no ragged edge for
// the batch sizes of a PPO update (256, 208 = 2000 mod 256, 40 envs, 512 units), and 16
// accumulators still cover the latency of vdpbf16ps; measured as fast as 12 on full tiles.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "rl/gemm.hpp"

#if defined(__AVX512F__) && defined(__AVX512BF16__) && defined(__AVX512BW__)
#define CODESIGN_HAVE_BF16_GEMM 1
#include <immintrin.h>
#endif

namespace codesign::rl {

std::uint16_t float_to_bf16(float x) {
  const std::uint32_t u = std::bit_cast<std::uint32_t>(x);
  if ((u & 0x7fffffffu) > 0x7f800000u) return static_cast<std::uint16_t>((u >> 16) | 0x40u);  // NaN
  // Round to nearest, ties to even, on the 16 bits that are dropped.
  return static_cast<std::uint16_t>((u + 0x7fffu + ((u >> 16) & 1u)) >> 16);
}

float bf16_to_float(std::uint16_t h) {
  return std::bit_cast<float>(static_cast<std::uint32_t>(h) << 16);
}

#if defined(CODESIGN_HAVE_BF16_GEMM)

namespace {

using Index = Eigen::Index;
constexpr Index kMr = 32;
constexpr Index kNr = 8;
constexpr Index kKc = 512;

// Tile of C (ldc) (=|+=) A panel * B panel over kq pairs of k.
// The epilogue of one full tile, resolved to tile-local pointers (see GemmEpilogue).
struct TileEpilogue {
  const float* bias = nullptr;  // rows i0..i0+31
  bool tanh = false;
  const float* t = nullptr;  // (i0, j0) of the tanh output, leading dimension ld_t
  Index ld_t = 0;
  bool squares = false;
  float* row_sums = nullptr;  // rows i0..i0+31
};

// Tile of C (ldc) (=|+=) A panel * B panel over kq pairs of k; then, if `e` is non-null, the
// epilogue on the registers before the store (re-loading a just-stored tile would stall on store
// forwarding). Returns `sq` plus the squares of the stored tile when e->squares.
__m512 micro_kernel(Index kq, const std::uint16_t* pa, const std::uint16_t* pb, float* c,
                    Index ldc, bool accumulate, const TileEpilogue* e, __m512 sq) {
  if (e != nullptr && e->t != nullptr)  // the epilogue's operand arrives during the products
    for (int j = 0; j < kNr; ++j) {
      _mm_prefetch(reinterpret_cast<const char*>(e->t + j * e->ld_t), _MM_HINT_T0);
      _mm_prefetch(reinterpret_cast<const char*>(e->t + j * e->ld_t + 16), _MM_HINT_T0);
    }
  __m512 c0[kNr], c1[kNr];
#pragma GCC unroll 8
  for (int j = 0; j < kNr; ++j) {
    c0[j] = _mm512_setzero_ps();
    c1[j] = _mm512_setzero_ps();
  }
  for (Index q = 0; q < kq; ++q) {
    const __m512bh a0 = (__m512bh)_mm512_load_si512(pa + q * 64);
    const __m512bh a1 = (__m512bh)_mm512_load_si512(pa + q * 64 + 32);
    const std::uint16_t* bq = pb + q * 2 * kNr;
#pragma GCC unroll 8
    for (int j = 0; j < kNr; ++j) {
      std::int32_t pair;
      std::memcpy(&pair, bq + 2 * j, sizeof pair);
      const __m512bh bj = (__m512bh)_mm512_set1_epi32(pair);
      c0[j] = _mm512_dpbf16_ps(c0[j], a0, bj);
      c1[j] = _mm512_dpbf16_ps(c1[j], a1, bj);
    }
  }
  if (e == nullptr) {
#pragma GCC unroll 8
    for (int j = 0; j < kNr; ++j) {
      float* cj = c + j * ldc;
      if (accumulate) {
        c0[j] = _mm512_add_ps(_mm512_loadu_ps(cj), c0[j]);
        c1[j] = _mm512_add_ps(_mm512_loadu_ps(cj + 16), c1[j]);
      }
      _mm512_storeu_ps(cj, c0[j]);
      _mm512_storeu_ps(cj + 16, c1[j]);
    }
    return sq;
  }
  // Epilogue (locals only: __m512 is may_alias, stores through it would force reloads of *e).
  const float* const bias = e->bias;
  const bool do_tanh = e->tanh;
  const float* const t = e->t;
  const Index ld_t = e->ld_t;
  const bool squares = e->squares;
  const __m512 one = _mm512_set1_ps(1.0f);
  const __m512 b0 = bias ? _mm512_loadu_ps(bias) : _mm512_setzero_ps();
  const __m512 b1 = bias ? _mm512_loadu_ps(bias + 16) : _mm512_setzero_ps();
  __m512 s0 = _mm512_setzero_ps(), s1 = _mm512_setzero_ps();
  for (int j = 0; j < kNr; ++j) {
    float* cj = c + j * ldc;
    __m512 v0 = c0[j], v1 = c1[j];
    if (accumulate) {
      v0 = _mm512_add_ps(_mm512_loadu_ps(cj), v0);
      v1 = _mm512_add_ps(_mm512_loadu_ps(cj + 16), v1);
    }
    if (bias) {
      v0 = _mm512_add_ps(v0, b0);
      v1 = _mm512_add_ps(v1, b1);
    }
    if (do_tanh) {
      v0 = Eigen::internal::ptanh(v0);
      v1 = Eigen::internal::ptanh(v1);
    }
    if (t) {  // times 1 - t^2
      const __m512 t0 = _mm512_loadu_ps(t + j * ld_t), t1 = _mm512_loadu_ps(t + j * ld_t + 16);
      v0 = _mm512_mul_ps(v0, _mm512_fnmadd_ps(t0, t0, one));
      v1 = _mm512_mul_ps(v1, _mm512_fnmadd_ps(t1, t1, one));
    }
    // A gradient (the squares epilogue) is read again only by the optimiser, a minibatch later:
    // streaming stores keep it from evicting the packed operands of the products in between.
    if (squares && (reinterpret_cast<std::uintptr_t>(cj) % 64 == 0)) {
      _mm512_stream_ps(cj, v0);
      _mm512_stream_ps(cj + 16, v1);
    } else {
      _mm512_storeu_ps(cj, v0);
      _mm512_storeu_ps(cj + 16, v1);
    }
    if (squares) sq = _mm512_fmadd_ps(v0, v0, _mm512_fmadd_ps(v1, v1, sq));
    s0 = _mm512_add_ps(s0, v0);
    s1 = _mm512_add_ps(s1, v1);
  }
  if (e->row_sums) {
    float* const sums = e->row_sums;
    _mm512_storeu_ps(sums, _mm512_add_ps(_mm512_loadu_ps(sums), s0));
    _mm512_storeu_ps(sums + 16, _mm512_add_ps(_mm512_loadu_ps(sums + 16), s1));
  }
  return sq;
}

// Interleaves two rows of 16 bf16 values: [x0 y0 x1 y1 ... x15 y15] from floats x, y.
inline __m512i interleave_pairs(__m512 x, __m512 y) {
  const __m512i both = (__m512i)_mm512_cvtne2ps_pbh(y, x);  // low half x, high half y
  const __m512i idx = _mm512_set_epi16(31, 15, 30, 14, 29, 13, 28, 12, 27, 11, 26, 10, 25, 9, 24,
                                       8, 23, 7, 22, 6, 21, 5, 20, 4, 19, 3, 18, 2, 17, 1, 16, 0);
  return _mm512_permutexvar_epi16(idx, both);
}

// In-register transpose of a 16 x 16 block of 32-bit elements: r[i] lane j <-> r[j] lane i.
inline void transpose_16x16(__m512i r[16]) {
  __m512i t[16], u[16];
  for (int k = 0; k < 8; ++k) {  // 2 x 2 blocks of 32-bit elements inside each 128-bit lane
    t[2 * k] = _mm512_unpacklo_epi32(r[2 * k], r[2 * k + 1]);
    t[2 * k + 1] = _mm512_unpackhi_epi32(r[2 * k], r[2 * k + 1]);
  }
  for (int k = 0; k < 4; ++k) {  // 4 x 4 blocks: lane L of u[4k + c] = column 4L + c, rows 4k..
    u[4 * k] = _mm512_unpacklo_epi64(t[4 * k], t[4 * k + 2]);
    u[4 * k + 1] = _mm512_unpackhi_epi64(t[4 * k], t[4 * k + 2]);
    u[4 * k + 2] = _mm512_unpacklo_epi64(t[4 * k + 1], t[4 * k + 3]);
    u[4 * k + 3] = _mm512_unpackhi_epi64(t[4 * k + 1], t[4 * k + 3]);
  }
  for (int c = 0; c < 4; ++c) {  // gather the four 128-bit lanes of each column
    const __m512i even_lo = _mm512_shuffle_i32x4(u[c], u[4 + c], 0x88);   // lanes 0, 2: rows 0-7
    const __m512i odd_lo = _mm512_shuffle_i32x4(u[c], u[4 + c], 0xdd);    // lanes 1, 3: rows 0-7
    const __m512i even_hi = _mm512_shuffle_i32x4(u[8 + c], u[12 + c], 0x88);
    const __m512i odd_hi = _mm512_shuffle_i32x4(u[8 + c], u[12 + c], 0xdd);
    r[c] = _mm512_shuffle_i32x4(even_lo, even_hi, 0x88);       // column c
    r[8 + c] = _mm512_shuffle_i32x4(even_lo, even_hi, 0xdd);   // column 8 + c
    r[4 + c] = _mm512_shuffle_i32x4(odd_lo, odd_hi, 0x88);     // column 4 + c
    r[12 + c] = _mm512_shuffle_i32x4(odd_lo, odd_hi, 0xdd);    // column 12 + c
  }
}

// Element (i, p) of op(X) for X column-major with leading dimension ld.
inline float element(bool trans, const float* x, Index ld, Index i, Index p) {
  return trans ? x[p + i * ld] : x[i + p * ld];
}

// Generic (slow) packing of one A panel: any transpose, partial rows, odd kc.
void pack_a_panel_generic(bool trans, const float* a, Index lda, Index m, Index i0, Index k0,
                          Index kc, std::uint16_t* panel) {
  const Index rows = std::min(kMr, m - i0);
  for (Index q = 0; q < (kc + 1) / 2; ++q)
    for (Index i = 0; i < kMr; ++i)
      for (Index r = 0; r < 2; ++r) {
        const Index p = 2 * q + r;
        const float v = (i < rows && p < kc) ? element(trans, a, lda, i0 + i, k0 + p) : 0.0f;
        panel[q * 64 + (i / 16) * 32 + (i % 16) * 2 + r] = float_to_bf16(v);
      }
}

// Generic (slow) packing of one B panel.
void pack_b_panel_generic(bool trans, const float* b, Index ldb, Index n, Index j0, Index k0,
                          Index kc, std::uint16_t* panel) {
  const Index cols = std::min(kNr, n - j0);
  for (Index q = 0; q < (kc + 1) / 2; ++q)
    for (Index j = 0; j < kNr; ++j)
      for (Index r = 0; r < 2; ++r) {
        const Index p = 2 * q + r;
        const float v = (j < cols && p < kc) ? element(!trans, b, ldb, j0 + j, k0 + p) : 0.0f;
        panel[q * 2 * kNr + j * 2 + r] = float_to_bf16(v);
      }
}

// Packs k range [k0, k0 + kc) of op(A) (m rows) into m_pad / 32 panels of kq pairs each.
// Full panels take a vectorised path whose loops follow the contiguous direction of the source
// (these operands come from L3 after the optimiser step; strided walks stall on them).
void pack_a(bool trans, const float* a, Index lda, Index m, Index k0, Index kc,
            std::uint16_t* packed) {
  const Index kq = (kc + 1) / 2;
  const Index full = (trans ? (kc % 32 == 0) : (kc % 2 == 0)) ? m / kMr * kMr : 0;
  if (!trans) {  // columns contiguous: a pair of columns feeds every panel in turn
    for (Index q = 0; q < kq && full > 0; ++q) {
      const float* col0 = a + (k0 + 2 * q) * lda;
      const float* col1 = col0 + lda;
      for (Index i0 = 0; i0 < full; i0 += kMr)
        for (Index h = 0; h < 2; ++h)
          _mm512_store_si512(packed + i0 * kq * 2 + q * 64 + 32 * h,
                             interleave_pairs(_mm512_loadu_ps(col0 + i0 + 16 * h),
                                              _mm512_loadu_ps(col1 + i0 + 16 * h)));
    }
  } else {  // row i of op(A) contiguous along k: (k, k+1) are adjacent, i.e. already a pair
    // 16 rows x 16 pairs at a time, transposed in registers into 16 stores of one pair each.
    __m512i r[16];
    for (Index i0 = 0; i0 < full; i0 += kMr) {
      std::uint32_t* base = reinterpret_cast<std::uint32_t*>(packed + i0 * kq * 2);
      for (Index h = 0; h < 2; ++h)
        for (Index p = 0; p < kc; p += 32) {
          for (int t = 0; t < 16; ++t) {
            const float* src = a + k0 + p + (i0 + 16 * h + t) * lda;
            r[t] = (__m512i)_mm512_cvtne2ps_pbh(_mm512_loadu_ps(src + 16), _mm512_loadu_ps(src));
          }
          transpose_16x16(r);
          for (int t = 0; t < 16; ++t) _mm512_store_si512(base + (p / 2 + t) * 32 + 16 * h, r[t]);
        }
    }
  }
  for (Index i0 = full; i0 < m; i0 += kMr)
    pack_a_panel_generic(trans, a, lda, m, i0, k0, kc, packed + i0 * kq * 2);
}

// Packs k range [k0, k0 + kc) of op(B) (n columns) into n_pad / 8 panels of kq pairs each.
void pack_b(bool trans, const float* b, Index ldb, Index n, Index k0, Index kc,
            std::uint16_t* packed) {
  const Index kq = (kc + 1) / 2;
  const Index full = (trans ? (kc % 2 == 0) : (kc % 32 == 0)) ? n / kNr * kNr : 0;
  if (!trans) {  // column j contiguous along k
    // 8 columns x 16 pairs at a time, transposed in registers (8 zero rows) into 16 stores.
    const __mmask16 lanes = (1u << kNr) - 1;
    __m512i r[16];
    for (Index j0 = 0; j0 < full; j0 += kNr) {
      std::uint32_t* base = reinterpret_cast<std::uint32_t*>(packed + j0 * kq * 2);
      for (Index p = 0; p < kc; p += 32) {
        for (int t = 0; t < 16; ++t) {
          if (t >= kNr) {
            r[t] = _mm512_setzero_si512();
            continue;
          }
          const float* src = b + k0 + p + (j0 + t) * ldb;
          r[t] = (__m512i)_mm512_cvtne2ps_pbh(_mm512_loadu_ps(src + 16), _mm512_loadu_ps(src));
        }
        transpose_16x16(r);
        for (int t = 0; t < 16; ++t)
          _mm512_mask_storeu_epi32(base + (p / 2 + t) * kNr, lanes, r[t]);
      }
    }
  } else {  // row p of op(B) contiguous along j: a pair of rows feeds every panel in turn
    const __mmask16 lanes = (1u << kNr) - 1;
    const __mmask32 out_lanes = (1u << (2 * kNr)) - 1;
    for (Index q = 0; q < kq && full > 0; ++q) {
      const float* row0 = b + (k0 + 2 * q) * ldb;
      const float* row1 = row0 + ldb;
      for (Index j0 = 0; j0 < full; j0 += kNr)
        _mm512_mask_storeu_epi16(packed + j0 * kq * 2 + q * 2 * kNr, out_lanes,
                                 interleave_pairs(_mm512_maskz_loadu_ps(lanes, row0 + j0),
                                                  _mm512_maskz_loadu_ps(lanes, row1 + j0)));
    }
  }
  for (Index j0 = full; j0 < n; j0 += kNr)
    pack_b_panel_generic(trans, b, ldb, n, j0, k0, kc, packed + j0 * kq * 2);
}

// Applies the epilogue to one finished tile of C (rows i0.., `rows` <= 32, `cols` <= 8) while it
// is still in L1. Returns the squares of the tile added to `sq` (sum_squares only). Everything
// lives in locals: __m512 is may_alias, so a store through a vector reference or array would
// make the compiler reload every field of `e` after it.
__m512 finish_tile(const GemmEpilogue& e, Index i0, Index rows, Index j0, Index cols, float* c,
                   Index ldc, __m512 sq) {
  const float* const bias_p = e.bias;
  const bool do_tanh = e.tanh;
  const float* const t_p = e.tanh_of_input;
  const Index ld_t = e.ld_tanh;
  const bool do_sq = e.sum_squares != nullptr;
  float* const sums_p = e.row_sums;
  const __mmask16 m0 = rows >= 16 ? __mmask16(0xffff) : __mmask16((1u << rows) - 1);
  const __mmask16 m1 =
      rows >= 32 ? __mmask16(0xffff) : rows <= 16 ? __mmask16(0) : __mmask16((1u << (rows - 16)) - 1);
  const __m512 one = _mm512_set1_ps(1.0f);
  const __m512 b0 = bias_p ? _mm512_maskz_loadu_ps(m0, bias_p + i0) : _mm512_setzero_ps();
  const __m512 b1 = bias_p ? _mm512_maskz_loadu_ps(m1, bias_p + i0 + 16) : _mm512_setzero_ps();
  __m512 s0 = _mm512_setzero_ps(), s1 = _mm512_setzero_ps();
  auto apply = [&](__m512 v, const float* t, __mmask16 mask, __m512 bias) {
    if (bias_p) v = _mm512_add_ps(v, bias);
    if (do_tanh) v = Eigen::internal::ptanh(v);
    if (t_p) {  // v * (1 - t^2)
      const __m512 tv = _mm512_maskz_loadu_ps(mask, t);
      v = _mm512_mul_ps(v, _mm512_fnmadd_ps(tv, tv, one));
    }
    return v;
  };
  for (Index j = 0; j < cols; ++j) {
    float* cj = c + i0 + (j0 + j) * ldc;
    const float* tj = t_p ? t_p + i0 + (j0 + j) * ld_t : nullptr;
    const __m512 v0 = apply(_mm512_maskz_loadu_ps(m0, cj), tj, m0, b0);
    _mm512_mask_storeu_ps(cj, m0, v0);
    __m512 v1 = _mm512_setzero_ps();
    if (m1 != 0) {
      v1 = apply(_mm512_maskz_loadu_ps(m1, cj + 16), tj ? tj + 16 : nullptr, m1, b1);
      _mm512_mask_storeu_ps(cj + 16, m1, v1);
    }
    if (do_sq) sq = _mm512_fmadd_ps(v0, v0, _mm512_fmadd_ps(v1, v1, sq));
    s0 = _mm512_add_ps(s0, v0);
    s1 = _mm512_add_ps(s1, v1);
  }
  if (sums_p) {
    _mm512_mask_storeu_ps(sums_p + i0, m0, _mm512_add_ps(_mm512_maskz_loadu_ps(m0, sums_p + i0), s0));
    if (m1 != 0)
      _mm512_mask_storeu_ps(sums_p + i0 + 16, m1,
                            _mm512_add_ps(_mm512_maskz_loadu_ps(m1, sums_p + i0 + 16), s1));
  }
  return sq;
}

// C (=|+=) packed A block (m rows, kq pairs) * op(B) for the k range [k0, k0 + kc); `e` is
// applied to each tile if this is the last block.
void multiply_block(const std::uint16_t* pa, Index m, Index k0, Index kc, bool trans_b,
                    const float* b, Index ldb, Index n, float* c, Index ldc, GemmWorkspace& ws,
                    const GemmEpilogue* e) {
  const Index m_pad = (m + kMr - 1) / kMr * kMr;
  const Index n_pad = (n + kNr - 1) / kNr * kNr;
  const Index kq = (kc + 1) / 2;
  const bool accumulate = k0 > 0;
  // Grow only: shrinking and regrowing would value-initialise (memset) the panels every call.
  const auto need_b = static_cast<std::size_t>(n_pad * kq * 2);
  if (ws.packed_b16.size() < need_b) ws.packed_b16.resize(need_b);
  std::uint16_t* pb = ws.packed_b16.data();
  pack_b(trans_b, b, ldb, n, k0, kc, pb);
  alignas(64) float tile[kMr * kNr];
  __m512 sq = _mm512_setzero_ps();
  for (Index j0 = 0; j0 < n_pad; j0 += kNr) {
    const Index cols = std::min(kNr, n - j0);
    for (Index i0 = 0; i0 < m_pad; i0 += kMr) {
      const Index rows = std::min(kMr, m - i0);
      float* c_tile = c + i0 + j0 * ldc;
      if (rows == kMr && cols == kNr) {
        if (e != nullptr) {  // epilogue in registers
          TileEpilogue te;
          te.bias = e->bias ? e->bias + i0 : nullptr;
          te.tanh = e->tanh;
          te.t = e->tanh_of_input ? e->tanh_of_input + i0 + j0 * e->ld_tanh : nullptr;
          te.ld_t = e->ld_tanh;
          te.squares = e->sum_squares != nullptr;
          te.row_sums = e->row_sums ? e->row_sums + i0 : nullptr;
          sq = micro_kernel(kq, pa + i0 * kq * 2, pb + j0 * kq * 2, c_tile, ldc, accumulate, &te,
                            sq);
        } else {
          micro_kernel(kq, pa + i0 * kq * 2, pb + j0 * kq * 2, c_tile, ldc, accumulate, nullptr,
                       sq);
        }
      } else {  // edge: through a scratch tile, then the epilogue on the valid part
        micro_kernel(kq, pa + i0 * kq * 2, pb + j0 * kq * 2, tile, kMr, false, nullptr, sq);
        for (Index j = 0; j < cols; ++j)
          for (Index i = 0; i < rows; ++i)
            c_tile[i + j * ldc] = (accumulate ? c_tile[i + j * ldc] : 0.0f) + tile[i + j * kMr];
        if (e != nullptr) sq = finish_tile(*e, i0, rows, j0, cols, c, ldc, sq);
      }
    }
    // Squares summed in float over one column panel (at most 8 x m terms), then in double.
    if (e != nullptr && e->sum_squares != nullptr) {
      *e->sum_squares += static_cast<double>(_mm512_reduce_add_ps(sq));
      sq = _mm512_setzero_ps();
    }
  }
  if (e != nullptr && e->sum_squares != nullptr) _mm_sfence();  // order the streaming stores
}

// Offset of K block k0 (a multiple of kKc) in a packed A of m rows: every earlier block is full.
Index block_offset(Index m, Index k0) { return (m + kMr - 1) / kMr * kMr * k0; }

void check_dims(Index m, Index n, Index k, const char* who) {
  if (m < 1 || n < 1 || k < 1) throw std::invalid_argument(std::string(who) + ": empty dimension");
}

}  // namespace

bool bf16_gemm_available() { return true; }

void gemm_bf16(bool trans_a, bool trans_b, Index m, Index n, Index k, const float* a, Index lda,
               const float* b, Index ldb, float* c, Index ldc, GemmWorkspace& ws,
               const GemmEpilogue* epilogue) {
  check_dims(m, n, k, "gemm_bf16");
  const Index m_pad = (m + kMr - 1) / kMr * kMr;
  const auto need_a = static_cast<std::size_t>(m_pad * ((std::min(k, kKc) + 1) / 2) * 2);
  if (ws.packed_a16.size() < need_a) ws.packed_a16.resize(need_a);
  for (Index k0 = 0; k0 < k; k0 += kKc) {
    const Index kc = std::min(kKc, k - k0);
    pack_a(trans_a, a, lda, m, k0, kc, ws.packed_a16.data());
    multiply_block(ws.packed_a16.data(), m, k0, kc, trans_b, b, ldb, n, c, ldc, ws,
                   k0 + kc == k ? epilogue : nullptr);
  }
}

void pack_bf16(bool trans_a, Index m, Index k, const float* a, Index lda, PackedBf16& out) {
  check_dims(m, 1, k, "pack_bf16");
  out.m = m;
  out.k = k;
  const Index m_pad = (m + kMr - 1) / kMr * kMr;
  const Index last_k0 = (k - 1) / kKc * kKc;
  const auto need =
      static_cast<std::size_t>(block_offset(m, last_k0) + m_pad * ((k - last_k0 + 1) / 2) * 2);
  if (out.data.size() < need) out.data.resize(need);
  for (Index k0 = 0; k0 < k; k0 += kKc)
    pack_a(trans_a, a, lda, m, k0, std::min(kKc, k - k0), out.data.data() + block_offset(m, k0));
}

void pack_bf16_both(Index m, Index k, const float* w, Index ldw, PackedBf16& plain,
                    PackedBf16& transposed, const ColumnHook* before_columns) {
  check_dims(m, 1, k, "pack_bf16_both");
  if (m % kMr != 0 || k % kMr != 0 || m > kKc || k > kKc) {  // general shapes: two passes
    if (before_columns != nullptr) (*before_columns)(0, k);
    pack_bf16(false, m, k, w, ldw, plain);
    pack_bf16(true, k, m, w, ldw, transposed);
    return;
  }
  // One pass over W in blocks of 32 rows x 16 columns: interleaved column pairs give the plain
  // panels; the same registers, converted as row pairs and transposed, give the transposed ones.
  plain.m = m;
  plain.k = k;
  transposed.m = k;
  transposed.k = m;
  const auto need = static_cast<std::size_t>(m * k);
  if (plain.data.size() < need) plain.data.resize(need);
  if (transposed.data.size() < need) transposed.data.resize(need);
  const Index kq_plain = k / 2, kq_trans = m / 2;
  __m512 x[16][2];
  __m512i r[16];
  // Columns outer, rows inner: 16 sequential read streams down 16 columns of W.
  for (Index c0 = 0; c0 < k; c0 += 16) {
    if (before_columns != nullptr) (*before_columns)(c0, c0 + 16);
    for (Index r0 = 0; r0 < m; r0 += kMr) {
      std::uint16_t* plain_panel = plain.data.data() + r0 * kq_plain * 2;
      for (int c = 0; c < 16; ++c)
        for (int h = 0; h < 2; ++h) x[c][h] = _mm512_loadu_ps(w + r0 + 16 * h + (c0 + c) * ldw);
      for (int t = 0; t < 8; ++t)
        for (int h = 0; h < 2; ++h)
          _mm512_store_si512(plain_panel + (c0 / 2 + t) * 64 + 32 * h,
                             interleave_pairs(x[2 * t][h], x[2 * t + 1][h]));
      for (int c = 0; c < 16; ++c) r[c] = (__m512i)_mm512_cvtne2ps_pbh(x[c][1], x[c][0]);
      transpose_16x16(r);
      std::uint32_t* trans_panel =
          reinterpret_cast<std::uint32_t*>(transposed.data.data() + (c0 / kMr) * kMr * kq_trans * 2);
      for (int t = 0; t < 16; ++t)
        _mm512_store_si512(trans_panel + (r0 / 2 + t) * 32 + ((c0 % kMr) / 16) * 16, r[t]);
    }
  }
}

void gemm_bf16_packed(const PackedBf16& a, bool trans_b, Index n, const float* b, Index ldb,
                      float* c, Index ldc, GemmWorkspace& ws, const GemmEpilogue* epilogue) {
  check_dims(a.m, n, a.k, "gemm_bf16_packed");
  for (Index k0 = 0; k0 < a.k; k0 += kKc) {
    const Index kc = std::min(kKc, a.k - k0);
    multiply_block(a.data.data() + block_offset(a.m, k0), a.m, k0, kc, trans_b, b, ldb, n, c,
                   ldc, ws, k0 + kc == a.k ? epilogue : nullptr);
  }
}

#else

bool bf16_gemm_available() { return false; }

void gemm_bf16(bool, bool, Eigen::Index, Eigen::Index, Eigen::Index, const float*, Eigen::Index,
               const float*, Eigen::Index, float*, Eigen::Index, GemmWorkspace&,
               const GemmEpilogue*) {
  throw std::logic_error("gemm_bf16: built without AVX-512 BF16; use float32");
}
void pack_bf16(bool, Eigen::Index, Eigen::Index, const float*, Eigen::Index, PackedBf16&) {
  throw std::logic_error("pack_bf16: built without AVX-512 BF16; use float32");
}
void pack_bf16_both(Eigen::Index, Eigen::Index, const float*, Eigen::Index, PackedBf16&,
                    PackedBf16&, const ColumnHook*) {
  throw std::logic_error("pack_bf16_both: built without AVX-512 BF16; use float32");
}
void gemm_bf16_packed(const PackedBf16&, bool, Eigen::Index, const float*, Eigen::Index, float*,
                      Eigen::Index, GemmWorkspace&, const GemmEpilogue*) {
  throw std::logic_error("gemm_bf16_packed: built without AVX-512 BF16; use float32");
}

#endif

}  // namespace codesign::rl
