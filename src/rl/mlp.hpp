#pragma once
// Multi-layer perceptron: tanh on every hidden layer, linear output layer.
//
// Precision: the learner runs in float32 (MlpT<float>, alias Mlp). Every GEMM of a PPO update is
// twice as fast in float32 as in float64 on AVX-512 hardware, and PyTorch/SB3 train in float32
// too. set_matmul_precision(BFloat16) rounds the operands of the large products to bf16 (float32
// sums, as bf16 autocast; docs/rl.md). The class is templated on the scalar so that the gradient
// checks in tests/rl run in float64 (MlpT<double>); both are explicitly instantiated in mlp.cpp.
//
// Layout (chosen for GEMM efficiency with Eigen's column-major storage):
//   * a batch is a matrix with one COLUMN per sample: input (in x B), output (out x B);
//   * layer l computes  a_l = f(W_l a_{l-1} + b_l),  W_l is (out_l x in_l), b_l is (out_l),
//     f = tanh for hidden layers and identity for the last;
//   * all parameters live in ONE flat vector, layer by layer: W_1 (column-major), b_1, W_2, b_2,
//     ... . Gradients use the same layout, so optimiser, gradient clipping and the policy file
//     treat the network as one vector. weight(l)/bias(l) are Eigen::Map views into it.
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "rl/gemm.hpp"
#include "rl/rng.hpp"

namespace codesign::rl {

template <class S>
class MlpT {
 public:
  using Scalar = S;
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using MatMap = Eigen::Map<Mat>;
  using ConstMatMap = Eigen::Map<const Mat>;
  using VecMap = Eigen::Map<Vec>;
  using ConstVecMap = Eigen::Map<const Vec>;

  // Activations of one forward pass, kept for the backward pass, plus scratch for backward.
  // Reusing one Cache across calls of the same batch size allocates nothing.
  struct Cache {
    std::vector<Mat> a;  // a[0] = input, a[l] = output of layer l (l = 1..num_layers)
    Mat delta;           // backward scratch: dL/d(pre-activation) of the current layer
    Mat delta_prev;      // backward scratch: dL/d(activation) of the layer below
    Vec ones;            // backward scratch: a vector of ones (bias gradients)
    GemmWorkspace gemm;  // packed panels of the blocked GEMMs (gemm.hpp)
    // bf16 products: each large layer's weight packed by forward() as W and, when
    // keep_transposed_weights, as W^T for backward() (one read of W serves both products).
    std::vector<PackedBf16> w_plain, w_transposed;
    std::vector<char> w_transposed_ready;  // per layer: w_transposed[l] is from this forward
    bool keep_transposed_weights = true;    // predict() turns it off (no backward follows)
    // Inference caches may keep w_plain across calls: set reuse_packed_weights, and call
    // weights_changed() whenever the parameters change (else stale weights are used).
    bool reuse_packed_weights = false;
    std::vector<char> w_plain_ready;
    void weights_changed() { w_plain_ready.clear(); }
  };

  MlpT() = default;
  // sizes = {input, hidden_1, ..., hidden_k, output}; at least two entries, all > 0.
  // Parameters are zero until init_orthogonal() or params() is written.
  explicit MlpT(std::vector<int> sizes);

  const std::vector<int>& sizes() const { return sizes_; }
  int num_layers() const { return static_cast<int>(sizes_.size()) - 1; }
  int input_dim() const { return sizes_.front(); }
  int output_dim() const { return sizes_.back(); }
  Eigen::Index num_params() const { return params_.size(); }

  Vec& params() { return params_; }
  const Vec& params() const { return params_; }
  // Views of layer l (1-based, 1..num_layers) into params(); same offsets apply to a gradient.
  MatMap weight(int l);
  ConstMatMap weight(int l) const;
  VecMap bias(int l);
  ConstVecMap bias(int l) const;
  Eigen::Index weight_offset(int l) const { return offsets_[l - 1]; }
  Eigen::Index bias_offset(int l) const;

  // Orthogonal init as torch.nn.init.orthogonal_ (QR of a Gaussian matrix, sign-fixed by
  // diag(R)), gain sqrt(2) for hidden layers and `output_gain` for the last; biases zero.
  void init_orthogonal(S output_gain, Rng& rng);

  // Large float32 layers use rl::sgemm (gemm.hpp) when available, everything else Eigen.
  // set_fast_gemm(false) forces Eigen everywhere (the benchmark's baseline).
  void set_fast_gemm(bool on) { fast_gemm_ = on; }
  bool fast_gemm() const { return fast_gemm_; }
  // BFloat16: the large float32 products use rl::gemm_bf16 instead of rl::sgemm (bf16 operands,
  // float32 sums; see gemm.hpp). Requires bf16_gemm_available(); ignored for double.
  void set_matmul_precision(MatmulPrecision p);
  MatmulPrecision matmul_precision() const { return precision_; }
  // Batched forward; fills cache.a and returns cache.a.back() (output_dim x B).
  // If before_use is given, it is called with flat parameter ranges [begin, end) before forward
  // reads them; the ranges are disjoint and together cover every parameter once (layer by layer;
  // a weight packed for bf16 column block by column block). The learner finishes its deferred
  // optimiser step through it (ppo.cpp).
  using ParamHook = std::function<void(Eigen::Index begin, Eigen::Index end)>;
  const Mat& forward(const Eigen::Ref<const Mat>& x, Cache& cache,
                     const ParamHook* before_use = nullptr) const;
  // Forward without keeping anything.
  Mat predict(const Eigen::Ref<const Mat>& x) const;

  // Backward pass of the forward that filled `cache`, with the parameters unchanged since then
  // (the bf16 path reuses the weights packed by that forward). d_out = dL/d(output) (output_dim x B).
  // Writes (overwrites) dL/dparams into grad (size num_params(), same layout as params()).
  // If d_input is non-null it receives dL/d(input) (input_dim x B); otherwise that GEMM is
  // skipped. Returns the squared L2 norm of grad, summed layer by layer right after each part is
  // written (while it is still in cache; global gradient clipping needs it).
  double backward(Cache& cache, const Eigen::Ref<const Mat>& d_out, Eigen::Ref<Vec> grad,
                Mat* d_input = nullptr) const;

  // Floating-point operations of the GEMMs of forward and of backward (2 per multiply-add;
  // backward without the input gradient of the first layer) for a batch of B samples; used by
  // the benchmark.
  double forward_flops(Eigen::Index batch) const;
  double backward_flops(Eigen::Index batch) const;

 private:
  std::vector<int> sizes_;
  std::vector<Eigen::Index> offsets_;  // start of W_l in params_
  Vec params_;
  bool fast_gemm_ = true;
  MatmulPrecision precision_ = MatmulPrecision::Float32;
};

using Mlp = MlpT<float>;

extern template class MlpT<float>;
extern template class MlpT<double>;

}  // namespace codesign::rl
