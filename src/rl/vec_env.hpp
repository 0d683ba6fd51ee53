#pragma once
// N independent environments stepped together on a thread pool, with SB3 VecEnv auto-reset:
// when an episode ends in step(), the environment is reset at once (unseeded, continuing its RNG),
// the returned observation is the first one of the new episode and the last observation of the
// finished episode is kept in terminal_obs (SB3's info["terminal_observation"]) for bootstrapping.
//
// Determinism: environment i owns its state and RNG and is seeded with seed + i by reset();
// nothing is shared between environments, so results are bit-identical for any thread count.
//
// Layout: one column per environment (obs_dim x n_envs, act_dim x n_envs).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rl/env.hpp"
#include "rl/thread_pool.hpp"

namespace codesign::rl {

struct VecStepResult {
  VecStepResult() = default;
  // Sized for n environments with obs_dim observations: nothing ended yet.
  VecStepResult(std::size_t obs_dim, std::size_t n)
      : obs(static_cast<Eigen::Index>(obs_dim), static_cast<Eigen::Index>(n)),
        rewards(static_cast<Eigen::Index>(n)),
        terminated(n, 0),
        truncated(n, 0),
        terminal_obs(n),
        reasons(n) {}
  Eigen::MatrixXd obs;      // obs_dim x n: next observation (a reset observation where done)
  Eigen::VectorXd rewards;  // n
  std::vector<std::uint8_t> terminated;
  std::vector<std::uint8_t> truncated;
  // Set exactly where the episode ended: the observation the step produced before auto-reset.
  std::vector<std::optional<Eigen::VectorXd>> terminal_obs;
  std::vector<std::string> reasons;  // StepResult::reason where done, else empty
  bool done(std::size_t i) const { return terminated[i] || truncated[i]; }
};

class VecEnv {
 public:
  // n_threads: 1 steps the environments on the calling thread; 0 = hardware concurrency.
  VecEnv(const EnvFactory& factory, std::size_t n_envs, std::uint64_t seed,
         std::size_t n_threads = 1);

  std::size_t num_envs() const { return envs_.size(); }
  const EnvSpec& spec() const { return envs_.front()->spec(); }
  std::uint64_t seed() const { return seed_; }

  // Resets every environment i with seed + i; returns obs_dim x n.
  Eigen::MatrixXd reset();
  // actions: act_dim x n, passed to each environment as given (clip before if needed).
  const VecStepResult& step(const Eigen::MatrixXd& actions);

 private:
  std::vector<std::unique_ptr<Env>> envs_;
  std::uint64_t seed_;
  ThreadPool pool_;
  VecStepResult result_;
};

}  // namespace codesign::rl
