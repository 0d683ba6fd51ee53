#pragma once
// Adam with PyTorch's semantics (torch.optim.Adam, no weight decay, no amsgrad):
//   m_t = b1 m_{t-1} + (1 - b1) g          v_t = b2 v_{t-1} + (1 - b2) g^2
//   p  -= lr / (1 - b1^t) * m_t / ( sqrt(v_t) / sqrt(1 - b2^t) + eps )
// Note where eps sits: it is added AFTER the bias correction of sqrt(v) (PyTorch), not to
// sqrt(v_hat) inside a single fraction of the original paper; the two differ in the first steps.
// SB3's PPO passes eps = 1e-5 (its policy optimizer_kwargs default), the default here.
//
// The optimiser works on a list of parameter blocks (pointer + gradient pointer + size). The
// moments of block i are created on the first step(); every later call must pass the same block
// sizes in the same order. All blocks share one step counter, like the parameters of one
// torch.optim.Adam.
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace codesign::rl {

struct AdamConfig {
  double beta1 = 0.9;
  double beta2 = 0.999;
  double eps = 1e-5;
};

template <class S>
struct AdamBlock {
  S* param = nullptr;
  const S* grad = nullptr;
  Eigen::Index size = 0;
};

template <class S>
class AdamT {
 public:
  explicit AdamT(const AdamConfig& config = {}) : config_(config) {}

  // One update of every block with learning rate lr. Throws std::invalid_argument if the block
  // sizes differ from the first call.
  // grad_scale multiplies every gradient on the fly (global gradient-norm clipping folded into
  // the same pass over memory; 1 = no scaling).
  void step(std::span<const AdamBlock<S>> blocks, double lr, double grad_scale = 1.0);

  // The same step, deferred: begin_step() advances the step counter and fixes lr and
  // grad_scale; apply() then updates entries [begin, end) of block i. Every entry of every block
  // must be applied exactly once before the next begin_step() (checked by count; throws
  // std::logic_error otherwise). step() = begin_step() + apply() on every whole block. The
  // learner uses it to update each layer's weights just before the next forward pass reads them
  // (still in cache for the bf16 packing).
  void begin_step(std::span<const AdamBlock<S>> blocks, double lr, double grad_scale = 1.0);
  void apply(std::span<const AdamBlock<S>> blocks, std::size_t i, Eigen::Index begin,
             Eigen::Index end);
  bool pending() const;  // a step was begun and not applied everywhere yet

  std::int64_t step_count() const { return t_; }
  const AdamConfig& config() const { return config_; }
  // First and second moments of block i (empty before the first step).
  const Eigen::Matrix<S, Eigen::Dynamic, 1>& first_moment(std::size_t i) const { return m_[i]; }
  const Eigen::Matrix<S, Eigen::Dynamic, 1>& second_moment(std::size_t i) const { return v_[i]; }
  std::size_t block_count() const { return m_.size(); }
  // Restores the state saved from step_count(), first_moment(i) and second_moment(i) (for
  // checkpoints). m and v must have one vector per block with equal sizes; throws
  // std::invalid_argument otherwise. No step may be pending.
  void restore(std::int64_t step_count, std::vector<Eigen::Matrix<S, Eigen::Dynamic, 1>> m,
               std::vector<Eigen::Matrix<S, Eigen::Dynamic, 1>> v);

 private:
  AdamConfig config_;
  std::int64_t t_ = 0;
  std::vector<Eigen::Matrix<S, Eigen::Dynamic, 1>> m_;
  std::vector<Eigen::Matrix<S, Eigen::Dynamic, 1>> v_;
  std::vector<Eigen::Index> applied_;  // per block: minus the entries still to apply
  struct Constants {
    S step_size = 0, inv_sqrt_bc2 = 0, eps = 0, b1 = 0, b2 = 0, c1 = 0, c2 = 0;
  } k_;  // of the current step
};

using Adam = AdamT<float>;

extern template class AdamT<float>;
extern template class AdamT<double>;

}  // namespace codesign::rl
