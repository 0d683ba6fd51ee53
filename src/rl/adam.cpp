#include "rl/adam.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace codesign::rl {

template <class S>
void AdamT<S>::step(std::span<const AdamBlock<S>> blocks, double lr) {
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  if (m_.empty()) {
    for (const auto& b : blocks) {
      m_.push_back(Vec::Zero(b.size));
      v_.push_back(Vec::Zero(b.size));
    }
  } else {
    bool same = blocks.size() == m_.size();
    for (std::size_t i = 0; same && i < blocks.size(); ++i) same = blocks[i].size == m_[i].size();
    if (!same) throw std::invalid_argument("Adam::step: parameter blocks changed between steps");
  }
  ++t_;
  const double b1 = config_.beta1, b2 = config_.beta2;
  const double bias_c1 = 1.0 - std::pow(b1, static_cast<double>(t_));
  const double bias_c2 = 1.0 - std::pow(b2, static_cast<double>(t_));
  const S step_size = static_cast<S>(lr / bias_c1);
  const S inv_sqrt_bc2 = static_cast<S>(1.0 / std::sqrt(bias_c2));
  const S eps = static_cast<S>(config_.eps);
  const S sb1 = static_cast<S>(b1), sb2 = static_cast<S>(b2);
  // Chunks of 2048 entries: the three vectorised Eigen expressions of a chunk run on data still
  // in L1, so the ~1M parameters, gradients and moments stream through memory once per step
  // (a scalar fused loop would not vectorise std::sqrt without -fno-math-errno).
  constexpr Eigen::Index kChunk = 2048;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const Eigen::Index n = blocks[i].size;
    for (Eigen::Index s = 0; s < n; s += kChunk) {
      const Eigen::Index len = std::min(kChunk, n - s);
      Eigen::Map<Vec> p(blocks[i].param + s, len);
      Eigen::Map<const Vec> g(blocks[i].grad + s, len);
      auto m = m_[i].segment(s, len);
      auto v = v_[i].segment(s, len);
      m = sb1 * m + (S(1) - sb1) * g;
      v = sb2 * v + (S(1) - sb2) * g.cwiseAbs2();
      p.array() -= step_size * m.array() / (v.array().sqrt() * inv_sqrt_bc2 + eps);
    }
  }
}

template class AdamT<float>;
template class AdamT<double>;

}  // namespace codesign::rl
