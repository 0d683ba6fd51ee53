#pragma once
// Whole rollouts of a feed-forward policy run where the environments are (docs/cluster.md).
//
// In the one-process rollout (rl/rollout.hpp) the policy acts on all ψ environments at each
// decision, so environments spread over MPI ranks would have to meet at every decision. A rank can
// instead run the whole rollout of its own environments and meet the others once, at the end, if
// every number it computes for an environment is the one the one-process rollout computes:
//   - the policy's normal draws: rank 0 draws the whole rollout's at the start, in the order the
//     one-process rollout draws them (rl::standard_normals, column by column, step after step), and
//     every rank acts with its columns of them (ActorCritic::act_with);
//   - the forward passes: a rank computes them on the ψ-wide batch with its environments' columns
//     at their own places (zeros elsewhere), so each column goes through the kernels chosen for ψ
//     columns at its own place: a column of a matrix product depends on no other column's values;
//   - the terminal bootstrap V(terminal obs) is one column, as in the one-process rollout.
// Observation statistics (ppo.normalize_observations) follow every environment's observations in
// order, and a recurrent policy keeps state: such rollouts stay step by step (OuterLoop decides).
//
// ShareRollout holds what the PPO buffer and the episode records need of n_steps decisions of some
// environments: per step the observations the policy saw, its sampled actions, values and
// log-probabilities, the rewards with the truncation bootstrap as the buffer stores them, the raw
// rewards, end flags, in-band counts and end reasons; then V of the observations after the last
// step.
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/env_pool.hpp"
#include "core/whisker_env.hpp"
#include "rl/actor_critic.hpp"
#include "rl/rollout_buffer.hpp"

namespace codesign::core {

struct RolloutStepColumns {
  Eigen::MatrixXf obs;               // obs_dim x n, as the policy saw them
  Eigen::MatrixXf actions;           // act_dim x n, the unclipped samples
  Eigen::RowVectorXf values, log_probs;
  Eigen::RowVectorXf rewards;        // with + γ V(terminal obs) where truncated and not terminated
  Eigen::RowVectorXd raw_rewards;    // as the environments gave them
  std::vector<char> done;            // terminated or truncated
  std::vector<int> in_band;          // where done: the episode's in-band decisions
  std::vector<std::string> reasons;  // where done: the end reason, else empty
};

struct ShareRollout {
  std::vector<RolloutStepColumns> steps;  // n_steps
  Eigen::RowVectorXf last_values;         // V(observations after the last step)
  double policy_s = 0.0;                  // wall seconds in the policy's forward passes
};

// A ShareRollout of n_steps decisions of n environments, every array sized and zero.
ShareRollout empty_share(int n_steps, std::size_t n, std::size_t obs_dim, std::size_t act_dim);

// Runs n_steps decisions of `model` on all of `pool`'s environments, started with `setups` (the
// pool's start()), which are columns places[0..] of a batch of `width` columns; normals[k] holds
// the standard normals of decision k for all `width` columns (act_dim x width). Actions are clipped
// to the pool's action bounds before they step; the last step does not restart finished episodes.
// std::invalid_argument if the sizes disagree.
ShareRollout run_share(EnvPool& pool, const std::vector<EpisodeSetup>& setups, const rl::ActorCritic& model,
                       rl::ActorCritic::InferenceCache& cache, const std::vector<std::size_t>& places,
                       std::size_t width, const std::vector<Eigen::MatrixXd>& normals, double gamma);

// run_share after the pool's start(): `obs` its first observations (obs_dim x size()).
ShareRollout run_started_share(EnvPool& pool, Eigen::MatrixXd obs, const rl::ActorCritic& model,
                               rl::ActorCritic::InferenceCache& cache, const std::vector<std::size_t>& places,
                               std::size_t width, const std::vector<Eigen::MatrixXd>& normals, double gamma);

// Copies `share` (environments in the share's order) into columns places[j] of `into`.
void place_share(const ShareRollout& share, const std::vector<std::size_t>& places, ShareRollout& into);

// Fills `buffer` with the rollout as rl::collect_rollout would (episode starts: 1 at step 0, then
// the previous step's end flags) and computes its returns and advantages.
void fill_buffer(const ShareRollout& rollout, double gamma, double gae_lambda, rl::RolloutBuffer& buffer);

// A pool that runs whole rollouts where its environments are (the MPI backend).
class RunAhead {
 public:
  virtual ~RunAhead() = default;
  // Starts every environment with its setup (as EnvPool::start) and runs normals.size() decisions
  // of `model` with those draws (normals[k]: act_dim x size()); returns the rollout of every
  // environment, in the environments' order.
  virtual ShareRollout rollout(const std::vector<EpisodeSetup>& setups, const rl::ActorCritic& model,
                               const std::vector<Eigen::MatrixXd>& normals, double gamma) = 0;
  // The next rollout's setups, known before the caller's PPO update: the pool may start
  // environments with them meanwhile where it has idle cores (a start draws nothing and depends on
  // the setup alone: env_pool.hpp). The next rollout() must get the same setups (else
  // std::invalid_argument). Default: nothing starts early.
  virtual void prestart(const std::vector<EpisodeSetup>& setups) { (void)setups; }
};

}  // namespace codesign::core
