#include "rl/mlp.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <Eigen/QR>

namespace codesign::rl {

template <class S>
MlpT<S>::MlpT(std::vector<int> sizes) : sizes_(std::move(sizes)) {
  if (sizes_.size() < 2) throw std::invalid_argument("MLP needs at least input and output sizes");
  Eigen::Index n = 0;
  for (std::size_t l = 0; l < sizes_.size(); ++l) {
    if (sizes_[l] <= 0)
      throw std::invalid_argument("MLP layer size must be > 0, got " + std::to_string(sizes_[l]));
    if (l == 0) continue;
    offsets_.push_back(n);
    n += static_cast<Eigen::Index>(sizes_[l]) * sizes_[l - 1] + sizes_[l];
  }
  params_ = Vec::Zero(n);
}

template <class S>
Eigen::Index MlpT<S>::bias_offset(int l) const {
  return offsets_[l - 1] + static_cast<Eigen::Index>(sizes_[l]) * sizes_[l - 1];
}

template <class S>
typename MlpT<S>::MatMap MlpT<S>::weight(int l) {
  return MatMap(params_.data() + offsets_[l - 1], sizes_[l], sizes_[l - 1]);
}
template <class S>
typename MlpT<S>::ConstMatMap MlpT<S>::weight(int l) const {
  return ConstMatMap(params_.data() + offsets_[l - 1], sizes_[l], sizes_[l - 1]);
}
template <class S>
typename MlpT<S>::VecMap MlpT<S>::bias(int l) {
  return VecMap(params_.data() + bias_offset(l), sizes_[l]);
}
template <class S>
typename MlpT<S>::ConstVecMap MlpT<S>::bias(int l) const {
  return ConstVecMap(params_.data() + bias_offset(l), sizes_[l]);
}

namespace {

// torch.nn.init.orthogonal_ for a (rows x cols) matrix, computed in double.
Eigen::MatrixXd orthogonal(Eigen::Index rows, Eigen::Index cols, double gain, Rng& rng) {
  const bool transpose = rows < cols;
  const Eigen::Index m = transpose ? cols : rows;  // tall: m >= n
  const Eigen::Index n = transpose ? rows : cols;
  Eigen::MatrixXd g(m, n);
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < m; ++i) g(i, j) = rng.normal();
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(g);
  Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(m, n);
  const auto r_diag = qr.matrixQR().diagonal();
  for (Eigen::Index j = 0; j < n; ++j)
    if (r_diag(j) < 0) q.col(j) = -q.col(j);
  if (transpose) q.transposeInPlace();
  return gain * q;
}

// dst = op(A) op(B) through the fast float32 GEMM when the shape is large enough for it to pay
// off; returns false (caller uses Eigen) otherwise.
// Shapes for which the blocked GEMMs beat Eigen (and which they are tested on).
bool fast_eligible(bool enabled, Eigen::Index m, Eigen::Index n, Eigen::Index k) {
  return enabled && fast_gemm_available() && m >= 64 && n >= 32 && k >= 32;
}

template <class S>
bool fast_product(bool enabled, MatmulPrecision precision, bool ta, bool tb, Eigen::Index m, Eigen::Index n, Eigen::Index k, const S* a,
                  Eigen::Index lda, const S* b, Eigen::Index ldb, S* c, Eigen::Index ldc,
                  GemmWorkspace& ws) {
  if constexpr (std::is_same_v<S, float>) {
    if (fast_eligible(enabled, m, n, k)) {
      if (precision == MatmulPrecision::BFloat16)
        gemm_bf16(ta, tb, m, n, k, a, lda, b, ldb, c, ldc, ws);
      else
        sgemm(ta, tb, m, n, k, a, lda, b, ldb, c, ldc, ws);
      return true;
    }
  }
  (void)enabled, (void)precision, (void)ta, (void)tb, (void)m, (void)n, (void)k, (void)a, (void)lda, (void)b, (void)ldb, (void)c,
      (void)ldc, (void)ws;
  return false;
}

}  // namespace

template <class S>
void MlpT<S>::set_matmul_precision(MatmulPrecision p) {
  if (p == MatmulPrecision::BFloat16 && !bf16_gemm_available())
    throw std::invalid_argument(
        "bf16 matrix products need AVX-512 BF16, which this build/CPU does not have");
  precision_ = p;
}

template <class S>
void MlpT<S>::init_orthogonal(S output_gain, Rng& rng) {
  for (int l = 1; l <= num_layers(); ++l) {
    const double gain = l == num_layers() ? static_cast<double>(output_gain) : std::sqrt(2.0);
    weight(l) = orthogonal(sizes_[l], sizes_[l - 1], gain, rng).template cast<S>();
    bias(l).setZero();
  }
}

template <class S>
const typename MlpT<S>::Mat& MlpT<S>::forward(const Eigen::Ref<const Mat>& x, Cache& cache,
                                              const ParamHook* before_use) const {
  if (x.rows() != input_dim())
    throw std::invalid_argument("MLP input has " + std::to_string(x.rows()) + " rows, expected " +
                                std::to_string(input_dim()));
  const int L = num_layers();
  cache.a.resize(static_cast<std::size_t>(L) + 1);
  cache.a[0] = x;
  cache.w_plain.resize(static_cast<std::size_t>(L) + 1);
  cache.w_transposed.resize(static_cast<std::size_t>(L) + 1);
  cache.w_transposed_ready.assign(static_cast<std::size_t>(L) + 1, 0);
  if (!cache.reuse_packed_weights || cache.w_plain_ready.size() != cache.w_plain.size())
    cache.w_plain_ready.assign(static_cast<std::size_t>(L) + 1, 0);
  for (int l = 1; l <= L; ++l) {
    Mat& out = cache.a[l];
    out.resize(sizes_[l], x.cols());
    const Mat& in = cache.a[l - 1];
    const bool bf16_layer = std::is_same_v<S, float> &&
                            precision_ == MatmulPrecision::BFloat16 &&
                            fast_eligible(fast_gemm_, out.rows(), out.cols(), in.rows());
    // W packed as W and W^T: its columns are made current just before they are packed.
    const bool pack_by_columns = bf16_layer && cache.keep_transposed_weights;
    if (before_use != nullptr && !pack_by_columns)  // the whole layer, before anything reads it
      (*before_use)(offsets_[l - 1], bias_offset(l) + sizes_[l]);
    if constexpr (std::is_same_v<S, float>) {
      if (bf16_layer) {
        const float* w = params_.data() + offsets_[l - 1];
        const auto li = static_cast<std::size_t>(l);
        if (pack_by_columns) {
          const Eigen::Index offset = offsets_[l - 1], rows = sizes_[l];
          const ColumnHook columns = [&](Eigen::Index c0, Eigen::Index c1) {
            (*before_use)(offset + c0 * rows, offset + c1 * rows);
          };
          pack_bf16_both(sizes_[l], sizes_[l - 1], w, sizes_[l], cache.w_plain[li],
                         cache.w_transposed[li], before_use != nullptr ? &columns : nullptr);
          if (before_use != nullptr) (*before_use)(bias_offset(l), bias_offset(l) + sizes_[l]);
          cache.w_transposed_ready[li] = 1;
        } else if (!(cache.reuse_packed_weights && cache.w_plain_ready[li])) {
          pack_bf16(false, sizes_[l], sizes_[l - 1], w, sizes_[l], cache.w_plain[li]);
        }
        cache.w_plain_ready[li] = 1;
        GemmEpilogue e;  // bias and tanh applied to each tile while it is in L1
        e.bias = params_.data() + bias_offset(l);
        e.tanh = l < L;
        gemm_bf16_packed(cache.w_plain[li], false, out.cols(), in.data(), in.rows(), out.data(),
                         out.rows(), cache.gemm, &e);
        continue;
      }
    }
    if (!fast_product<S>(fast_gemm_, precision_, false, false, out.rows(), out.cols(), in.rows(),
                         params_.data() + offsets_[l - 1], out.rows(), in.data(), in.rows(),
                         out.data(), out.rows(), cache.gemm)) {
      // A short inner dimension (the observation layer) column by column: no zero-fill and no
      // packing of the operands; bias and tanh while the column is in L1.
      if (in.rows() < 16) {
        const auto w = weight(l);
        const auto b = bias(l);
        for (Eigen::Index j = 0; j < in.cols(); ++j) {
          auto col = out.col(j);
          col = b + w.col(0) * in(0, j);
          for (Eigen::Index p = 1; p < in.rows(); ++p) col += w.col(p) * in(p, j);
          if (l < L) col.array() = col.array().tanh();
        }
        continue;
      }
      out.noalias() = weight(l) * in;
    }
    out.colwise() += bias(l);
    // (Kept apart from the bias: Eigen evaluates tanh of a broadcast sum one scalar at a time.)
    if (l < L) out.array() = out.array().tanh();
  }
  return cache.a.back();
}

template <class S>
typename MlpT<S>::Mat MlpT<S>::predict(const Eigen::Ref<const Mat>& x) const {
  Cache cache;
  cache.keep_transposed_weights = false;
  return forward(x, cache);
}

template <class S>
double MlpT<S>::backward(Cache& cache, const Eigen::Ref<const Mat>& d_out, Eigen::Ref<Vec> grad,
                         Mat* d_input) const {
  const int L = num_layers();
  if (static_cast<int>(cache.a.size()) != L + 1 || d_out.rows() != output_dim() ||
      d_out.cols() != cache.a.back().cols() || grad.size() != num_params())
    throw std::invalid_argument("MLP backward: sizes do not match the cached forward pass");
  [[maybe_unused]] const bool bf16 = precision_ == MatmulPrecision::BFloat16;
  const Eigen::Index batch = d_out.cols();
  cache.delta = d_out;
  double squared_norm = 0;
  bool bias_grad_done = false;  // g_b of layer l already summed by the epilogue of layer l + 1
  for (int l = L; l >= 1; --l) {
    const Mat& below = cache.a[l - 1];
    MatMap g_w(grad.data() + offsets_[l - 1], sizes_[l], sizes_[l - 1]);
    VecMap g_b(grad.data() + bias_offset(l), sizes_[l]);

    // Weight gradient dW = delta below^T (bf16: its squared norm summed in the epilogue).
    bool w_norm_done = false;
    if constexpr (std::is_same_v<S, float>) {
      if (bf16 && fast_eligible(fast_gemm_, g_w.rows(), g_w.cols(), batch)) {
        GemmEpilogue e;
        e.sum_squares = &squared_norm;
        gemm_bf16(false, true, g_w.rows(), g_w.cols(), batch, cache.delta.data(),
                  cache.delta.rows(), below.data(), below.rows(), g_w.data(), g_w.rows(),
                  cache.gemm, &e);
        w_norm_done = true;
      }
    }
    if (!w_norm_done &&
        !fast_product<S>(fast_gemm_, precision_, false, true, g_w.rows(), g_w.cols(), batch,
                         cache.delta.data(), cache.delta.rows(), below.data(), below.rows(),
                         g_w.data(), g_w.rows(), cache.gemm))
      g_w.noalias() = cache.delta * below.transpose();
    if (!w_norm_done) squared_norm += static_cast<double>(g_w.squaredNorm());
    // Bias gradient = row sums of delta, as a GEMV with a ones vector (vectorised; a rowwise
    // sum of a column-major matrix walks rows with a stride).
    if (!bias_grad_done) {
      if (cache.ones.size() != batch) cache.ones = Vec::Ones(batch);
      g_b.noalias() = cache.delta * cache.ones;
    }
    squared_norm += static_cast<double>(g_b.squaredNorm());
    bias_grad_done = false;

    if (l == 1) {
      if (d_input != nullptr) d_input->noalias() = weight(1).transpose() * cache.delta;
      break;
    }
    // Input gradient, times the tanh derivative of the layer below: (W^T delta) .* (1 - a^2).
    cache.delta_prev.resize(sizes_[l - 1], batch);
    if constexpr (std::is_same_v<S, float>) {
      const auto li = static_cast<std::size_t>(l);
      if (li < cache.w_transposed_ready.size() && cache.w_transposed_ready[li] &&
          fast_eligible(fast_gemm_, sizes_[l - 1], batch, sizes_[l])) {
        // W^T packed by the forward pass; the epilogue applies the derivative and sums the bias
        // gradient of layer l - 1.
        VecMap g_b_below(grad.data() + bias_offset(l - 1), sizes_[l - 1]);
        g_b_below.setZero();
        GemmEpilogue e;
        e.tanh_of_input = below.data();
        e.ld_tanh = below.rows();
        e.row_sums = g_b_below.data();
        gemm_bf16_packed(cache.w_transposed[li], false, batch, cache.delta.data(),
                         cache.delta.rows(), cache.delta_prev.data(), sizes_[l - 1], cache.gemm,
                         &e);
        cache.delta.swap(cache.delta_prev);
        bias_grad_done = true;
        continue;
      }
    }
    if (!fast_product<S>(fast_gemm_, precision_, true, false, sizes_[l - 1], batch, sizes_[l],
                         params_.data() + offsets_[l - 1], sizes_[l], cache.delta.data(),
                         cache.delta.rows(), cache.delta_prev.data(), sizes_[l - 1],
                         cache.gemm)) {
      if (sizes_[l] < 16) {  // output layer: a few outer products, column by column
        const auto w = weight(l);
        for (Eigen::Index j = 0; j < batch; ++j) {
          auto col = cache.delta_prev.col(j);
          col = w.row(0).transpose() * cache.delta(0, j);
          for (Eigen::Index p = 1; p < sizes_[l]; ++p)
            col += w.row(p).transpose() * cache.delta(p, j);
        }
      } else {
        cache.delta_prev.noalias() = weight(l).transpose() * cache.delta;
      }
    }
    // below = tanh(z): d tanh / dz = 1 - tanh^2
    cache.delta.resize(below.rows(), below.cols());
    cache.delta.array() = cache.delta_prev.array() * (S(1) - below.array().square());
  }
  return squared_norm;
}

template <class S>
double MlpT<S>::forward_flops(Eigen::Index batch) const {
  double macs = 0;
  for (int l = 1; l <= num_layers(); ++l) macs += double(sizes_[l]) * sizes_[l - 1];
  return 2.0 * macs * static_cast<double>(batch);
}

template <class S>
double MlpT<S>::backward_flops(Eigen::Index batch) const {
  double macs = 0;
  for (int l = 1; l <= num_layers(); ++l) {
    const double w = double(sizes_[l]) * sizes_[l - 1];
    macs += l > 1 ? 2 * w : w;  // weight gradient, plus input gradient above the first layer
  }
  return 2.0 * macs * static_cast<double>(batch);
}

template class MlpT<float>;
template class MlpT<double>;

}  // namespace codesign::rl
