#pragma once
// Observation normalisation with running statistics, as SB3's VecNormalize(norm_obs=True):
// per component, obs ← clip((obs − mean) / sqrt(var + ε), ±clip), ε = 1e-8, clip = 10, with
// mean and var the running moments of every observation seen in training so far (SB3's
// RunningMeanStd: count starts at 1e-4, batches merged with the parallel-variance formula of
// Chan et al., population variance). The statistics are frozen (ObsNormalization,
// policy_file.hpp) for evaluation and stored in the policy file.
//
// Where they are updated: rl::collect_rollout (rollout.hpp) updates with each step's batch of
// observations just before the policy acts on it, so every observation is counted once (the
// observation after a rollout's last step is counted when the next rollout acts on it).
// SB3 counts an observation when the environment returns it; over a run the two count the
// same observations.
#include <Eigen/Core>

#include "rl/policy_file.hpp"

namespace codesign::rl {

struct RunningObsStats {
  RunningObsStats() = default;
  explicit RunningObsStats(int dim)
      : mean(Eigen::VectorXd::Zero(dim)), var(Eigen::VectorXd::Ones(dim)) {}
  Eigen::VectorXd mean, var;
  double count = 1e-4;  // SB3's RunningMeanStd(epsilon=1e-4)
  // Merges a batch (dim × B, B ≥ 1) into the moments.
  void update(const Eigen::MatrixXd& batch);
  // The transform with the present moments (ε = 1e-8, clip = 10).
  ObsNormalization frozen() const;
};

// Applies a frozen normalisation to every column.
Eigen::MatrixXd normalize_columns(const ObsNormalization& n, const Eigen::MatrixXd& obs);

}  // namespace codesign::rl
