#pragma once
// The rollout backend of Algorithm 1 across MPI ranks (issue 20 §1).
//
// The ψ environments of an iteration are split into contiguous slices, one per rank of
// MPI_COMM_WORLD (env_slice). Rank 0 runs the co-design (it samples the designs, runs the PPO
// update, writes the run folder) and steps its own slice; every other rank holds only its slice's
// environments (a ThreadEnvPool of its own simulators) and serves rank 0's calls until told to stop
// (serve_env_pool, which waits for rank 0 without polling a core). Each call of the EnvPool
// interface is one exchange:
//   start(setups):  rank 0 sends each rank its slice's setups; each answers its first observations.
//   step(actions):  rank 0 sends each rank its slice's action columns, steps its own slice
//                   meanwhile, then receives each slice's rewards, end flags, in-band counts,
//                   observations, terminal observations and end reasons.
// Every environment owns its state and draws no random numbers (env_pool.hpp), and doubles cross
// the wire bit for bit, so a run gives the same results on any number of ranks and threads per
// rank. Live telemetry of training steps (set_step_observer) is kept for environments of rank 0's
// slice (environment 0 is always there); an observer on another rank's environment is refused.
#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "codesign/env_pool.hpp"

namespace codesign::cluster {

// The environments [first, first + count) of `rank` among `ranks`: contiguous, sizes differing by
// at most one, the larger slices first. Throws std::invalid_argument if ranks < 1, rank outside
// [0, ranks), or n_envs < ranks (every rank steps at least one environment).
struct EnvSlice {
  std::size_t first = 0, count = 0;
};
EnvSlice env_slice(std::size_t n_envs, int rank, int ranks);

// Rank 0's pool. `local` steps environments [0, env_slice(n_envs, 0, ranks).count); ranks
// 1..ranks-1 must be in serve_env_pool with their slices. The destructor tells them to stop.
class MpiEnvPool final : public core::EnvPool {
 public:
  MpiEnvPool(std::unique_ptr<core::ThreadEnvPool> local, std::size_t n_envs, int ranks);
  ~MpiEnvPool() override;
  MpiEnvPool(const MpiEnvPool&) = delete;
  MpiEnvPool& operator=(const MpiEnvPool&) = delete;

  std::size_t size() const override { return n_envs_; }
  const rl::EnvSpec& spec() const override { return local_->spec(); }
  Eigen::MatrixXd start(const std::vector<core::EpisodeSetup>& setups) override;
  const rl::VecStepResult& step(const Eigen::MatrixXd& actions, bool restart) override;
  int last_in_band(std::size_t i) const override { return last_in_band_.at(i); }
  double settle_seconds() const override;
  double step_seconds() const override;
  void set_step_observer(std::size_t i, StepObserver observer, int every) override;
  // The PPO update's threads: rank 0's rollout threads, or two threads of its own when rank 0 steps
  // its slice on one. The other ranks sleep through the update (serve_env_pool waits without
  // polling), so on a machine shared by the ranks the update still gets the actor and the critic
  // side by side, as with `--threads 2` in one process. Results do not change (env_pool.hpp).
  rl::ThreadPool* thread_pool() override { return update_pool_ ? update_pool_.get() : local_->thread_pool(); }

 private:
  std::array<double, 2> remote_seconds() const;

  std::unique_ptr<core::ThreadEnvPool> local_;
  std::unique_ptr<rl::ThreadPool> update_pool_;  // null when local_ has two threads or more
  std::size_t n_envs_;
  int ranks_;
  std::vector<EnvSlice> slices_;
  rl::VecStepResult result_;
  std::vector<int> last_in_band_;
};

// On rank 0, while ranks 1..ranks-1 are in serve_env_pool: the mean wall time of one exchange of a
// step's shape with one rank — rank 0 sends `out_doubles` numbers, the rank answers `in_doubles`
// (and, as after a step, a short second message) — over `repeats` rounds through every rank in
// turn. For the scaling model (scaling_model.hpp); the ranks keep serving afterwards.
double time_exchanges(int ranks, std::size_t out_doubles, std::size_t in_doubles, int repeats);

// Ranks 1..: answers rank 0's calls with `local` (the environments of env_slice(n_envs, rank,
// ranks)) until rank 0's pool is destroyed. Throws std::runtime_error if a message fails or does
// not fit the slice.
void serve_env_pool(core::ThreadEnvPool& local);

}  // namespace codesign::cluster
