#pragma once
// Diagonal Gaussian with a state-independent log standard deviation (SB3's
// DiagGaussianDistribution): action ~ N(mean(obs), diag(exp(log_std))^2).
//
// Batches are column-per-sample, as in mlp.hpp: mean and actions are (act_dim x B), log_std is
// (act_dim). Log-probabilities are summed over action dimensions (one value per sample).
//
//   log p(a) = sum_i [ -0.5 ((a_i - mu_i) / sigma_i)^2 - log sigma_i - 0.5 log(2 pi) ]
//   H        = sum_i [ 0.5 + 0.5 log(2 pi) + log sigma_i ]            (same for every sample)
//   d log p / d mu_i        = (a_i - mu_i) / sigma_i^2
//   d log p / d log_sigma_i = ((a_i - mu_i) / sigma_i)^2 - 1
//   d H / d log_sigma_i     = 1
#include <Eigen/Core>

#include "rl/rng.hpp"

namespace codesign::rl {

template <class S>
struct GaussianTypes {
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using RowVec = Eigen::Matrix<S, 1, Eigen::Dynamic>;
};

// Log-density of each column of `actions` (1 x B).
template <class S>
typename GaussianTypes<S>::RowVec gaussian_log_prob(
    const Eigen::Ref<const typename GaussianTypes<S>::Mat>& mean,
    const Eigen::Ref<const typename GaussianTypes<S>::Vec>& log_std,
    const Eigen::Ref<const typename GaussianTypes<S>::Mat>& actions);

// Entropy of one sample's distribution (the same for all samples).
template <class S>
S gaussian_entropy(const Eigen::Ref<const typename GaussianTypes<S>::Vec>& log_std);

// Samples mean + exp(log_std) * z, z ~ N(0, 1) drawn from rng column by column (sample 0 dims
// 0..A-1, then sample 1, ...). Returns (act_dim x B), unclipped.
template <class S>
typename GaussianTypes<S>::Mat gaussian_sample(
    const Eigen::Ref<const typename GaussianTypes<S>::Mat>& mean,
    const Eigen::Ref<const typename GaussianTypes<S>::Vec>& log_std, Rng& rng);

// The same with the standard normals given (act_dim x B, as gaussian_sample draws them):
// mean + exp(log_std) * z, so gaussian_sample(mean, log_std, rng) equals this with the draws it
// would take. MPI ranks that run their environments' rollouts get the rollout's draws from rank 0.
template <class S>
typename GaussianTypes<S>::Mat gaussian_sample_with(
    const Eigen::Ref<const typename GaussianTypes<S>::Mat>& mean,
    const Eigen::Ref<const typename GaussianTypes<S>::Vec>& log_std, const Eigen::Ref<const Eigen::MatrixXd>& normals);

// act_dim x B standard normals, drawn as gaussian_sample draws them (column by column).
Eigen::MatrixXd standard_normals(Eigen::Index act_dim, Eigen::Index cols, Rng& rng);

// Chain rule through log_prob: given d_logp = dL/d(log p) (1 x B), writes
// d_mean = dL/d(mean) (act_dim x B) and ADDS dL/d(log_std) to d_log_std (act_dim).
template <class S>
void gaussian_log_prob_backward(const Eigen::Ref<const typename GaussianTypes<S>::Mat>& mean,
                                const Eigen::Ref<const typename GaussianTypes<S>::Vec>& log_std,
                                const Eigen::Ref<const typename GaussianTypes<S>::Mat>& actions,
                                const Eigen::Ref<const typename GaussianTypes<S>::RowVec>& d_logp,
                                typename GaussianTypes<S>::Mat& d_mean,
                                Eigen::Ref<typename GaussianTypes<S>::Vec> d_log_std);

// Chain rule through entropy: ADDS d_entropy * dH/d(log_std) (= d_entropy per component).
template <class S>
void gaussian_entropy_backward(S d_entropy, Eigen::Ref<typename GaussianTypes<S>::Vec> d_log_std);

}  // namespace codesign::rl
