#include "rl/gru.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace codesign::rl {

namespace {

template <class S>
S sigmoid(S a) {
  return S(1) / (S(1) + std::exp(-a));
}

}  // namespace

template <class S>
GruT<S>::GruT(int input_dim, int hidden_dim) : input_(input_dim), hidden_(hidden_dim) {
  if (input_dim < 1 || hidden_dim < 1) throw std::invalid_argument("Gru: sizes must be positive");
  params_ = Vec::Zero(3 * Eigen::Index{hidden_dim} * (input_dim + hidden_dim + 2));
}

template <class S>
void GruT<S>::init_uniform(Rng& rng) {
  const double k = 1.0 / std::sqrt(static_cast<double>(hidden_));
  for (Eigen::Index i = 0; i < params_.size(); ++i) params_(i) = S(k * (2.0 * rng.uniform() - 1.0));
}

template <class S>
const typename GruT<S>::Mat& GruT<S>::forward(const Eigen::Ref<const Mat>& x, const Eigen::Ref<const RowVec>& starts,
                                              const Eigen::Ref<const Mat>& h0, Eigen::Index steps,
                                              Cache& c) const {
  const Eigen::Index b = h0.cols(), n = steps * b, hd = hidden_;
  if (steps < 1 || x.rows() != input_ || x.cols() != n || starts.size() != n || h0.rows() != hd)
    throw std::invalid_argument("Gru::forward: shapes disagree (x " + std::to_string(x.rows()) + " x " +
                                std::to_string(x.cols()) + ", " + std::to_string(steps) + " steps of " +
                                std::to_string(b) + " sequences)");
  c.steps = steps;
  c.batch = b;
  c.x = x;
  c.starts = starts;
  // The input part of every gate for all steps at once: one large product.
  c.gates.noalias() = w_ih() * x;
  c.gates.colwise() += b_ih();
  c.h_prev.resize(hd, n);
  c.hn.resize(hd, n);
  c.h.resize(hd, n);
  Mat gh(3 * hd, b);
  for (Eigen::Index t = 0; t < steps; ++t) {
    const Eigen::Index c0 = t * b;
    for (Eigen::Index j = 0; j < b; ++j) {
      const bool reset = starts(c0 + j) != S(0);
      if (reset)
        c.h_prev.col(c0 + j).setZero();
      else if (t == 0)
        c.h_prev.col(j) = h0.col(j);
      else
        c.h_prev.col(c0 + j) = c.h.col(c0 - b + j);
    }
    gh.noalias() = w_hh() * c.h_prev.middleCols(c0, b);
    gh.colwise() += b_hh();
    for (Eigen::Index j = 0; j < b; ++j) {
      const Eigen::Index col = c0 + j;
      for (Eigen::Index i = 0; i < hd; ++i) {
        const S r = sigmoid(c.gates(i, col) + gh(i, j));
        const S z = sigmoid(c.gates(hd + i, col) + gh(hd + i, j));
        const S hn = gh(2 * hd + i, j);
        const S nn = std::tanh(c.gates(2 * hd + i, col) + r * hn);
        c.gates(i, col) = r;
        c.gates(hd + i, col) = z;
        c.gates(2 * hd + i, col) = nn;
        c.hn(i, col) = hn;
        c.h(i, col) = (S(1) - z) * nn + z * c.h_prev(i, col);
      }
    }
  }
  return c.h;
}

template <class S>
void GruT<S>::step(const Eigen::Ref<const Mat>& x, const Eigen::Ref<const RowVec>& starts, Mat& h) const {
  const Eigen::Index b = x.cols(), hd = hidden_;
  if (x.rows() != input_ || starts.size() != b || h.rows() != hd || h.cols() != b)
    throw std::invalid_argument("Gru::step: shapes disagree");
  for (Eigen::Index j = 0; j < b; ++j)
    if (starts(j) != S(0)) h.col(j).setZero();
  Mat gi = w_ih() * x;
  gi.colwise() += b_ih();
  Mat gh = w_hh() * h;
  gh.colwise() += b_hh();
  for (Eigen::Index j = 0; j < b; ++j)
    for (Eigen::Index i = 0; i < hd; ++i) {
      const S r = sigmoid(gi(i, j) + gh(i, j));
      const S z = sigmoid(gi(hd + i, j) + gh(hd + i, j));
      const S nn = std::tanh(gi(2 * hd + i, j) + r * gh(2 * hd + i, j));
      h(i, j) = (S(1) - z) * nn + z * h(i, j);
    }
}

template <class S>
double GruT<S>::backward(Cache& c, const Eigen::Ref<const Mat>& d_out, Eigen::Ref<Vec> grad, Mat* d_input,
                         Mat* d_h0) const {
  const Eigen::Index b = c.batch, n = c.steps * b, hd = hidden_;
  if (d_out.rows() != hd || d_out.cols() != n || grad.size() != num_params())
    throw std::invalid_argument("Gru::backward: shapes disagree with the forward pass");
  MatMap dw_ih(grad.data(), 3 * hd, input_);
  MatMap dw_hh(grad.data() + w_hh_offset(), 3 * hd, hd);
  VecMap db_ih(grad.data() + b_ih_offset(), 3 * hd);
  VecMap db_hh(grad.data() + b_hh_offset(), 3 * hd);
  dw_hh.setZero();
  db_hh.setZero();
  c.d_gates_in.resize(3 * hd, n);
  Mat carry = Mat::Zero(hd, b);  // dL/dh_t through the later steps
  Mat d_gh(3 * hd, b), dh_prev(hd, b);
  for (Eigen::Index t = c.steps - 1; t >= 0; --t) {
    const Eigen::Index c0 = t * b;
    for (Eigen::Index j = 0; j < b; ++j) {
      const Eigen::Index col = c0 + j;
      for (Eigen::Index i = 0; i < hd; ++i) {
        const S dh = d_out(i, col) + carry(i, j);
        const S r = c.gates(i, col), z = c.gates(hd + i, col), nn = c.gates(2 * hd + i, col);
        const S hp = c.h_prev(i, col);
        // h' = (1 − z) n + z h
        const S da_n = dh * (S(1) - z) * (S(1) - nn * nn);  // through n's tanh
        const S da_z = dh * (hp - nn) * z * (S(1) - z);
        const S da_r = da_n * c.hn(i, col) * r * (S(1) - r);
        c.d_gates_in(i, col) = da_r;
        c.d_gates_in(hd + i, col) = da_z;
        c.d_gates_in(2 * hd + i, col) = da_n;
        d_gh(i, j) = da_r;
        d_gh(hd + i, j) = da_z;
        d_gh(2 * hd + i, j) = da_n * r;
        dh_prev(i, j) = dh * z;
      }
    }
    dw_hh.noalias() += d_gh * c.h_prev.middleCols(c0, b).transpose();
    db_hh += d_gh.rowwise().sum();
    dh_prev.noalias() += w_hh().transpose() * d_gh;
    // The reset mask: a state that was zeroed before step t passes no gradient back.
    for (Eigen::Index j = 0; j < b; ++j)
      if (c.starts(c0 + j) != S(0)) dh_prev.col(j).setZero();
    carry = dh_prev;
  }
  dw_ih.noalias() = c.d_gates_in * c.x.transpose();
  db_ih = c.d_gates_in.rowwise().sum();
  if (d_input) d_input->noalias() = w_ih().transpose() * c.d_gates_in;
  if (d_h0) *d_h0 = carry;
  return static_cast<double>(grad.squaredNorm());
}

template class GruT<float>;
template class GruT<double>;

}  // namespace codesign::rl
