#pragma once
// One gated recurrent unit layer (GRU), with PyTorch's equations (torch.nn.GRU, one layer):
//   r  = σ(W_ir x + b_ir + W_hr h + b_hr)
//   z  = σ(W_iz x + b_iz + W_hz h + b_hz)
//   n  = tanh(W_in x + b_in + r ⊙ (W_hn h + b_hn))
//   h' = (1 − z) ⊙ n + z ⊙ h
// over a sequence of T steps for a batch of B sequences, with back-propagation through the whole
// given sequence (the caller cuts sequences: the learner passes one rollout column, 50 decisions
// in the co-design).
//
// Layout, as mlp.hpp: one COLUMN per sample. A sequence batch is (dim x T·B) with column t·B + b
// holding step t of sequence b (the rollout buffer's t·n_envs + e when all columns are taken).
// Per-step reset masks `starts` (1 x T·B): where starts(t·B + b) = 1, sequence b's state is set
// to zero before step t (an episode begins there), so nothing flows across it, forward or back.
// The initial state h0 (H x B) is the state before step 0 (and is also masked by starts at t = 0).
//
// Parameters in ONE flat vector: W_ih (3H x I, column-major), W_hh (3H x H), b_ih (3H), b_hh
// (3H); the 3H rows are the gates in PyTorch's order r, z, n. Gradients use the same layout.
// Init as PyTorch: every parameter uniform in [−1/√H, 1/√H] (SB3-contrib's recurrent policies
// keep the recurrent layer's default init; only the MLP and heads get orthogonal init).
#include <vector>

#include <Eigen/Core>

#include "rl/rng.hpp"

namespace codesign::rl {

template <class S>
class GruT {
 public:
  using Scalar = S;
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using RowVec = Eigen::Matrix<S, 1, Eigen::Dynamic>;
  using MatMap = Eigen::Map<Mat>;
  using ConstMatMap = Eigen::Map<const Mat>;
  using VecMap = Eigen::Map<Vec>;
  using ConstVecMap = Eigen::Map<const Vec>;

  // What backward() needs of one forward pass (reused across calls without reallocating when
  // the shapes repeat).
  struct Cache {
    Mat x;       // input, I x T·B
    Mat h_prev;  // state each step started from, after the reset mask, H x T·B
    Mat gates;   // r, z, n stacked (3H x T·B)
    Mat hn;      // W_hn h_prev + b_hn, H x T·B (n's recurrent part before r scales it)
    Mat h;       // outputs h_t, H x T·B
    RowVec starts;
    Eigen::Index steps = 0, batch = 0;
    Mat d_gates_in;  // backward scratch: dL/d(W_ih x + b_ih) of every step, 3H x T·B
  };

  GruT() = default;
  GruT(int input_dim, int hidden_dim);

  int input_dim() const { return input_; }
  int hidden_dim() const { return hidden_; }
  Eigen::Index num_params() const { return params_.size(); }
  Vec& params() { return params_; }
  const Vec& params() const { return params_; }
  // Views into params() (and, with the same offsets, into a gradient).
  ConstMatMap w_ih() const { return {params_.data(), 3 * hidden_, input_}; }
  ConstMatMap w_hh() const { return {params_.data() + w_hh_offset(), 3 * hidden_, hidden_}; }
  ConstVecMap b_ih() const { return {params_.data() + b_ih_offset(), 3 * hidden_}; }
  ConstVecMap b_hh() const { return {params_.data() + b_hh_offset(), 3 * hidden_}; }
  Eigen::Index w_hh_offset() const { return Eigen::Index{3} * hidden_ * input_; }
  Eigen::Index b_ih_offset() const { return w_hh_offset() + Eigen::Index{3} * hidden_ * hidden_; }
  Eigen::Index b_hh_offset() const { return b_ih_offset() + Eigen::Index{3} * hidden_; }

  // PyTorch's default init (see top of file).
  void init_uniform(Rng& rng);

  // Forward over `steps` steps: x is (I x steps·B), starts (1 x steps·B), h0 (H x B). Fills cache
  // and returns the outputs (H x steps·B); the last step's state is its last B columns.
  const Mat& forward(const Eigen::Ref<const Mat>& x, const Eigen::Ref<const RowVec>& starts,
                     const Eigen::Ref<const Mat>& h0, Eigen::Index steps, Cache& cache) const;

  // One step without keeping anything: h ← GRU(x, h · (1 − starts)) for B columns.
  void step(const Eigen::Ref<const Mat>& x, const Eigen::Ref<const RowVec>& starts, Mat& h) const;

  // Back-propagation through time of the forward that filled `cache`. d_out = dL/d(h_t) for every
  // output (H x steps·B). Writes (overwrites) dL/dparams into grad; if d_input is non-null it
  // receives dL/dx (I x steps·B); if d_h0 is non-null, dL/dh0 (H x B). Returns the squared norm
  // of grad.
  double backward(Cache& cache, const Eigen::Ref<const Mat>& d_out, Eigen::Ref<Vec> grad,
                  Mat* d_input = nullptr, Mat* d_h0 = nullptr) const;

 private:
  int input_ = 0, hidden_ = 0;
  Vec params_;
};

using Gru = GruT<float>;

extern template class GruT<float>;
extern template class GruT<double>;

}  // namespace codesign::rl
