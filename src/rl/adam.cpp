#include "rl/adam.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace codesign::rl {

namespace {

#if defined(__AVX512F__)
// One fused pass of the float update over a block: reads p, g, m, v once and writes p, m, v
// once (the update is bound by memory traffic; ~1M parameters do not fit in L2). sqrt and the
// division are the correctly rounded AVX-512 instructions. Masked tail.
void adam_block_avx512(float* p, const float* g, float* m, float* v, Eigen::Index n, float b1,
                       float b2, float c1, float c2, float step_size, float inv_sqrt_bc2,
                       float eps) {
  const __m512 vb1 = _mm512_set1_ps(b1), vb2 = _mm512_set1_ps(b2);
  const __m512 vc1 = _mm512_set1_ps(c1), vc2 = _mm512_set1_ps(c2);
  const __m512 vstep = _mm512_set1_ps(step_size), vbc = _mm512_set1_ps(inv_sqrt_bc2);
  const __m512 veps = _mm512_set1_ps(eps);
  for (Eigen::Index i = 0; i < n; i += 16) {
    const __mmask16 k = n - i >= 16 ? __mmask16(0xffff) : __mmask16((1u << (n - i)) - 1);
    const __m512 gi = _mm512_maskz_loadu_ps(k, g + i);
    const __m512 mi = _mm512_fmadd_ps(vb1, _mm512_maskz_loadu_ps(k, m + i), _mm512_mul_ps(vc1, gi));
    const __m512 vi = _mm512_fmadd_ps(vb2, _mm512_maskz_loadu_ps(k, v + i),
                                      _mm512_mul_ps(vc2, _mm512_mul_ps(gi, gi)));
    const __m512 denom = _mm512_fmadd_ps(_mm512_sqrt_ps(vi), vbc, veps);
    const __m512 pi = _mm512_sub_ps(_mm512_maskz_loadu_ps(k, p + i),
                                    _mm512_div_ps(_mm512_mul_ps(vstep, mi), denom));
    _mm512_mask_storeu_ps(m + i, k, mi);
    _mm512_mask_storeu_ps(v + i, k, vi);
    _mm512_mask_storeu_ps(p + i, k, pi);
  }
}
#endif

}  // namespace

template <class S>
void AdamT<S>::begin_step(std::span<const AdamBlock<S>> blocks, double lr, double grad_scale) {
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  if (m_.empty()) {
    for (const auto& b : blocks) {
      m_.push_back(Vec::Zero(b.size));
      v_.push_back(Vec::Zero(b.size));
    }
    applied_.assign(blocks.size(), 0);
  } else {
    bool same = blocks.size() == m_.size();
    for (std::size_t i = 0; same && i < blocks.size(); ++i) same = blocks[i].size == m_[i].size();
    if (!same) throw std::invalid_argument("Adam::step: parameter blocks changed between steps");
  }
  if (pending())
    throw std::logic_error("Adam::begin_step: the previous step was not applied to every entry");
  ++t_;
  const double b1 = config_.beta1, b2 = config_.beta2;
  const double bias_c1 = 1.0 - std::pow(b1, static_cast<double>(t_));
  const double bias_c2 = 1.0 - std::pow(b2, static_cast<double>(t_));
  k_.step_size = static_cast<S>(lr / bias_c1);
  k_.inv_sqrt_bc2 = static_cast<S>(1.0 / std::sqrt(bias_c2));
  k_.eps = static_cast<S>(config_.eps);
  k_.b1 = static_cast<S>(b1);
  k_.b2 = static_cast<S>(b2);
  // (1 - b1) s g and (1 - b2) (s g)^2 with the clipping factor s folded into the constants.
  k_.c1 = static_cast<S>((1.0 - b1) * grad_scale);
  k_.c2 = static_cast<S>((1.0 - b2) * grad_scale * grad_scale);
  for (std::size_t i = 0; i < blocks.size(); ++i) applied_[i] = -blocks[i].size;
}

template <class S>
void AdamT<S>::restore(std::int64_t step_count, std::vector<Eigen::Matrix<S, Eigen::Dynamic, 1>> m,
                       std::vector<Eigen::Matrix<S, Eigen::Dynamic, 1>> v) {
  if (pending()) throw std::logic_error("Adam::restore: a step is pending");
  if (step_count < 0 || m.size() != v.size())
    throw std::invalid_argument("Adam::restore: negative step count or moment lists of different lengths");
  for (std::size_t i = 0; i < m.size(); ++i)
    if (m[i].size() != v[i].size()) throw std::invalid_argument("Adam::restore: moment sizes differ");
  if (step_count > 0 && m.empty()) throw std::invalid_argument("Adam::restore: steps taken but no moments");
  t_ = step_count;
  m_ = std::move(m);
  v_ = std::move(v);
  applied_.assign(m_.size(), 0);
}

template <class S>
bool AdamT<S>::pending() const {
  for (const Eigen::Index a : applied_)
    if (a != 0) return true;
  return false;
}

template <class S>
void AdamT<S>::apply(std::span<const AdamBlock<S>> blocks, std::size_t i, Eigen::Index begin,
                     Eigen::Index end) {
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  if (i >= blocks.size() || i >= m_.size() || begin < 0 || end > blocks[i].size || begin > end ||
      applied_[i] + (end - begin) > 0)
    throw std::logic_error("Adam::apply: range outside the pending step");
  applied_[i] += end - begin;
  S* const param = blocks[i].param + begin;
  const S* const grad = blocks[i].grad + begin;
  S* const m = m_[i].data() + begin;
  S* const v = v_[i].data() + begin;
  const Eigen::Index n = end - begin;
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<S, float>) {
    adam_block_avx512(param, grad, m, v, n, k_.b1, k_.b2, k_.c1, k_.c2, k_.step_size,
                      k_.inv_sqrt_bc2, k_.eps);
    return;
  }
#endif
  // Portable path (double, or no AVX-512). Chunks of 2048 entries: the three vectorised Eigen
  // expressions of a chunk run on data still in L1, so parameters, gradients and moments stream
  // through memory once (a scalar fused loop would not vectorise std::sqrt without
  // -fno-math-errno).
  constexpr Eigen::Index kChunk = 2048;
  for (Eigen::Index s = 0; s < n; s += kChunk) {
    const Eigen::Index len = std::min(kChunk, n - s);
    Eigen::Map<Vec> p(param + s, len);
    Eigen::Map<const Vec> g(grad + s, len);
    Eigen::Map<Vec> mm(m + s, len), vv(v + s, len);
    mm = k_.b1 * mm + k_.c1 * g;
    vv = k_.b2 * vv + k_.c2 * g.cwiseAbs2();
    p.array() -= k_.step_size * mm.array() / (vv.array().sqrt() * k_.inv_sqrt_bc2 + k_.eps);
  }
}

template <class S>
void AdamT<S>::step(std::span<const AdamBlock<S>> blocks, double lr, double grad_scale) {
  begin_step(blocks, lr, grad_scale);
  for (std::size_t i = 0; i < blocks.size(); ++i) apply(blocks, i, 0, blocks[i].size);
}

template class AdamT<float>;
template class AdamT<double>;

}  // namespace codesign::rl
