#include "rl/gaussian.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace codesign::rl {

namespace {
template <class S>
void check(Eigen::Index mean_rows, Eigen::Index mean_cols, Eigen::Index log_std_size,
           Eigen::Index act_rows, Eigen::Index act_cols) {
  if (mean_rows != log_std_size || act_rows != mean_rows || act_cols != mean_cols)
    throw std::invalid_argument("Gaussian: mean, log_std and actions sizes disagree");
}
}  // namespace

template <class S>
typename GaussianTypes<S>::RowVec gaussian_log_prob(
    const Eigen::Ref<const typename GaussianTypes<S>::Mat>& mean,
    const Eigen::Ref<const typename GaussianTypes<S>::Vec>& log_std,
    const Eigen::Ref<const typename GaussianTypes<S>::Mat>& actions) {
  check<S>(mean.rows(), mean.cols(), log_std.size(), actions.rows(), actions.cols());
  const typename GaussianTypes<S>::Vec inv_std = (-log_std.array()).exp();
  const S constant = log_std.sum() + S(0.5 * std::log(2.0 * std::numbers::pi)) * S(log_std.size());
  typename GaussianTypes<S>::RowVec out(mean.cols());
  for (Eigen::Index j = 0; j < mean.cols(); ++j) {
    const S sq = ((actions.col(j) - mean.col(j)).array() * inv_std.array()).square().sum();
    out(j) = S(-0.5) * sq - constant;
  }
  return out;
}

template <class S>
S gaussian_entropy(const Eigen::Ref<const typename GaussianTypes<S>::Vec>& log_std) {
  const S per_dim = S(0.5 + 0.5 * std::log(2.0 * std::numbers::pi));
  return per_dim * S(log_std.size()) + log_std.sum();
}

Eigen::MatrixXd standard_normals(Eigen::Index act_dim, Eigen::Index cols, Rng& rng) {
  Eigen::MatrixXd z(act_dim, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < act_dim; ++i) z(i, j) = rng.normal();
  return z;
}

template <class S>
typename GaussianTypes<S>::Mat gaussian_sample_with(
    const Eigen::Ref<const typename GaussianTypes<S>::Mat>& mean,
    const Eigen::Ref<const typename GaussianTypes<S>::Vec>& log_std, const Eigen::Ref<const Eigen::MatrixXd>& normals) {
  check<S>(mean.rows(), mean.cols(), log_std.size(), normals.rows(), normals.cols());
  const typename GaussianTypes<S>::Vec stddev = log_std.array().exp();
  typename GaussianTypes<S>::Mat out(mean.rows(), mean.cols());
  for (Eigen::Index j = 0; j < mean.cols(); ++j)
    for (Eigen::Index i = 0; i < mean.rows(); ++i)
      out(i, j) = mean(i, j) + stddev(i) * static_cast<S>(normals(i, j));
  return out;
}

template <class S>
typename GaussianTypes<S>::Mat gaussian_sample(
    const Eigen::Ref<const typename GaussianTypes<S>::Mat>& mean,
    const Eigen::Ref<const typename GaussianTypes<S>::Vec>& log_std, Rng& rng) {
  check<S>(mean.rows(), mean.cols(), log_std.size(), mean.rows(), mean.cols());
  return gaussian_sample_with<S>(mean, log_std, standard_normals(mean.rows(), mean.cols(), rng));
}

template <class S>
void gaussian_log_prob_backward(const Eigen::Ref<const typename GaussianTypes<S>::Mat>& mean,
                                const Eigen::Ref<const typename GaussianTypes<S>::Vec>& log_std,
                                const Eigen::Ref<const typename GaussianTypes<S>::Mat>& actions,
                                const Eigen::Ref<const typename GaussianTypes<S>::RowVec>& d_logp,
                                typename GaussianTypes<S>::Mat& d_mean,
                                Eigen::Ref<typename GaussianTypes<S>::Vec> d_log_std) {
  check<S>(mean.rows(), mean.cols(), log_std.size(), actions.rows(), actions.cols());
  if (d_logp.size() != mean.cols() || d_log_std.size() != log_std.size())
    throw std::invalid_argument("Gaussian backward: gradient sizes disagree");
  const typename GaussianTypes<S>::Vec inv_var = (S(-2) * log_std.array()).exp();
  d_mean.resize(mean.rows(), mean.cols());
  for (Eigen::Index j = 0; j < mean.cols(); ++j) {
    for (Eigen::Index i = 0; i < mean.rows(); ++i) {
      const S diff = actions(i, j) - mean(i, j);
      d_mean(i, j) = d_logp(j) * diff * inv_var(i);
      d_log_std(i) += d_logp(j) * (diff * diff * inv_var(i) - S(1));
    }
  }
}

template <class S>
void gaussian_entropy_backward(S d_entropy, Eigen::Ref<typename GaussianTypes<S>::Vec> d_log_std) {
  d_log_std.array() += d_entropy;
}

#define CODESIGN_GAUSSIAN_INSTANTIATE(S)                                                         \
  template GaussianTypes<S>::RowVec gaussian_log_prob<S>(                                        \
      const Eigen::Ref<const GaussianTypes<S>::Mat>&, const Eigen::Ref<const GaussianTypes<S>::Vec>&, \
      const Eigen::Ref<const GaussianTypes<S>::Mat>&);                                           \
  template S gaussian_entropy<S>(const Eigen::Ref<const GaussianTypes<S>::Vec>&);                \
  template GaussianTypes<S>::Mat gaussian_sample<S>(const Eigen::Ref<const GaussianTypes<S>::Mat>&, \
                                                    const Eigen::Ref<const GaussianTypes<S>::Vec>&, \
                                                    Rng&);                                       \
  template GaussianTypes<S>::Mat gaussian_sample_with<S>(const Eigen::Ref<const GaussianTypes<S>::Mat>&, \
                                                         const Eigen::Ref<const GaussianTypes<S>::Vec>&, \
                                                         const Eigen::Ref<const Eigen::MatrixXd>&);  \
  template void gaussian_log_prob_backward<S>(                                                   \
      const Eigen::Ref<const GaussianTypes<S>::Mat>&, const Eigen::Ref<const GaussianTypes<S>::Vec>&, \
      const Eigen::Ref<const GaussianTypes<S>::Mat>&, const Eigen::Ref<const GaussianTypes<S>::RowVec>&, \
      GaussianTypes<S>::Mat&, Eigen::Ref<GaussianTypes<S>::Vec>);                                \
  template void gaussian_entropy_backward<S>(S, Eigen::Ref<GaussianTypes<S>::Vec>);

CODESIGN_GAUSSIAN_INSTANTIATE(float)
CODESIGN_GAUSSIAN_INSTANTIATE(double)
#undef CODESIGN_GAUSSIAN_INSTANTIATE

}  // namespace codesign::rl
