// `codesign bench cluster [--config configs/paper.toml] [--iterations N] [--warmup K]
//                         [--threads T] [--model-threads T] [--exchanges N] [--contiguous]
//                         [--lockstep] [--from-run RUN]`
// alone, or under `mpirun -np N` (docs/cluster.md).
//
// Rank 0 runs K warm-up iterations of Algorithm 1 (they mesh the designs first sampled and build
// their simulators, a cost a long run pays once) and N timed ones with the run's rollout backend
// (threads alone, or the MPI ranks of this launch), and prints the measured wall time per
// iteration split into collection, PPO update, policy inference and distribution update; the
// collection CPU of one environment per iteration (settles and FEM steps) and the collection wall
// of one environment per round of the busiest rank's threads (the model's c, which also holds
// resets, observations, thread hand-offs and imbalance); the CPU of simulator builds and meshing
// (every rank); the machine's busy, idle and stolen core-seconds over the timed iterations from
// /proc/stat (every process: run it on otherwise idle cores); with ≥ 2 ranks, the cost of one exchange
// of a step's shape between rank 0 and one rank (mean of --exchanges rounds). Then the scaling
// model (bench/scaling_model.hpp) with these costs: seconds per iteration and the projected run
// time for 1 … ψ ranks of --model-threads threads, with the update on rank 0 (as built) and
// spread over the ranks (a bound: not built, messages free), beside the measured figure of this
// launch, and the goal (the paper run in ≤ 5 min on 16 ranks); then the spread update
// with its gradients' messages, per minibatch with a gradient (counted over the timed iterations)
// 2 (N − 1)/N times one gradient's transfer: as measured between this launch's ranks (under
// mpirun), and over links of 10, 25 and 100 Gb/s (the gradient's bytes over the link's rate); its
// compute is the busiest rank's share of each minibatch, timed on synthetic data against the whole
// minibatch (a narrow share runs the products below their full speed). Without MPI the exchange
// cost is not measured and the model's message term is 0 (said so). A launch with more threads
// than cores on rank 0's machine (ranks there × --threads) is measured as any other, and the
// bench says that its c is a share of a core, which the model cannot use. With --from-run, a
// finished one-process run of this launch's threads is projected too, iteration by iteration from
// its ppo.csv, with the busiest rank's factors measured here (experiments/cluster_projection.sh's
// arithmetic, cluster::projected_run_seconds).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <unistd.h>

#include "base/peak_memory.hpp"
#include "bench/cost_spread.hpp"
#include "bench/scaling_model.hpp"
#include "cli_options.hpp"
#include "cluster/mpi_env_pool.hpp"
#include "cluster/mpi_world.hpp"
#include "cluster/rollout_messages.hpp"
#include "core/outer_loop.hpp"
#include "commands.hpp"
#include "minibatch_timing.hpp"
#include "rl/recurrent_ppo.hpp"
#include "base/errors.hpp"
#include "io/formats/csv_table.hpp"
#include "run/rollout_backend.hpp"
#include "run/run_folder.hpp"
#include "run/run_config.hpp"

namespace codesign::app {

namespace {

// A minibatch of `width` samples of standard normal values for a policy of these sizes.
rl::PpoMinibatchT<float> synthetic_minibatch(Eigen::Index obs_rows, Eigen::Index act_rows, Eigen::Index width,
                                             std::uint64_t seed) {
  rl::Rng rng(seed);
  auto normals = [&](Eigen::Index rows) {
    Eigen::MatrixXf x(rows, width);
    for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = static_cast<float>(rng.normal());
    return x;
  };
  rl::PpoMinibatchT<float> mb;
  mb.obs = normals(obs_rows);
  mb.actions = normals(act_rows);
  mb.old_log_prob = normals(1);
  mb.advantages = normals(1);
  mb.returns = normals(1);
  return mb;
}

// Median seconds of one minibatch's loss and gradient on `width` samples of synthetic data (the
// cost does not depend on the values), on one thread, with the run's feed-forward model: its sizes
// and matrix-product precision. After one untimed pass.
double minibatch_gradient_seconds(const rl::ActorCritic& model, Eigen::Index width, int reps) {
  const rl::PpoMinibatchT<float> mb = synthetic_minibatch(model.critic_input_dim(), model.act_dim(), width, 20261206);
  return minibatch_loss_seconds<float>(model, mb, {0.2, 0.01, 0.5, true}, 1, reps);
}

// The same for the recurrent model (rl/recurrent_ppo.hpp): a minibatch of `sequences` whole
// sequences of `steps` decisions, each one episode from a zero state as the co-design's columns
// are, synthetic values, on one thread. After one untimed pass.
double recurrent_minibatch_gradient_seconds(const rl::RecurrentActorCritic& model, int sequences, int steps,
                                            int reps) {
  const Eigen::Index cols = Eigen::Index{sequences} * steps;
  rl::RecurrentMinibatchT<float> mb;
  mb.samples = synthetic_minibatch(model.critic_input_dim(), model.act_dim(), cols, 20261207);
  mb.starts = Eigen::RowVectorXf::Zero(cols);
  mb.starts.head(sequences).setOnes();  // column t·B + b: step 0 of every sequence starts an episode
  mb.h0_actor = Eigen::MatrixXf::Zero(model.actor_gru().hidden_dim(), sequences);
  mb.h0_critic = Eigen::MatrixXf::Zero(model.critic_gru().hidden_dim(), sequences);
  mb.steps = steps;
  rl::RecurrentWorkspaceT<float> ws;
  auto grad = model.zero_grad();
  const rl::PpoLossCoefficients coefs{0.2, 0.01, 0.5, true};
  return median_seconds([&] { rl::recurrent_minibatch_loss<float>(model, mb, coefs, &grad, ws); }, 1, reps);
}

// The machine's CPU time so far from the first line of /proc/stat, in core-seconds: busy (user,
// nice, system, irq, softirq), idle (idle, iowait) and stolen by the hypervisor. All zero where
// the file cannot be read.
struct MachineTimes {
  double busy = 0.0, idle = 0.0, stolen = 0.0;
};
MachineTimes machine_times() {
  MachineTimes t;
  std::ifstream in("/proc/stat");
  std::string cpu;
  double f[8] = {0, 0, 0, 0, 0, 0, 0, 0};  // user nice system idle iowait irq softirq steal
  if (!(in >> cpu) || cpu != "cpu") return t;
  for (double& x : f)
    if (!(in >> x)) return t;
  const double hz = static_cast<double>(sysconf(_SC_CLK_TCK));
  t.busy = (f[0] + f[1] + f[2] + f[5] + f[6]) / hz;
  t.idle = (f[3] + f[4]) / hz;
  t.stolen = f[7] / hz;
  return t;
}

// The rollout pool of a one-process launch, forwarding every call to the pool it owns, that reads
// after start() and after each step() every environment's settle and step CPU since the start
// (work_since_start: in one process a read of counters, nothing exchanged): the per-decision costs
// cluster::meeting_load_factor simulates the ranks' meetings from.
class DecisionCostRecorder final : public core::EnvPool {
 public:
  explicit DecisionCostRecorder(std::unique_ptr<core::EnvPool> inner) : inner_(std::move(inner)) {}
  std::size_t size() const override { return inner_->size(); }
  const rl::EnvSpec& spec() const override { return inner_->spec(); }
  Eigen::MatrixXd start(const std::vector<core::EpisodeSetup>& setups) override {
    Eigen::MatrixXd obs = inner_->start(setups);
    const std::vector<double> w = inner_->work_since_start();
    profiles_.assign(w.size(), {});
    for (std::size_t i = 0; i < w.size(); ++i) profiles_[i].push_back(w[i]);
    last_ = w;
    return obs;
  }
  const rl::VecStepResult& step(const Eigen::MatrixXd& actions, bool restart) override {
    const rl::VecStepResult& r = inner_->step(actions, restart);
    const std::vector<double> w = inner_->work_since_start();
    for (std::size_t i = 0; i < w.size() && i < profiles_.size(); ++i) {
      profiles_[i].push_back(w[i] - last_[i]);
      last_[i] = w[i];
    }
    return r;
  }
  int last_in_band(std::size_t i) const override { return inner_->last_in_band(i); }
  double settle_seconds() const override { return inner_->settle_seconds(); }
  double step_seconds() const override { return inner_->step_seconds(); }
  double build_seconds() const override { return inner_->build_seconds(); }
  void set_step_observer(std::size_t i, StepObserver observer, int every) override {
    inner_->set_step_observer(i, std::move(observer), every);
  }
  std::vector<double> work_since_start() const override { return inner_->work_since_start(); }
  rl::ThreadPool* thread_pool() override { return inner_->thread_pool(); }
  // Per environment, its costs at the last rollout's start and decisions.
  const std::vector<std::vector<double>>& profiles() const { return profiles_; }

 private:
  std::unique_ptr<core::EnvPool> inner_;
  std::vector<std::vector<double>> profiles_;
  std::vector<double> last_;
};

struct BenchClusterOptions {
  std::string config = "configs/paper.toml";
  int iterations = 3;
  int warmup = 3;
  int threads = 0;
  int model_threads = 0;
  int exchanges = 200;
  bool contiguous = false;
  bool lockstep = false;
  int spread_draws = 4000;
  std::string from_run;  // a finished one-process run of this launch's threads, projected with the factors
};

// Per iteration, the collection, policy and update seconds of RUN/ppo.csv (InputError naming the
// file and the column if it is missing or malformed).
std::vector<cluster::RunIteration> read_run_iterations(const std::string& dir) {
  const io::CsvTable t = io::read_csv((std::filesystem::path(dir) / run::run_file::kPpo).string());
  const std::size_t collect = t.column("collect_s"), policy = t.column("policy_s"), update = t.column("update_s");
  std::vector<cluster::RunIteration> run;
  for (std::size_t r = 0; r < t.rows(); ++r) run.push_back({t.number(r, collect), t.number(r, policy), t.number(r, update)});
  if (run.empty()) throw InputError(t.path() + ": no PPO update (a run's ppo.csv has one row per iteration)");
  return run;
}

// The cost of the ranks' meeting at every decision (cluster::meeting_load_factor), from this
// one-process launch's per-decision costs. The model's c was measured with this launch's own
// meetings (one rank of `launch_threads` threads), so a projection scales it by L_N / L_1.
// `whole_run`: a finished one-process run of launch_threads threads (--from-run), projected too.
void print_meetings(const std::vector<cluster::DecisionCosts>& samples, const cluster::ScalingCosts& c,
                    double iterations_total, int launch_threads, bool whole_rollouts, const BenchClusterOptions& o,
                    const std::vector<cluster::RunIteration>& whole_run) {
  const std::size_t psi = c.environments;
  const std::uint64_t seed = 20261205;
  double mean_total = 0.0;  // an environment's iteration, the samples' mean (meeting_load_factor's unit)
  for (const cluster::DecisionCosts& d : samples)
    for (double x : d.seconds) mean_total += x / static_cast<double>(samples.size());
  const cluster::MeetingLoad own = cluster::meeting_load_factor(samples, psi, 1, launch_threads, o.spread_draws, seed);
  const double update_in_samples = c.env_collect_s > 0.0 ? c.update_s * mean_total * own.lockstep / c.env_collect_s : 0.0;
  std::printf("bench cluster: the meeting at every decision (apps/bench/cost_spread.hpp), from %zu environment "
              "iterations of %zu decision costs each (every iteration above): L = the collection over the model's "
              "rounds x mean cost, mean of %d simulated iterations split by cost; this launch (1 rank x %d "
              "thread(s)): L_1 = %.3f\n",
              samples.size(), samples.front().seconds.size(), o.spread_draws, launch_threads, own.lockstep);
  if (launch_threads > 1 && static_cast<std::size_t>(launch_threads) <= psi) {
    const cluster::MeetingLoad split =
        cluster::meeting_load_factor(samples, psi, launch_threads, 1, o.spread_draws, seed);
    const double rounds_one = static_cast<double>(cluster::collection_rounds(psi, 1, launch_threads));
    const double rounds_split = static_cast<double>(cluster::collection_rounds(psi, launch_threads, 1));
    std::printf("  the same %d cores as %d ranks x 1 thread: collection x %.3f of this launch's meeting at every "
                "decision (L = %.3f), x %.3f if the ranks met only at the iteration's end (L = %.3f)\n",
                launch_threads, launch_threads, split.lockstep * rounds_split / (own.lockstep * rounds_one),
                split.lockstep, split.run_ahead * rounds_split / (own.lockstep * rounds_one), split.run_ahead);
  }
  // Which meeting a run of this config has under mpirun (MpiEnvPool::rollout, core/run_ahead.hpp).
  std::printf("  under mpirun this config's rollouts %s\n",
              whole_rollouts ? "run whole on each rank: the ranks meet at the iteration's end (the 'iteration's end' "
                               "columns)"
                             : "go step by step (a recurrent policy or observation statistics): the ranks meet at every "
                               "decision (the 'every decision' columns)");
  std::printf("  ranks | L meeting every decision | of it the start's meeting (settles) | L meeting at the "
              "iteration's end | floor of any order of a rank's jobs | run, update on rank 0: every decision, "
              "iteration's end (c x L / L_1)\n");
  for (int r : {1, 2, 4, 8, 16, 32, 64}) {
    if (static_cast<std::size_t>(r) > psi) break;
    // With this launch's update in the samples' seconds (u · mean · L_1 / c) for after_update; the
    // other factors do not depend on it.
    const cluster::MeetingLoad m = cluster::meeting_load_factor(samples, psi, r, c.threads_per_rank, o.spread_draws,
                                                                seed, update_in_samples);
    cluster::ScalingCosts every = c, end = c;
    every.collect_factor = m.lockstep / own.lockstep;
    end.collect_factor = m.run_ahead / own.lockstep;
    std::printf("  %5d | %24.3f | %35.3f | %32.3f | %34.3f | %8.1f min, %8.1f min\n", r, m.lockstep, m.start,
                m.run_ahead, m.floor,
                iterations_total * cluster::iteration_seconds(every, r) / 60.0,
                iterations_total * cluster::iteration_seconds(end, r) / 60.0);
    // The ranks' starts run while rank 0 updates (MpiEnvPool::prestart, as built for whole
    // rollouts; simulated for every rank but 0, as on ranks of other machines or of t >= 2 threads):
    // the collection from the update's end, a rank's start beyond the update counted on that rank;
    // and the bound that cluster_projection.sh takes per iteration of a run: the starts hidden (F)
    // plus what the slowest rank's starts (P) outlast the update.
    cluster::ScalingCosts pre = end, bound = end;
    pre.collect_factor = m.after_update / own.lockstep;
    bound.collect_factor = m.prestarted / own.lockstep;
    bound.prestart_s = m.prestart / own.lockstep *
                       static_cast<double>(cluster::collection_rounds(psi, r, c.threads_per_rank)) * c.env_collect_s;
    const double run_pre = iterations_total * cluster::iteration_seconds(pre, r) / 60.0;
    if (r > 1)
      std::printf("        | the ranks' starts during rank 0's update (%.3f s): L = %.3f after it, run %.1f min; bound: the "
                  "slowest rank's starts %.3f s, F = %.3f, P = %.3f (experiments/cluster_projection.sh), run %.1f min\n",
                  c.update_s, m.after_update, run_pre, bound.prestart_s, m.prestarted / own.lockstep,
                  m.prestart / own.lockstep, iterations_total * cluster::iteration_seconds(bound, r) / 60.0);
    // The same factors applied to every iteration of a whole run (experiments/cluster_projection.sh).
    double whole_pre = 0.0;
    if (!whole_run.empty() && r > 1) {
      const double whole_end = cluster::projected_run_seconds(whole_run, psi, launch_threads, r, c.threads_per_rank,
                                                              m.run_ahead / own.lockstep, 0.0) / 60.0;
      whole_pre = cluster::projected_run_seconds(whole_run, psi, launch_threads, r, c.threads_per_rank,
                                                 m.prestarted / own.lockstep, m.prestart / own.lockstep) / 60.0;
      std::printf("        | fed with the whole run (%zu iterations, --from-run): meeting at the iteration's end %.2f min; "
                  "the starts during rank 0's update %.2f min (bound)\n",
                  whole_run.size(), whole_end, whole_pre);
    }
    if (r == 16) {
      if (!whole_run.empty() && whole_rollouts)
        std::printf("  goal (docs/journal/cluster.md), the model fed with the whole run: the run in <= 5 min on 16 ranks x %d "
                    "thread(s): %.2f min (whole rollouts started during rank 0's update, bound): %s\n",
                    c.threads_per_rank, whole_pre, whole_pre <= 5.0 ? "met" : "NOT met");
      const double run16 = whole_rollouts ? run_pre : iterations_total * cluster::iteration_seconds(every, r) / 60.0;
      cluster::ScalingCosts at_floor = c;
      at_floor.collect_factor = m.floor / own.lockstep;
      std::printf("  goal (docs/journal/cluster.md), the meeting counted, this launch's iterations: the run in <= 5 min on 16 ranks x "
                  "%d thread(s): %.1f min (%s): %s; with the starts in the collection %.1f min, with the floor of any "
                  "order of a rank's jobs %.1f min\n",
                  c.threads_per_rank, run16,
                  whole_rollouts ? "whole rollouts on the ranks, started during rank 0's update" : "step by step",
                  run16 <= 5.0 ? "met" : "NOT met", iterations_total * cluster::iteration_seconds(end, r) / 60.0,
                  iterations_total * cluster::iteration_seconds(at_floor, r) / 60.0);
    }
  }
  // Not built: the threads of each rank running their environments' whole rollouts too, so nothing
  // meets before the iteration's end. 16 ranks of t threads then hold the slots of 16·t ranks of one
  // thread (ψ = 40, t = 2: 8 slots of 2 environments, 24 of 1) with the same rounds, split over the
  // slots by cost at once rather than over the ranks and then their threads.
  const int t = c.threads_per_rank;
  if (t > 1 && static_cast<std::size_t>(16 * t) <= psi) {
    const cluster::MeetingLoad m = cluster::meeting_load_factor(samples, psi, 16 * t, 1, o.spread_draws, seed);
    cluster::ScalingCosts end = c;
    end.collect_factor = m.run_ahead / own.lockstep;
    std::printf("  16 ranks x %d threads, each thread running its environments' whole rollout (not built; simulated as "
                "%d ranks x 1 thread): L = %.3f at the iteration's end, run %.1f min\n",
                t, 16 * t, m.run_ahead, iterations_total * cluster::iteration_seconds(end, 16) / 60.0);
  }
}

// This launch's rollout pool: under mpirun the MPI pool (shared out by cost unless --contiguous,
// whole rollouts on the ranks unless --lockstep); in one process the threads' pool inside a
// recorder of each decision's costs, for the meetings.
struct RolloutPool {
  std::unique_ptr<core::EnvPool> owned;
  cluster::MpiEnvPool* mpi = nullptr;
  DecisionCostRecorder* recorder = nullptr;
};

RolloutPool make_bench_pool(std::shared_ptr<core::SimulatorPool> sims, const core::LoopConfig& lc,
                            const BenchClusterOptions& options, int ranks, const std::vector<int>& here) {
  RolloutPool made;
  made.owned = run::make_rollout_pool(std::move(sims), lc, static_cast<std::size_t>(options.threads), ranks, here);
  made.mpi = dynamic_cast<cluster::MpiEnvPool*>(made.owned.get());
  if (made.mpi) {
    made.mpi->set_share_by_cost(!options.contiguous);
    made.mpi->set_run_ahead(!options.lockstep);
  } else {
    auto recorder = std::make_unique<DecisionCostRecorder>(std::move(made.owned));
    made.recorder = recorder.get();
    made.owned = std::move(recorder);
  }
  return made;
}

// This launch as the bench measures it: the options, the loop and its config, the pool the loop
// steps, the simulators, and the launch's sizes.
struct Launch {
  const BenchClusterOptions& options;
  const core::LoopConfig& lc;
  core::OuterLoop& loop;
  core::SimulatorPool& sims;
  core::EnvPool& pool;
  cluster::MpiEnvPool* mpi_pool;        // under mpirun, else null
  DecisionCostRecorder* recorder;       // in one process, else null
  int ranks;
  std::size_t threads;                  // rollout threads per rank
  int psi, n_steps;
  int ranks_here;                       // the ranks on rank 0's machine
  bool oversubscribed;                  // more threads than cores on rank 0's machine
};

// The model reads c as the collection of a thread with a core of its own; with more threads
// than cores on rank 0's machine the ranks share cores, and c is a share of one.
bool cores_shared(int ranks_here, std::size_t threads) {
  const unsigned cores = std::thread::hardware_concurrency();
  return cores > 0 && static_cast<std::size_t>(ranks_here) * threads > cores;
}

void print_launch(const Launch& launch) {
  std::printf("bench cluster: %s: psi = %d environments x %d decisions; %d rank(s) x %zu thread(s)\n",
              launch.options.config.c_str(), launch.psi, launch.n_steps, launch.ranks, launch.threads);
  if (launch.oversubscribed)
    std::printf("  this launch runs %d rank(s) x %zu thread(s) on the %u cores of rank 0's machine: the ranks share "
                "cores, so the model's c below is not one core's collection and its projection is not meaningful; "
                "feed the model from a launch with ranks x threads <= cores\n",
                launch.ranks_here, launch.threads, std::thread::hardware_concurrency());
}

// Each environment's settle and step CPU over each iteration, with its design: for the designs'
// cost spread in the model (bench/cost_spread.hpp). Read between iterations, outside the timing.
struct CostLog {
  std::vector<cluster::CostSample> costs;
  std::vector<cluster::DecisionCosts> decision_costs;  // the same, decision by decision (one process)
};

// Adds the iteration's costs to `log` and returns its per-environment costs (under MPI: one
// exchange with every rank).
std::vector<double> keep_costs(const Launch& launch, const core::IterationReport& report, CostLog& log) {
  const std::vector<double> work = launch.pool.work_since_start();
  for (std::size_t i = 0; i < work.size() && i < report.samples.size(); ++i)
    log.costs.push_back({report.samples[i].design, work[i]});
  if (launch.recorder)
    for (std::size_t i = 0; i < launch.recorder->profiles().size() && i < report.samples.size(); ++i)
      log.decision_costs.push_back({report.samples[i].design, launch.recorder->profiles()[i]});
  return work;
}

// What this launch's messages cost (zero in one process).
struct MessageCosts {
  bool ran_ahead = false;  // whole rollouts on the ranks
  double exchange = 0.0;   // one exchange with one rank, of a step's or a whole rollout's shape
  std::size_t gradient_floats = 0;
  double gradient_transfer = 0.0;  // one gradient moved one way between rank 0 and a rank
};

MessageCosts time_messages(const Launch& launch) {
  MessageCosts messages;
  // One exchange of a step's shape with one rank: the actions of the largest slice of a 2-rank
  // split out, its step results back (rewards, flags, observations, terminal observations).
  // With whole rollouts on the ranks (the warm-up ran some: MpiEnvPool::rollouts), one exchange
  // per iteration of that shape instead: the policy's parameters and the rollout's normal draws
  // out (broadcast in a run; sent to each rank in turn here, so no cheaper), the slice's record back.
  const int psi = launch.psi, n_steps = launch.n_steps, ranks = launch.ranks, rounds = launch.options.exchanges;
  messages.ran_ahead = launch.mpi_pool && launch.mpi_pool->rollouts() > 0;
  if (ranks > 1) {
    const std::size_t slice = cluster::env_slice(static_cast<std::size_t>(psi), 0, 2).count;
    const std::size_t obs = launch.pool.spec().observation.dim(), act = launch.pool.spec().action.dim();
    const auto steps = static_cast<std::size_t>(n_steps);
    messages.exchange = messages.ran_ahead
                            ? cluster::time_exchanges(ranks,
                                                      cluster::policy_size(launch.loop.model()) / 2 +
                                                          steps * act * static_cast<std::size_t>(psi),
                                                      cluster::share_floats(n_steps, slice, obs, act) / 2 +
                                                          cluster::share_doubles(n_steps, slice),
                                                      rounds)
                            : cluster::time_exchanges(ranks, slice * act, slice * (5 + 2 * obs), rounds);
  }

  // A data-parallel update's messages (scaling_model.hpp): one gradient (the parameters' size)
  // moved one way between rank 0 and a rank, answered by a short reply.
  messages.gradient_floats = static_cast<std::size_t>(launch.loop.recurrent_model()
                                                          ? launch.loop.recurrent_model()->num_params()
                                                          : launch.loop.model().num_params());
  messages.gradient_transfer =
      ranks > 1 ? cluster::time_exchanges(ranks, (messages.gradient_floats + 1) / 2, 1, std::min(rounds, 50)) : 0.0;
  return messages;
}

// The pool's and the simulators' counters before the timed iterations.
struct CountersAtStart {
  int built = 0;
  double settle = 0.0, step = 0.0, build = 0.0;
  int starts = 0, moved = 0;
  double start_wait = 0.0, step_wait = 0.0, rollout_wait = 0.0;
  int rollouts = 0;
  double lent = 0.0, lent_all = 0.0;
  int received = 0, sent = 0;
};

CountersAtStart read_counters(const Launch& launch, int built) {
  CountersAtStart at;
  at.built = built;
  at.settle = launch.pool.settle_seconds();
  at.step = launch.pool.step_seconds();
  at.build = launch.pool.build_seconds();
  if (const cluster::MpiEnvPool* mpi = launch.mpi_pool) {
    at.starts = mpi->starts();
    at.moved = mpi->reassigned_starts();
    at.start_wait = mpi->start_wait_seconds();
    at.step_wait = mpi->step_wait_seconds();
    at.rollout_wait = mpi->rollout_wait_seconds();
    at.rollouts = mpi->rollouts();
    at.lent = mpi->lent_seconds();
    at.lent_all = mpi->lent_seconds_of_all_ranks();
    at.received = mpi->meshes_received();
    at.sent = mpi->meshes_sent();
  }
  return at;
}

// Sums over the timed iterations, their wall time less the cost recording between them, and the
// machine's CPU times before and after.
struct TimedIterations {
  double collect = 0.0, update = 0.0, dist = 0.0, policy = 0.0, imbalance = 0.0, wall = 0.0;
  double minibatches = 0.0;  // with a gradient: those applied, and the one that stopped the update early
  std::size_t restarts = 0;  // episodes that ended before the rollout's last step and so restarted
  MachineTimes machine_before, machine_after;
};

std::size_t restarted_episodes(const core::IterationReport& report, int psi, int n_steps) {
  std::size_t restarts = 0;
  std::vector<int> taken(static_cast<std::size_t>(psi), 0);  // decisions of each environment so far
  for (const core::EpisodeRecord& episode : report.episodes) {
    const auto env = static_cast<std::size_t>(episode.env);
    taken[env] += episode.decisions;
    if (episode.reason != "rollout_end" && taken[env] < n_steps) ++restarts;
  }
  return restarts;
}

TimedIterations run_timed_iterations(const Launch& launch, CostLog& log) {
  TimedIterations timed;
  double recording_s = 0.0;
  timed.machine_before = machine_times();
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < launch.options.iterations; ++k) {
    const core::IterationReport report = launch.loop.iterate();
    timed.collect += report.collect_s;
    timed.update += report.update_s;
    timed.dist += report.distribution_s;
    timed.policy += report.policy_s;
    timed.minibatches += report.ppo.minibatches_applied + (report.ppo.early_stopped ? 1 : 0);
    timed.restarts += restarted_episodes(report, launch.psi, launch.n_steps);
    // Not part of a run (under MPI an exchange with every rank): left out of the wall time.
    const auto q0 = std::chrono::steady_clock::now();
    const std::vector<double> work = keep_costs(launch, report, log);
    if (launch.mpi_pool) timed.imbalance += launch.mpi_pool->imbalance(work);
    recording_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - q0).count();
  }
  timed.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() - recording_s;
  timed.machine_after = machine_times();
  return timed;
}

// The collection of one environment per iteration: CPU in settles and FEM steps, and the wall of
// one round of the busiest rank's threads (the model's c): this launch's collection less its
// policy inference and its messages (`exchanges` per iteration with each rank), over its rounds.
struct EnvCollection {
  double cpu = 0.0, wall = 0.0;
  int exchanges = 0;
};

EnvCollection env_collection(const Launch& launch, const CountersAtStart& start, const TimedIterations& timed,
                             const MessageCosts& messages) {
  const int psi = launch.psi;
  const double n = launch.options.iterations;
  EnvCollection env;
  env.cpu = (launch.pool.settle_seconds() - start.settle + launch.pool.step_seconds() - start.step) /
            launch.options.iterations / psi;
  env.exchanges = messages.ran_ahead ? 1 : launch.n_steps + 1;
  const double message_s = (launch.ranks - 1) * env.exchanges * messages.exchange;
  env.wall = std::max(0.0, timed.collect / n - timed.policy / n - message_s) /
             static_cast<double>(cluster::collection_rounds(static_cast<std::size_t>(psi), launch.ranks,
                                                            static_cast<int>(launch.threads)));
  return env;
}

// Rank 0's wall per iteration and its parts, the collection per environment, the simulators built
// and the settles and restarts.
void print_measured(const Launch& launch, const CountersAtStart& start, const TimedIterations& timed,
                    const EnvCollection& env) {
  const cluster::MpiEnvPool* mpi_pool = launch.mpi_pool;
  const double n = launch.options.iterations;
  std::printf("bench cluster: measured on %d rank(s): %.3f s per iteration: collection %.3f s (policy inference "
              "%.3f s of it), PPO update %.3f s, distribution %.4f s; rank 0's peak resident memory %.0f MiB\n",
              launch.ranks, timed.wall / n, timed.collect / n, timed.policy / n, timed.update / n, timed.dist / n,
              peak_resident_mib());
  std::printf("  collection of one environment per iteration: %.4f s CPU in settles and FEM steps, %.4f s wall per "
              "round of a rank's threads (the model's c)\n",
              env.cpu, env.wall);
  std::printf("  simulators built during the timed iterations on rank 0: %d (after %d warm-up iteration(s)); CPU "
              "in building simulators and meshing designs, every rank: %.3f s per iteration\n",
              launch.sims.constructed() - start.built, launch.options.warmup,
              (launch.pool.build_seconds() - start.build) / n);
  if (mpi_pool)
    std::printf("  designs' meshes during the timed iterations: %d made on the other ranks and sent to rank 0, %d sent "
                "to a rank that had not built the design (built there from the mesh: %.4f s CPU each on rank 0, "
                "against %.4f s to mesh one)\n",
                mpi_pool->meshes_received() - start.received, mpi_pool->meshes_sent() - start.sent,
                launch.sims.build_stats().seconds_per_adopted(), launch.sims.build_stats().seconds_per_model());
  std::printf("  of it in settles (each start's and each restart's): %.4f s CPU; episodes restarted within a rollout: "
              "%.1f per iteration\n",
              (launch.pool.settle_seconds() - start.settle) / launch.options.iterations / launch.psi,
              static_cast<double>(timed.restarts) / n);
}

// Under mpirun: how the environments were shared out, how long rank 0 waited for the other ranks,
// and the whole rollouts and lent threads.
void print_mpi_sharing(const cluster::MpiEnvPool& mpi_pool, const BenchClusterOptions& options,
                       const CountersAtStart& start, const TimedIterations& timed) {
  const int iterations = options.iterations;
  std::printf("  environments shared out by cost at %d of %d timed starts; the busiest rank's settle and step CPU "
              "over the mean rank's: %.3f (mean over the timed iterations; 1 = balanced)\n",
              mpi_pool.reassigned_starts() - start.moved, mpi_pool.starts() - start.starts,
              timed.imbalance / iterations);
  std::printf("  rank 0 idle at the meeting points, waiting for the other ranks after its own share: %.3f s per "
              "iteration (%.3f s at the start, %.3f s over the steps)\n",
              (mpi_pool.start_wait_seconds() - start.start_wait + mpi_pool.step_wait_seconds() - start.step_wait) /
                  iterations,
              (mpi_pool.start_wait_seconds() - start.start_wait) / iterations,
              (mpi_pool.step_wait_seconds() - start.step_wait) / iterations);
  std::printf("  whole rollouts on the ranks (meeting once per iteration): %d of %d timed iterations%s; rank 0 idle "
              "waiting for the other ranks' records after its own share: %.3f s per iteration; rank 0 "
              "stepped on threads lent by ranks of its machine that were done: %.3f s per iteration (every rank: "
              "%.3f s)\n",
              mpi_pool.rollouts() - start.rollouts, iterations, options.lockstep ? " (--lockstep)" : "",
              (mpi_pool.rollout_wait_seconds() - start.rollout_wait) / iterations,
              (mpi_pool.lent_seconds() - start.lent) / iterations,
              (mpi_pool.lent_seconds_of_all_ranks() - start.lent_all) / iterations);
}

// The machine's core-seconds over the timed iterations, and the exchange's cost.
void print_machine_and_exchange(const Launch& launch, const TimedIterations& timed, const EnvCollection& env,
                                const MessageCosts& messages) {
  const double n = launch.options.iterations;
  const MachineTimes& before = timed.machine_before;
  const MachineTimes& after = timed.machine_after;
  if (after.busy + after.idle > 0.0)
    std::printf("  the machine over the timed iterations (/proc/stat, every process): %.3f core-s busy, %.3f idle, %.3f "
                "stolen by the hypervisor per iteration; busy beyond the settles and FEM steps: %.3f core-s\n",
                (after.busy - before.busy) / n, (after.idle - before.idle) / n, (after.stolen - before.stolen) / n,
                (after.busy - before.busy) / n - env.cpu * launch.psi);
  if (launch.ranks > 1)
    std::printf("  one exchange rank 0 <-> one rank (%s, mean of %d rounds over %d ranks): %.1f us\n",
                messages.ran_ahead ? "a whole rollout's shape" : "a step's shape", launch.options.exchanges,
                launch.ranks - 1, 1e6 * messages.exchange);
  else
    std::printf("  exchange cost not measured (one process; run under mpirun -np 2 for it): the model's message "
                "term is 0\n");
}

// The scaling model's costs as measured by this launch (threads per rank: --model-threads, else
// this launch's).
cluster::ScalingCosts measured_scaling_costs(const Launch& launch, const TimedIterations& timed,
                                             const EnvCollection& env, const MessageCosts& messages) {
  const double n = launch.options.iterations;
  cluster::ScalingCosts scaling;
  scaling.environments = static_cast<std::size_t>(launch.psi);
  scaling.threads_per_rank =
      launch.options.model_threads > 0 ? launch.options.model_threads : static_cast<int>(launch.threads);
  scaling.env_collect_s = env.wall;
  scaling.exchanges = env.exchanges;
  scaling.exchange_s = messages.exchange;
  scaling.update_s = timed.update / n;
  // Policy inference runs on rank 0 while the ranks wait; it is part of the collection's wall.
  scaling.policy_s = timed.policy / n;
  scaling.distribution_s = timed.dist / n;
  return scaling;
}

// The same costs with the update spread over the ranks (not built; a bound).
cluster::ScalingCosts with_update_spread(const cluster::ScalingCosts& scaling) {
  cluster::ScalingCosts spread = scaling;
  spread.update_spread = true;
  return spread;
}

// Seconds per iteration and the run's minutes for 1 .. psi ranks, with the update on rank 0 and
// spread, and the goal of 5 minutes on 16 ranks.
void print_model(const Launch& launch, const cluster::ScalingCosts& scaling, double iterations_total) {
  const int psi = launch.psi;
  std::printf("bench cluster: model (docs/cluster.md): %d thread(s) per rank, %.0f iterations for %lld timesteps\n",
              scaling.threads_per_rank, iterations_total, static_cast<long long>(launch.lc.codesign.total_timesteps));
  std::printf("  ranks | update on rank 0 (built): s per iteration, run, speed-up | update spread (bound): s per "
              "iteration, run\n");
  const cluster::ScalingCosts spread = with_update_spread(scaling);
  const double base = cluster::iteration_seconds(scaling, 1);
  for (int r : {1, 2, 4, 8, 16, 32, 64}) {
    if (r > psi) break;
    const double on_rank0 = cluster::iteration_seconds(scaling, r), spread_s = cluster::iteration_seconds(spread, r);
    std::printf("  %5d | %7.3f s %8.1f min %6.2fx | %7.3f s %8.1f min%s\n", r, on_rank0,
                iterations_total * on_rank0 / 60.0, base / on_rank0, spread_s, iterations_total * spread_s / 60.0,
                r == launch.ranks && scaling.threads_per_rank == static_cast<int>(launch.threads)
                    ? (launch.oversubscribed ? "   (this launch: measured above; cores shared)"
                                             : "   (this launch: measured above)")
                    : "");
  }
  if (psi >= 16) {
    const double m16 = iterations_total * cluster::iteration_seconds(scaling, 16) / 60.0;
    const double s16 = iterations_total * cluster::iteration_seconds(spread, 16) / 60.0;
    std::printf("  goal (docs/journal/cluster.md): the run in <= 5 min on 16 ranks by the model: %.1f min with the update on rank 0: "
                "%s; %.1f min with it spread (not built; messages free, priced below): %s\n",
                m16, m16 <= 5.0 ? "met" : "NOT met", s16, s16 <= 5.0 ? "would be met" : "NOT met either");
  }
}

// e(N): the busiest rank's share of a minibatch, ceil(B/N) samples, against the whole (one
// thread), for the feed-forward policy. Prints the measured figures.
std::map<int, double> feedforward_share_costs(const Launch& launch) {
  std::map<int, double> share_cost;
  const int batch = launch.lc.ppo.batch_size;
  const double whole = minibatch_gradient_seconds(launch.loop.model(), batch, 15);
  std::printf("  one minibatch's loss and gradient on one thread, %d samples: %.2f ms; the busiest rank's share "
              "on N ranks, times N, over it (the model's e):",
              batch, 1e3 * whole);
  for (int r : {2, 4, 8, 16, 32, 64}) {
    if (r > launch.psi || r > batch) break;
    const int share = (batch + r - 1) / r;
    share_cost[r] = minibatch_gradient_seconds(launch.loop.model(), share, 15) * r / whole;
    std::printf(" N = %d (%d samples) %.2f;", r, share, share_cost[r]);
  }
  std::printf("\n");
  return share_cost;
}

// The same for the recurrent policy: ceil(S/N) whole sequences of the minibatch's S (at least
// one: with more ranks than sequences the others have nothing to do, which e prices).
std::map<int, double> recurrent_share_costs(const Launch& launch) {
  std::map<int, double> share_cost;
  const int n_steps = launch.n_steps;
  const int sequences = rl::sequences_per_minibatch(launch.lc.ppo, launch.psi);
  const rl::RecurrentActorCritic& model = *launch.loop.recurrent_model();
  const double whole = recurrent_minibatch_gradient_seconds(model, sequences, n_steps, 15);
  std::printf("  one minibatch's loss and gradient on one thread, %d sequences of %d decisions: %.2f ms; the "
              "busiest rank's share on N ranks, times N, over it (the model's e):",
              sequences, n_steps, 1e3 * whole);
  for (int r : {2, 4, 8, 16, 32, 64}) {
    if (r > launch.psi) break;
    const int share = (sequences + r - 1) / r;
    share_cost[r] = recurrent_minibatch_gradient_seconds(model, share, n_steps, 15) * r / whole;
    std::printf(" N = %d (%d sequence(s)) %.2f;", r, share, share_cost[r]);
  }
  std::printf("\n");
  return share_cost;
}

// The spread update with its gradients' messages at their least (scaling_model.hpp), y from
// this launch's ranks (shared memory on one machine) and from links of given speeds.
void print_spread_update(const Launch& launch, const cluster::ScalingCosts& scaling, double iterations_total,
                         const TimedIterations& timed, const MessageCosts& messages) {
  cluster::ScalingCosts priced = with_update_spread(scaling);  // e and y are set per row below
  priced.update_minibatches = timed.minibatches / launch.options.iterations;
  const double bytes = 4.0 * static_cast<double>(messages.gradient_floats);
  std::printf("bench cluster: the update spread with its messages: %.1f minibatches with a gradient per iteration, a "
              "gradient of %zu floats (%.1f MB), 2 (N-1)/N gradients in and out of every rank per minibatch\n",
              priced.update_minibatches, messages.gradient_floats, bytes / 1e6);
  std::map<int, double> share_cost =
      launch.loop.recurrent_model() ? recurrent_share_costs(launch) : feedforward_share_costs(launch);
  std::vector<std::pair<std::string, double>> links;
  if (launch.ranks > 1) links.emplace_back("this launch's ranks", messages.gradient_transfer);
  for (double gbps : {10.0, 25.0, 100.0})
    links.emplace_back(std::to_string(static_cast<int>(gbps)) + " Gb/s link", bytes * 8.0 / (gbps * 1e9));
  std::printf("  ranks | update on rank 0 | spread (e u/N), messages free");
  for (const auto& [name, transfer_s] : links)
    std::printf(" | spread, %s (y = %.2f ms)", name.c_str(), 1e3 * transfer_s);
  std::printf("   (run, min)\n");
  for (int r : {1, 2, 4, 8, 16, 32, 64}) {
    if (r > launch.psi) break;
    cluster::ScalingCosts free_messages = priced;  // y = 0
    free_messages.update_share_cost = share_cost.count(r) ? share_cost[r] : 1.0;
    std::printf("  %5d | %16.1f | %29.1f", r, iterations_total * cluster::iteration_seconds(scaling, r) / 60.0,
                iterations_total * cluster::iteration_seconds(free_messages, r) / 60.0);
    for (const auto& [name, transfer_s] : links) {
      cluster::ScalingCosts with = free_messages;
      with.gradient_transfer_s = transfer_s;
      std::printf(" | %*.1f", static_cast<int>(name.size()) + 21,
                  iterations_total * cluster::iteration_seconds(with, r) / 60.0);
    }
    std::printf("\n");
  }
}

// The designs' cost spread: how much more the busiest rank carries than the model's rounds · c.
void print_cost_spread(const Launch& launch, const cluster::ScalingCosts& scaling, double iterations_total,
                       const std::vector<cluster::CostSample>& costs) {
  const int spread_draws = launch.options.spread_draws;
  std::map<int, int> designs;
  for (const cluster::CostSample& sample : costs) ++designs[sample.design];
  std::printf("bench cluster: the designs' cost spread (apps/bench/cost_spread.hpp), from %zu samples of %zu designs "
              "(every iteration above): F = the busiest rank's collection over the model's rounds x c, mean of %d "
              "simulated iterations\n",
              costs.size(), designs.size(), spread_draws);
  const cluster::CostSummary summary = cluster::summarize_costs(costs);
  std::printf("  one environment's settle and step CPU per iteration: mean %.3f s; the designs' means %.3f to %.3f s "
              "(standard deviation %.3f s across designs, %.3f s within a design)\n",
              summary.mean, summary.least_design, summary.largest_design, summary.across_designs,
              summary.within_design);
  std::printf("  ranks | F contiguous slices | F split by cost (built) | run, update on rank 0: with F contiguous, "
              "with F by cost\n");
  for (int r : {1, 2, 4, 8, 16, 32, 64}) {
    if (r > launch.psi) break;
    const cluster::BusiestLoad load = cluster::busiest_load_factor(costs, static_cast<std::size_t>(launch.psi), r,
                                                                   scaling.threads_per_rank, spread_draws, 20261204);
    cluster::ScalingCosts contiguous = scaling, by_cost = scaling;
    contiguous.collect_factor = load.contiguous;
    by_cost.collect_factor = load.by_cost;
    std::printf("  %5d | %19.3f | %23.3f | %8.1f min, %8.1f min\n", r, load.contiguous, load.by_cost,
                iterations_total * cluster::iteration_seconds(contiguous, r) / 60.0,
                iterations_total * cluster::iteration_seconds(by_cost, r) / 60.0);
  }
}

// The part of an iteration no rank count shortens, and the run's least time with it.
void print_serial_part(const cluster::ScalingCosts& scaling, double iterations_total) {
  std::printf("  serial part per iteration (update + policy + distribution): %.3f s: with the update on rank 0 the "
              "model's floor is %.1f min\n",
              scaling.update_s + scaling.policy_s + scaling.distribution_s,
              iterations_total *
                  (scaling.update_s + scaling.policy_s + scaling.distribution_s + scaling.env_collect_s) / 60.0);
}

int run_bench_cluster(const BenchClusterOptions& options) {
  // Read first: a bad run folder is one message before any work.
  const std::vector<cluster::RunIteration> whole_run =
      options.from_run.empty() ? std::vector<cluster::RunIteration>{} : read_run_iterations(options.from_run);
  const run::RunConfig setup = run::read_run_config(options.config);
  const run::RunSettings settings = run::run_settings(setup);
  const core::LoopConfig& lc = settings.loop;
  const std::vector<int> here = cluster::ranks_on_this_machine();  // collective: before the ranks part
  if (run::serve_unless_rank_zero(settings, static_cast<std::size_t>(options.threads), here)) return 0;
  const int ranks = cluster::world_size();
  auto sims = std::make_shared<core::SimulatorPool>(settings.spec, settings.scene, settings.solver);
  RolloutPool rollout_pool = make_bench_pool(sims, lc, options, ranks, here);
  core::EnvPool& pool = *rollout_pool.owned;
  const std::size_t threads =
      options.threads > 0 ? static_cast<std::size_t>(options.threads) : std::max(1u, std::thread::hardware_concurrency());
  core::OuterLoop loop(lc, std::move(rollout_pool.owned));
  const int ranks_here = static_cast<int>(here.size());
  const Launch launch{options, lc, loop, *sims, pool, rollout_pool.mpi, rollout_pool.recorder, ranks, threads,
                      lc.codesign.designs_per_update, lc.ppo.n_steps, ranks_here, cores_shared(ranks_here, threads)};
  print_launch(launch);

  CostLog log;
  // The warm-up meshes the designs first sampled and builds their simulators.
  for (int k = 0; k < options.warmup; ++k) keep_costs(launch, loop.iterate(), log);
  const int built = sims->constructed();
  const MessageCosts messages = time_messages(launch);
  const CountersAtStart start = read_counters(launch, built);
  const TimedIterations timed = run_timed_iterations(launch, log);

  const EnvCollection env = env_collection(launch, start, timed, messages);
  print_measured(launch, start, timed, env);
  if (launch.mpi_pool) print_mpi_sharing(*launch.mpi_pool, options, start, timed);
  print_machine_and_exchange(launch, timed, env, messages);

  const cluster::ScalingCosts scaling = measured_scaling_costs(launch, timed, env, messages);
  const double iterations_total =
      static_cast<double>(lc.codesign.total_timesteps) / (static_cast<double>(launch.psi) * launch.n_steps);
  print_model(launch, scaling, iterations_total);
  print_spread_update(launch, scaling, iterations_total, timed, messages);
  print_cost_spread(launch, scaling, iterations_total, log.costs);
  print_serial_part(scaling, iterations_total);
  if (!log.decision_costs.empty())
    print_meetings(log.decision_costs, scaling, iterations_total, static_cast<int>(threads),
                   core::whole_rollouts_allowed(lc), options, whole_run);
  else
    std::printf("bench cluster: the meetings at every decision are simulated from a one-process launch's decision "
                "costs (not recorded under mpirun)\n");
  return 0;
}

}  // namespace

void add_bench_cluster_command(CLI::App& bench, Runner& run) {
  auto opt = std::make_shared<BenchClusterOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "cluster", "Algorithm 1 on this launch's MPI ranks: measured costs and the scaling model to 64 ranks");
  cmd->add_option("--config", opt->config, "run config (default configs/paper.toml)");
  cmd->add_option("--iterations", opt->iterations, "timed iterations (default 3)")->check(CLI::Range(1, 1000));
  cmd->add_option("--warmup", opt->warmup, "untimed iterations first (default 3)")->check(CLI::Range(1, 1000));
  add_threads_option(*cmd, opt->threads, "rollout threads per rank (0: all cores)");
  cmd->add_option("--model-threads", opt->model_threads, "threads per rank in the model (default: this launch's)")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--contiguous", opt->contiguous,
               "under mpirun: keep the contiguous slices of environments, not shared out by cost (to compare)");
  cmd->add_flag("--lockstep", opt->lockstep,
               "under mpirun: step the rollouts decision by decision across the ranks, not whole rollouts on each "
               "rank (to compare; results are the same)");
  cmd->add_option("--from-run", opt->from_run,
                  "a finished one-process run of this launch's --threads (its ppo.csv): projected iteration by "
                  "iteration with the measured factors");
  cmd->add_option("--exchanges", opt->exchanges, "rounds of the exchange timing (default 200)")->check(CLI::Range(1, 1000000));
  cmd->callback([opt, &run] { run = [opt] { return run_bench_cluster(*opt); }; });
}

}  // namespace codesign::app
