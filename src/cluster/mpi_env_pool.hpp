#pragma once
// The rollout backend of Algorithm 1 across MPI ranks (docs/cluster.md).
//
// The ψ environments of an iteration are shared out over the ranks of MPI_COMM_WORLD: env_slice
// fixes how many each rank steps, assign_by_cost (env_assignment.hpp) which ones, anew at every
// start() from the cost each design had when last stepped, so that the ranks, which meet at every
// decision, carry similar work. Rank 0 runs the co-design (it samples the designs, runs the PPO
// update, writes the run folder) and steps its own share; every other rank holds only its share's
// environments (a ThreadEnvPool of its own simulators) and serves rank 0's calls until told to stop
// (serve_env_pool, which waits for rank 0 without polling a core). Each call of the EnvPool
// interface is one exchange:
//   start(setups):  rank 0 asks each rank what its environments cost in the iteration just ended
//                   (none before the first start), chooses the assignment, sends each rank its
//                   share's setups; each answers its first observations.
//   step(actions):  rank 0 sends each rank its share's action columns, steps its own share
//                   meanwhile, then receives each share's rewards, end flags, in-band counts,
//                   observations, terminal observations and end reasons.
//   rollout(...):   (run_ahead.hpp; the co-design's feed-forward rollouts without observation
//                   statistics) after the same assignment as start(), each rank gets its share's
//                   setups and places, then the policy's parameters and the rollout's normal draws
//                   (two broadcasts); every rank, rank 0 included, runs its environments' whole
//                   rollout and the ranks meet once, when each sends rank 0 its record.
//   prestart(...):  (before rank 0's PPO update, OuterLoop) the next rollout's assignment, and its
//                   setups and places to the ranks with idle cores meanwhile, which start their
//                   environments at once; that rollout then sends those ranks only the
//                   broadcasts. A start depends on its setup alone, so the results do not change.
// Every environment owns its state, draws no random numbers and starts each iteration afresh
// (env_pool.hpp), and doubles cross the wire bit for bit, so a run gives the same results on any
// number of ranks and threads per rank, whichever rank steps which environment. Live telemetry of
// training steps (set_step_observer) is kept for environments of rank 0's slice (environment 0 is
// always there); they stay on rank 0 at their own place. An observer on another place is refused.
#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "cluster/env_assignment.hpp"
#include "cluster/lent_threads.hpp"
#include "core/env_pool.hpp"
#include "core/run_ahead.hpp"
#include "rl/actor_critic.hpp"

namespace codesign::cluster {

// Rank 0's pool. `local` holds env_slice(n_envs, 0, ranks).count environments; ranks 1..ranks-1
// must be in serve_env_pool with pools of their slices' sizes. The destructor tells them to stop.
class MpiEnvPool final : public core::EnvPool, public core::RunAhead {
 public:
  // `lending`: rank 0's own threads and the other ranks on its machine, whose threads it takes up
  // in a whole rollout once they are done (lent_threads.hpp); `local` holds room for them. Default:
  // none lent, rank 0 uses all of local's threads.
  MpiEnvPool(std::unique_ptr<core::ThreadEnvPool> local, std::size_t n_envs, int ranks, Lending lending = {});
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
  double build_seconds() const override;
  void set_step_observer(std::size_t i, StepObserver observer, int every) override;
  // One exchange with every rank; between a prestart() and its rollout, the last rollout's work as
  // read before the prestart (no exchange).
  std::vector<double> work_since_start() const override;
  // The PPO update's threads: rank 0's rollout threads, or two threads of its own when rank 0 steps
  // its slice on one. The other ranks sleep through the update (serve_env_pool waits without
  // polling; those with cores of their own start the next rollout first: prestart()), so on a
  // machine shared by the ranks the update still gets the actor and the critic
  // side by side, as with `--threads 2` in one process. Results do not change (env_pool.hpp).
  rl::ThreadPool* thread_pool() override { return update_pool_ ? update_pool_.get() : local_->thread_pool(); }
  int ranks() const { return ranks_; }
  // Whole rollouts on the ranks (RunAhead), on by default; off: every rollout goes step by step,
  // meeting at every decision (for the bench's comparison). Results are the same either way.
  core::RunAhead* run_ahead() override { return run_ahead_ ? this : nullptr; }
  void set_run_ahead(bool on) { run_ahead_ = on; }
  core::ShareRollout rollout(const std::vector<core::EpisodeSetup>& setups, const rl::ActorCritic& model,
                             const std::vector<Eigen::MatrixXd>& normals, double gamma) override;
  // Chooses the next rollout's assignment now and sends each rank that has idle cores during rank
  // 0's update (prestarts()) its share's setups, places and meshes: it starts its environments
  // (meshes, builds, settles) at once and waits for the rollout's draws. Rank 0's own share starts
  // in the rollout, as do the shares of ranks on rank 0's machine when the update takes their cores
  // (rank 0 with fewer than two threads of its own: the update runs the actor and the critic on two).
  void prestart(const std::vector<core::EpisodeSetup>& setups) override;
  // Whether rank r (1..) gets its setups before rank 0's update (see prestart()).
  bool prestarts(int r) const;
  // Rollouts whose shares some rank started before rank 0's update, so far.
  int prestarted_rollouts() const { return prestarted_rollouts_; }
  // Rollouts run on the ranks so far (RunAhead::rollout), and the wall seconds rank 0 waited for
  // the other ranks' records after its own share was done.
  int rollouts() const { return rollouts_; }
  double rollout_wait_seconds() const { return rollout_wait_s_; }
  // Off: every start keeps the contiguous slices (env_slice), whatever the costs; for the bench's
  // comparison of the two. On by default.
  void set_share_by_cost(bool on) { share_by_cost_ = on; }
  // Starts so far, and of them those whose assignment was not the contiguous slices.
  int starts() const { return starts_; }
  int reassigned_starts() const { return reassigned_; }
  // Of `work` (per environment, as work_since_start() gives it): the busiest rank's total over the
  // mean rank's under the current assignment (1: balanced; for the bench).
  double imbalance(const std::vector<double>& work) const;
  // Wall seconds rank 0 spent so far waiting for the other ranks' answers after its own share was
  // done, in start() and in step(): its idle time at the decisions' meeting points (for the bench).
  double start_wait_seconds() const { return start_wait_s_; }
  double step_wait_seconds() const { return step_wait_s_; }
  // Designs' meshes sent so far to ranks that got a design they had not built (so they built its
  // model from the mesh instead of meshing it), and meshes the ranks sent rank 0 (the ones they made).
  int meshes_sent() const { return meshes_sent_; }
  // Wall seconds of whole rollouts rank 0 stepped on more threads than its own, lent by ranks of
  // its machine that were done (lent_threads.hpp); and the same summed over every rank (one
  // exchange with each).
  double lent_seconds() const { return lent_s_; }
  double lent_seconds_of_all_ranks() const;
  int meshes_received() const { return meshes_received_; }

 private:
  std::array<double, 4> remote_seconds() const;  // settle, step, build CPU seconds, lent wall seconds: ranks 1..
  void learn_costs(const std::vector<double>& work);  // the iteration just ended's work_since_start(), into design_cost_
  void send_meshes_to(int r);       // mesh_sends_[r], after r's setups
  // Rank r's share of `placed` (the places order_ holds), the batch's width and gamma, and its meshes.
  void send_share(int r, int command, int flag, const std::vector<core::EpisodeSetup>& placed, double gamma);
  void receive_meshes_from(int r);  // after r's answer: the meshes r made, built here too
  // The assignment of a start (learn_costs, assign_by_cost into order_): the setups in place order.
  // `work`: the last iteration's work_since_start() if already read (else read here).
  std::vector<core::EpisodeSetup> assign(const std::vector<core::EpisodeSetup>& setups,
                                         const std::vector<double>* work = nullptr);

  std::unique_ptr<core::ThreadEnvPool> local_;
  std::unique_ptr<rl::ThreadPool> update_pool_;  // null when local_ has two threads or more
  std::size_t n_envs_;
  int ranks_;
  std::vector<EnvSlice> slices_;
  rl::VecStepResult result_;
  std::vector<int> last_in_band_;
  // Place j of the slices steps environment order_[j] (identity until the first start()).
  std::vector<std::size_t> order_;
  std::vector<std::size_t> pinned_;      // environments with a step observer (on rank 0, own place)
  std::vector<double> design_cost_;      // per design, CPU seconds in its last iteration (NaN: unknown)
  BuildCosts build_;                     // the last start's designs, what each rank holds (record_held) and builds
  rl::VecStepResult placed_;             // a step's results in place order, before they are put back
  std::vector<int> placed_in_band_;
  Eigen::MatrixXd placed_actions_;
  bool share_by_cost_ = true;
  bool run_ahead_ = true;
  std::vector<std::vector<int>> mesh_sends_;  // per rank: the designs whose meshes go with its next setups
  Lending lending_;
  // The setups of the last prestart() (the caller's order) and their placed order, until the
  // rollout that uses them (the ranks sent theirs: prestarts()).
  std::vector<core::EpisodeSetup> prestart_setups_, prestart_placed_;
  // While a prestart waits for its rollout: the last rollout's work and assignment (what
  // work_since_start() and imbalance() report then).
  std::vector<double> work_before_prestart_;
  std::vector<std::size_t> order_before_prestart_;
  int prestarted_rollouts_ = 0;
  int starts_ = 0, reassigned_ = 0, rollouts_ = 0, meshes_sent_ = 0, meshes_received_ = 0;
  double start_wait_s_ = 0.0, step_wait_s_ = 0.0, rollout_wait_s_ = 0.0, lent_s_ = 0.0;
  rl::ActorCritic::InferenceCache cache_;  // rank 0's forward passes in rollout()
};

// On rank 0, while ranks 1..ranks-1 are in serve_env_pool: the mean wall time of one exchange of a
// step's shape with one rank — rank 0 sends `out_doubles` numbers, the rank answers `in_doubles`
// (and, as after a step, a short second message) — over `repeats` rounds through every rank in
// turn. For the scaling model (apps/bench/scaling_model.hpp); the ranks keep serving afterwards.
double time_exchanges(int ranks, std::size_t out_doubles, std::size_t in_doubles, int repeats);

// Ranks 1..: answers rank 0's calls with `local` (the environments of env_slice(n_envs, rank,
// ranks)) until rank 0's pool is destroyed. `model`: a feed-forward model of the run's shape, whose
// parameters each rollout() overwrites (null: the run has none, and a rollout() is refused).
// Throws std::runtime_error if a message fails, has another length than the slice needs, or asks
// a whole rollout without a model; std::invalid_argument from the message readers
// (rollout_messages.hpp) if a setup's fields or the policy's size do not fit, which rank 0
// running the same config cannot send.
// `lending`: as MpiEnvPool's, for this rank.
void serve_env_pool(core::ThreadEnvPool& local, rl::ActorCritic* model = nullptr, const Lending& lending = {});

}  // namespace codesign::cluster
