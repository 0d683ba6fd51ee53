#pragma once
// Rollout collection backend of Algorithm 1: ψ whisker environments, each given its own design
// for the iteration, stepped together.
//
// EnvPool is the interface a backend implements (a multi-process backend would forward the same
// calls to worker processes); ThreadEnvPool steps the environments on a thread pool.
// Semantics (both): start() begins one episode per environment with its EpisodeSetup and
// returns the first observations; step() applies one action per environment. An environment
// whose episode ended (terminated or truncated) restarts at once with the SAME setup (SB3's
// auto-reset), its last observation kept in terminal_obs. Results never depend on the number
// of threads: every environment owns its state and draws no random numbers.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/whisker_env.hpp"
#include "rl/thread_pool.hpp"
#include "rl/vec_env.hpp"

namespace codesign::core {

class RunAhead;  // run_ahead.hpp

class EnvPool {
 public:
  virtual ~EnvPool() = default;
  virtual std::size_t size() const = 0;
  virtual const rl::EnvSpec& spec() const = 0;
  // setups.size() == size(); returns obs_dim x size.
  virtual Eigen::MatrixXd start(const std::vector<EpisodeSetup>& setups) = 0;
  // actions: act_dim x size, already clipped to the action bounds. restart = false on the last
  // step of a rollout: a finished episode is not restarted (its obs column is then the terminal
  // observation), which saves a settle per environment and iteration.
  virtual const rl::VecStepResult& step(const Eigen::MatrixXd& actions, bool restart) = 0;
  // Decisions inside the force band during the episode of environment i that ended at the last
  // step() (valid where that step ended an episode).
  virtual int last_in_band(std::size_t i) const = 0;
  // Seconds (summed over the environments, i.e. CPU time) spent settling and stepping so far.
  virtual double settle_seconds() const = 0;
  virtual double step_seconds() const = 0;
  // Seconds (CPU time) the simulator pool the environments lease from spent building simulators
  // and the designs' models so far (SimulatorPool::build_seconds; builds for any other user of that
  // pool count too): rollout work outside the settles and steps.
  virtual double build_seconds() const = 0;
  // Called with environment i's setup and the simulation state at the end of every `every`-th
  // decision it takes (counted over all its episodes), before an auto-reset, on the thread that
  // steps it. For decimated live telemetry of a training environment; it only reads, so results
  // do not change. An empty function or every <= 0: off.
  using StepObserver = std::function<void(const EpisodeSetup&, const TraceRow&)>;
  virtual void set_step_observer(std::size_t i, StepObserver observer, int every) = 0;
  // Per environment, the thread CPU seconds of its settles and steps since the last start() began
  // (that start's settle included): what its design cost in this iteration, for balancing the
  // environments over MPI ranks (cluster::assign_by_cost) and the bench's model.
  virtual std::vector<double> work_since_start() const = 0;
  // The threads that step the environments, idle between rollouts: the PPO update borrows them
  // for the actor's and the critic's passes side by side (results do not change). Null: none.
  virtual rl::ThreadPool* thread_pool() { return nullptr; }
  // A pool whose environments are stepped by other processes may run a feed-forward policy's
  // whole rollouts there (run_ahead.hpp), with the same results as start() and step() by step();
  // null: it does not.
  virtual RunAhead* run_ahead() { return nullptr; }
};

class ThreadEnvPool final : public EnvPool {
 public:
  // n_threads counts the caller (0: all cores). privileged: the environments append the
  // privileged features (whisker_env.hpp) for a privileged critic.
  ThreadEnvPool(std::shared_ptr<SimulatorPool> sims, const TaskConfig& task, std::size_t n_envs,
                std::size_t n_threads, bool privileged = false);
  std::size_t size() const override { return envs_.size(); }
  const rl::EnvSpec& spec() const override { return envs_.front()->spec(); }
  Eigen::MatrixXd start(const std::vector<EpisodeSetup>& setups) override;
  const rl::VecStepResult& step(const Eigen::MatrixXd& actions, bool restart) override;
  int last_in_band(std::size_t i) const override { return last_in_band_[i]; }
  double settle_seconds() const override;
  double step_seconds() const override;
  double build_seconds() const override { return sims_->build_seconds(); }
  const SimulatorPool& simulators() const { return *sims_; }
  SimulatorPool& simulators() { return *sims_; }
  void set_step_observer(std::size_t i, StepObserver observer, int every) override;
  std::size_t threads() const { return pool_.size(); }
  // How many of the threads step the environments (1 to threads(); the rest sleep): all of them
  // unless set. An MPI rank's pool has room for the threads of other ranks on its machine and uses
  // its own until they lend theirs (cluster/lent_threads.hpp). Results do not change.
  void set_threads_in_use(std::size_t n);
  std::size_t threads_in_use() const { return in_use_; }
  // `lender`, if set, is asked on the calling thread when a start() or step() begins and after each
  // environment that thread steps; its answer (clamped to 1..threads()) becomes the threads in use,
  // and a larger one wakes more threads into the call under way. Empty: off.
  void set_lender(std::function<std::size_t()> lender) { lender_ = std::move(lender); }
  rl::ThreadPool* thread_pool() override { return &pool_; }
  std::vector<double> work_since_start() const override;

 private:
  std::shared_ptr<SimulatorPool> sims_;
  std::vector<std::unique_ptr<WhiskerEnv>> envs_;
  rl::ThreadPool pool_;
  std::size_t in_use_;
  std::function<std::size_t()> lender_;
  std::function<std::size_t()> recount();  // for ThreadPool::parallel_for_ordered: empty without a lender
  rl::VecStepResult result_;
  std::vector<int> last_in_band_;
  struct Observer {
    StepObserver fn;
    int every = 0;
    std::int64_t decisions = 0;
  };
  std::vector<Observer> observers_;  // one per environment
  // Longest-first scheduling (ThreadPool::parallel_for_ordered): each environment's last step
  // and each design's last start, in seconds of wall time, predict the next ones; the costliest
  // are claimed first so the threads finish a step together. Only the order of work changes.
  std::vector<double> step_cost_;          // per environment
  std::vector<double> start_cost_;         // per design (+inf: never started here yet)
  std::vector<double> work_mark_;          // per environment: settle + step seconds at the last start()
  std::vector<std::size_t> order_;
  void order_by_cost(const std::vector<double>& cost);
};

}  // namespace codesign::core
