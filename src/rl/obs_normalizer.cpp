#include "rl/obs_normalizer.hpp"

#include <stdexcept>

namespace codesign::rl {

void RunningObsStats::update(const Eigen::MatrixXd& batch) {
  if (batch.rows() != mean.size() || batch.cols() < 1)
    throw std::invalid_argument("RunningObsStats::update: batch of the wrong size");
  const double b = static_cast<double>(batch.cols());
  const Eigen::VectorXd batch_mean = batch.rowwise().mean();
  const Eigen::VectorXd batch_var = (batch.colwise() - batch_mean).array().square().rowwise().mean();
  const Eigen::VectorXd delta = batch_mean - mean;
  const double total = count + b;
  mean += delta * (b / total);
  const Eigen::VectorXd m2 = var * count + batch_var * b + delta.cwiseProduct(delta) * (count * b / total);
  var = m2 / total;
  count = total;
}

ObsNormalization RunningObsStats::frozen() const {
  ObsNormalization n;
  n.mean = mean;
  n.var = var;
  return n;
}

Eigen::MatrixXd normalize_columns(const ObsNormalization& n, const Eigen::MatrixXd& obs) {
  Eigen::MatrixXd out(obs.rows(), obs.cols());
  for (Eigen::Index j = 0; j < obs.cols(); ++j) out.col(j) = n.apply(obs.col(j));
  return out;
}

}  // namespace codesign::rl
