#include "run/run.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <sstream>

#include <unistd.h>

#include "base/duration_text.hpp"
#include "base/errors.hpp"
#include "codesign/design_sweep.hpp"
#include "codesign/evaluation.hpp"
#include "codesign/failure_count.hpp"
#include "codesign/policy_controller.hpp"
#include "fem/design.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_log.hpp"
#include "io/run_lock.hpp"
#include "io/telemetry.hpp"
#include "rl/policy_file.hpp"
#include "run/checkpoint.hpp"
#include "run/codesign_tables_writer.hpp"
#include "run/rollout_backend.hpp"
#include "run/run_folder.hpp"
#include "run/stop_signals.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/codesign)

namespace {

namespace fs = std::filesystem;
using io::CsvLog;

std::string num(double v) { return CsvLog::num(v); }
std::string num(std::int64_t v) { return CsvLog::num(v); }
std::string num(int v) { return CsvLog::num(static_cast<std::int64_t>(v)); }

using fem::design_label;

// The run's logs, created or resumed together.
struct Logs {
  static std::vector<std::string> q_columns() {
    std::vector<std::string> c{"k", "t"};
    for (int j = 0; j < fem::kDesignCount; ++j) {
      std::string name = "q";  // (not "q" + to_string: GCC 12 reports a false -Wrestrict)
      name += std::to_string(j);
      c.push_back(std::move(name));
    }
    return c;
  }
  // distribution.csv of the entropy schedule has a target_entropy column after entropy; under the
  // ramp (no target) its columns are those of runs from before the schedule existed.
  static std::vector<std::string> distribution_columns(bool target_entropy) {
    std::vector<std::string> c{"k", "t", "phase", "beta", "entropy"};
    if (target_entropy) c.push_back("target_entropy");
    for (const char* name : {"top1_j", "top1_q", "top2_j", "top2_q", "top3_j", "top3_q", "best_j", "best_score",
                             "best_mu1_kPa", "best_mu2_kPa", "best_sigma1_kPa", "best_sigma2_kPa"})
      c.emplace_back(name);
    return c;
  }
  Logs(const fs::path& dir, const std::map<std::string, std::uint64_t>* resume, bool target_entropy) {
    const std::vector<std::pair<std::string, std::vector<std::string>>> logs{
        {run_file::kEpisodes,
         {"t", "k", "j", "n", "l_mm", "w_mm", "p1_kPa", "p2_kPa", "phase_rad", "return", "decisions", "in_band",
          "first", "reason"}},
        {run_file::kPpo,
         {"k", "t", "pg_loss", "value_loss", "entropy_loss", "loss", "approx_kl", "clip_fraction",
          "explained_variance", "lr", "ent_coef", "epochs", "early_stopped", "grad_norm", "collect_s", "update_s",
          "policy_s", "steps_per_s"}},
        {run_file::kDistribution, distribution_columns(target_entropy)},
        {run_file::kQDisc, q_columns()},
        {run_file::kSampled,
         {"k", "t", "i", "j", "p1_kPa", "p2_kPa", "return", "mu1_kPa", "mu2_kPa", "sigma1_kPa", "sigma2_kPa"}}};
    // A resume cuts the logs back to the checkpoint only once all of them fit it: a resume that
    // fails leaves every file as it was.
    for (const auto& [name, columns] : logs) (void)position(dir, name, columns, resume);
    std::unique_ptr<CsvLog>* member[] = {&episodes, &ppo, &distribution, &q, &sampled};
    for (std::size_t i = 0; i < logs.size(); ++i) {
      const auto& [name, columns] = logs[i];
      *member[i] = std::make_unique<CsvLog>((dir / name).string(), columns, position(dir, name, columns, resume));
    }
  }

  // The checkpointed length of a log to resume (checked against the file), or none.
  static std::optional<std::uint64_t> position(const fs::path& dir, const std::string& name,
                                               const std::vector<std::string>& columns,
                                               const std::map<std::string, std::uint64_t>* resume) {
    if (!resume) return std::nullopt;
    const auto it = resume->find(name);
    if (it == resume->end()) throw InputError("checkpoint: has no position for " + name);
    CsvLog::check_resumable((dir / name).string(), columns, it->second);
    return it->second;
  }

  std::map<std::string, std::uint64_t> flush() {
    return {{run_file::kEpisodes, episodes->flush()},
            {run_file::kPpo, ppo->flush()},
            {run_file::kDistribution, distribution->flush()},
            {run_file::kQDisc, q->flush()},
            {run_file::kSampled, sampled->flush()}};
  }

  std::unique_ptr<CsvLog> episodes, ppo, distribution, q, sampled;
};

// What the CSV logs and the telemetry both say of the distribution after an iteration.
struct DistributionSummary {
  Phase phase = Phase::Exploration;
  double entropy = 0.0;
  std::optional<double> target_entropy;  // the entropy schedule's H*(t); none under the ramp
  Eigen::VectorXd q;          // q_disc over the 110 designs
  std::array<int, 3> top{};   // the three most probable designs, most probable first
  int best = 0;               // leading design and its score, mean and sigma of p in kPa
  double best_score = 0.0;
  Eigen::Vector2d mu = Eigen::Vector2d::Zero(), sigma = Eigen::Vector2d::Zero();
};

DistributionSummary summarize(const DesignDistribution& dist, std::int64_t t) {
  DistributionSummary s;
  s.phase = dist.phase(t);
  s.entropy = dist.entropy(t);
  s.target_entropy = dist.target_entropy(t);
  s.q = dist.probabilities(t);
  std::vector<int> order(static_cast<std::size_t>(s.q.size()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return s.q[a] > s.q[b]; });
  for (std::size_t i = 0; i < s.top.size() && i < order.size(); ++i) s.top[i] = order[i];
  s.best = dist.leading_design();
  s.best_score = dist.state().score[s.best];
  s.mu = dist.mean_pressures_kPa(s.best);
  s.sigma = dist.sigma_pressures_kPa(s.best);
  return s;
}

void log_iteration(Logs& logs, const IterationReport& rep, const DesignDistribution& dist,
                   const DistributionSummary& sum, double steps_per_s) {
  for (const EpisodeRecord& e : rep.episodes) {
    const fem::Design d = fem::design_from_index(e.setup.design);
    logs.episodes->row({num(rep.t), num(rep.k), num(e.setup.design), num(d.n), num(d.chamber_length_mm),
                        num(d.wall_mm), num(e.setup.p1_kPa), num(e.setup.p2_kPa), num(e.setup.plate_phase_rad),
                        num(e.episode_return), num(e.decisions), num(e.in_band), num(e.first ? 1 : 0), e.reason});
  }
  const rl::PpoStats& p = rep.ppo;
  logs.ppo->row({num(rep.k), num(rep.t), num(p.pg_loss), num(p.value_loss), num(p.entropy_loss), num(p.loss),
                 num(p.approx_kl), num(p.clip_fraction), num(p.explained_variance), num(rep.learning_rate),
                 num(p.ent_coef), num(p.epochs_done), num(p.early_stopped ? 1 : 0), num(p.grad_norm),
                 num(rep.collect_s), num(rep.update_s), num(rep.policy_s), num(steps_per_s)});
  const Eigen::VectorXd& q = sum.q;
  std::vector<std::string> dist_row{num(rep.k), num(rep.t), to_string(sum.phase), num(rep.beta), num(sum.entropy)};
  if (sum.target_entropy) dist_row.push_back(num(*sum.target_entropy));
  dist_row.insert(dist_row.end(), {num(sum.top[0]), num(q[sum.top[0]]), num(sum.top[1]), num(q[sum.top[1]]),
                                   num(sum.top[2]), num(q[sum.top[2]]), num(sum.best), num(sum.best_score),
                                   num(sum.mu[0]), num(sum.mu[1]), num(sum.sigma[0]), num(sum.sigma[1])});
  logs.distribution->row(dist_row);
  std::vector<std::string> row{num(rep.k), num(rep.t)};
  for (Eigen::Index j = 0; j < q.size(); ++j) row.push_back(num(q[j]));
  logs.q->row(row);
  for (std::size_t i = 0; i < rep.samples.size(); ++i) {
    const DesignSample& s = rep.samples[i];
    const Eigen::Vector2d m = dist.mean_pressures_kPa(s.design), sd = dist.sigma_pressures_kPa(s.design);
    logs.sampled->row({num(rep.k), num(rep.t), num(static_cast<std::int64_t>(i)), num(s.design),
                       num(s.pressures_kPa[0]), num(s.pressures_kPa[1]), num(rep.returns[i]), num(m[0]), num(m[1]),
                       num(sd[0]), num(sd[1])});
  }
}

// Wall time and messages spent on telemetry (filling messages, encoding, sending), summed over
// threads; RunResult reports them so `codesign bench telemetry` can state the cost.
struct PublishMeter {
  std::atomic<std::int64_t> ns{0}, messages{0};
  class Scope {
   public:
    Scope(PublishMeter& m, std::int64_t messages) : m_(m), start_(std::chrono::steady_clock::now()) {
      m_.messages.fetch_add(messages, std::memory_order_relaxed);
    }
    ~Scope() {
      const auto d = std::chrono::steady_clock::now() - start_;
      m_.ns.fetch_add(std::chrono::duration_cast<std::chrono::nanoseconds>(d).count(), std::memory_order_relaxed);
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    PublishMeter& m_;
    std::chrono::steady_clock::time_point start_;
  };
};

// The iteration's rows as LCM messages (the same numbers as the CSV logs).
void publish_iteration(io::Telemetry& tel, const IterationReport& rep, const DistributionSummary& sum,
                       double steps_per_s) {
  if (!tel.enabled()) return;
  for (const EpisodeRecord& e : rep.episodes) {
    const fem::Design d = fem::design_from_index(e.setup.design);
    codesign_lcm::episode_t m{};
    m.timestep = rep.t;
    m.iteration = rep.k;
    m.env = e.env;
    m.design = e.setup.design;
    m.n_chambers = d.n;
    m.l_mm = d.chamber_length_mm;
    m.w_mm = d.wall_mm;
    m.pressures_kPa[0] = e.setup.p1_kPa;
    m.pressures_kPa[1] = e.setup.p2_kPa;
    m.phase_rad = e.setup.plate_phase_rad;
    m.episode_return = e.episode_return;
    m.decisions = e.decisions;
    m.in_band = e.in_band;
    m.first = e.first;
    m.reason = e.reason;
    tel.publish(m);
  }
  const rl::PpoStats& p = rep.ppo;
  codesign_lcm::ppo_update_t u{};
  u.iteration = rep.k;
  u.timestep = rep.t;
  u.pg_loss = p.pg_loss;
  u.value_loss = p.value_loss;
  u.entropy_loss = p.entropy_loss;
  u.loss = p.loss;
  u.approx_kl = p.approx_kl;
  u.clip_fraction = p.clip_fraction;
  u.explained_variance = p.explained_variance;
  u.learning_rate = rep.learning_rate;
  u.ent_coef = p.ent_coef;
  u.epochs = p.epochs_done;
  u.early_stopped = p.early_stopped;
  u.grad_norm = p.grad_norm;
  u.collect_s = rep.collect_s;
  u.update_s = rep.update_s;
  u.policy_s = rep.policy_s;
  u.steps_per_s = steps_per_s;
  tel.publish(u);
  codesign_lcm::distribution_t q{};
  q.iteration = rep.k;
  q.timestep = rep.t;
  q.phase = to_string(sum.phase);
  q.beta = rep.beta;
  q.entropy = sum.entropy;
  q.target_entropy = sum.target_entropy.value_or(std::numeric_limits<double>::quiet_NaN());
  for (Eigen::Index j = 0; j < sum.q.size() && j < 110; ++j) q.probabilities[j] = sum.q[j];
  q.best_design = sum.best;
  q.best_score = sum.best_score;
  q.best_mu_kPa[0] = sum.mu[0];
  q.best_mu_kPa[1] = sum.mu[1];
  q.best_sigma_kPa[0] = sum.sigma[0];
  q.best_sigma_kPa[1] = sum.sigma[1];
  tel.publish(q);
}

// The simulation steps of an evaluation trace.
codesign_lcm::sim_step_t sim_step_message(const EpisodeSetup& setup, const TraceRow& r, std::int64_t t) {
  codesign_lcm::sim_step_t m{};
  m.timestep = t;
  m.t_s = r.t_s;
  m.theta_rad = r.theta_rad;
  m.force_mN = r.force_mN;
  m.strain = r.strain;
  for (int i = 0; i < 3; ++i) m.tip_mm[i] = r.tip_mm[i];
  m.plate_z_mm = r.plate_z_mm;
  m.design = setup.design;
  m.pressures_kPa[0] = setup.p1_kPa;
  m.pressures_kPa[1] = setup.p2_kPa;
  m.decision = r.decision;
  m.action = r.action;
  return m;
}

void publish_trace(io::Telemetry& tel, const DesignEvaluation& e, std::int64_t t) {
  if (!tel.enabled()) return;
  for (const TraceRow& r : e.trace) tel.publish(sim_step_message(e.setup, r, t));
}

// Makes DIR ready for the run, before any simulator is built: on --resume the checkpoint to
// continue from (none when the run stopped before its first one and DIR/config.toml is this
// config: it then starts again); otherwise DIR refused if it holds an earlier run (unless
// --force), created, and its config files written, results of an earlier run removed.
std::optional<Checkpoint> prepare_run_folder(const RunSettings& settings, const RunOptions& options,
                                             const std::string& resolved, std::uint64_t fp) {
  const fs::path dir(options.dir);
  const fs::path ckpt_path = dir / run_file::kCheckpoint;
  std::optional<Checkpoint> ckpt;
  std::error_code ec;
  bool fresh = !options.resume;
  if (options.resume) {
    if (fs::exists(ckpt_path, ec)) {
      ckpt = load_checkpoint(ckpt_path.string(), fp);
    } else {
      // Stopped before its first checkpoint: nothing to keep, so start this run's config again.
      std::ifstream in(dir / run_file::kConfig, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      if (!in || text.str() != resolved)
        throw InputError(dir.string() + ": no checkpoint.bin (and no config.toml of this config) to resume from; "
                         "start the run without --resume");
      fresh = true;
    }
  }
  if (fresh && !options.resume) {
    for (const char* f : {run_file::kConfig, run_file::kCheckpoint, run_file::kResult, run_file::kEpisodes})
      if (fs::exists(dir / f, ec) && !options.force)
        throw InputError(dir.string() + ": already holds " + f + " of an earlier run; continue it with --resume, "
                         "or choose another -o, or pass --force to start afresh");
    fs::create_directories(dir, ec);
    if (ec) throw InputError(dir.string() + ": cannot create the run folder: " + ec.message());
  }
  if (fresh) {
    for (const char* f : {run_file::kCheckpoint, run_file::kResult, run_file::kPolicy}) fs::remove(dir / f, ec);
    for (const KeptCheckpoint& kc : kept_checkpoints(settings.loop.codesign)) fs::remove(dir / kc.file, ec);
    io::write_file_atomically((dir / run_file::kConfig).string(), [&](std::ostream& out) { out << resolved; });
    if (!options.resume)
      io::write_file_atomically((dir / run_file::kConfigInput).string(),
                                [&](std::ostream& out) { out << settings.config_text; });
  }
  return ckpt;
}

// The training-time telemetry: the state after every telemetry_train_every-th decision of training
// environment 0 on its own channel and, with the recurrent policy, its memory in that environment
// after every decision; both stamped with the run's timestep at the start of the iteration they
// belong to (iteration_start_t), their cost counted in `meter`.
void observe_training(OuterLoop& loop, io::Telemetry& telemetry, const RunOptions& options,
                      std::atomic<std::int64_t>& iteration_start_t, PublishMeter& meter) {
  if (!telemetry.enabled()) return;
  if (options.telemetry_train_every > 0) {
    io::Telemetry& tel = telemetry;
    loop.envs().set_step_observer(
        0,
        [&tel, &iteration_start_t, &meter](const EpisodeSetup& s, const TraceRow& r) {
          const PublishMeter::Scope timed(meter, 1);
          tel.publish_training(sim_step_message(s, r, iteration_start_t.load(std::memory_order_relaxed)));
        },
        options.telemetry_train_every);
  }
  if (loop.recurrent_model()) {
    io::Telemetry& tel = telemetry;
    loop.set_memory_observer([&tel, &iteration_start_t, &meter](int decision, int design, const Eigen::VectorXf& a,
                                                                const Eigen::VectorXf& c) {
      const PublishMeter::Scope timed(meter, 1);
      codesign_lcm::policy_memory_t m{};
      m.timestep = iteration_start_t.load(std::memory_order_relaxed);
      m.decision = decision;
      m.design = design;
      m.units = static_cast<std::int32_t>(a.size());
      m.actor_h.assign(a.data(), a.data() + a.size());
      m.critic_h.assign(c.data(), c.data() + c.size());
      m.actor_norm = a.cast<double>().norm();
      m.critic_norm = c.cast<double>().norm();
      tel.publish(m);
    });
  }
}

// What the final evaluation tests: d* at p* (the single design of that baseline; else the leading
// design at its collapsed optimum, or at its mean pressures if the distribution never
// collapsed) and the runner-up at its mean pressures (none for the single-design baseline).
struct FinalDesigns {
  EpisodeSetup best;
  std::optional<EpisodeSetup> runner;
};
FinalDesigns final_designs(const DesignDistribution& dist, const CodesignConfig& c) {
  FinalDesigns f;
  if (c.baseline == Baseline::SingleDesign) {
    const DesignSample d = single_design(c);
    f.best = {d.design, d.pressures_kPa[0], d.pressures_kPa[1], 0.0, 0.0};
    return f;
  }
  const std::vector<int> rank = dist.ranking();
  const int jb = dist.leading_design();
  const Eigen::Vector2d pb = dist.state().collapsed ? dist.pressures_kPa(dist.state().best_latent, jb)
                                                    : dist.mean_pressures_kPa(jb);
  f.best = {jb, pb[0], pb[1], 0.0, 0.0};
  const int jr = rank[0] == jb ? rank[1] : rank[0];
  const Eigen::Vector2d pr = dist.mean_pressures_kPa(jr);
  f.runner = EpisodeSetup{jr, pr[0], pr[1], 0.0, 0.0};
  return f;
}

// The run's closing lines on stdout: d* and its test, the fixed-angle reference, the runner-up,
// numerical failures, where result.toml is.
void print_result(const fs::path& dir, const ResultFile& rr, const DesignEvaluation& eb,
                  const std::optional<FixedThetaTuning>& fixed, const std::optional<DesignEvaluation>& er) {
  const EpisodeSetup& best = eb.setup;
  const std::int64_t numerical = rr.run.numerical_failures;
  const double wall_total = rr.run.wall_s;
  const int eval_episodes = rr.eval_episodes;
  std::printf("codesign: d* = %s, p* = [%.4g, %.4g] kPa: test return %.2f +- %.2f over %d episodes (band %.0f%%)\n",
              design_label(best.design).c_str(), best.p1_kPa, best.p2_kPa, eb.mean_return, eb.std_return,
              eval_episodes, 100.0 * eb.mean_band_fraction);
  if (fixed)
    std::printf("codesign: d* with the base held at its best fixed angle %.2f deg (no controller): test return %.2f +- %.2f "
                "(band %.0f%%); the policy %s it by %.2f\n",
                fixed->theta0_rad * 180.0 / std::numbers::pi, fixed->test.mean_return, fixed->test.std_return,
                100.0 * fixed->test.mean_band_fraction, eb.mean_return > fixed->test.mean_return ? "beats" : "trails",
                std::abs(eb.mean_return - fixed->test.mean_return));
  if (er)
    std::printf("codesign: runner-up %s, p = [%.4g, %.4g] kPa: test return %.2f +- %.2f (band %.0f%%)\n",
                design_label(er->setup.design).c_str(), er->setup.p1_kPa, er->setup.p2_kPa, er->mean_return, er->std_return,
                100.0 * er->mean_band_fraction);
  if (numerical > 0)
    std::printf("codesign: %lld training episodes ended by a numerical failure (episodes.csv reason \"numerical: ...\")\n",
                static_cast<long long>(numerical));
  std::printf("codesign: %lld timesteps in %s -> %s\n", static_cast<long long>(rr.run.timesteps),
              duration_text(wall_total).c_str(), (dir / run_file::kResult).string().c_str());
}

}  // namespace

RunResult run_codesign(const RunSettings& settings, const RunOptions& options) {
  const auto t_start = std::chrono::steady_clock::now();
  const fs::path dir(options.dir);
  // Taken before anything in DIR is looked at: a refused run reads and changes nothing.
  const std::unique_ptr<io::RunLock> own_lock = options.lock ? nullptr : lock_run_folder(options.dir, options.resume);
  const fs::path ckpt_path = dir / run_file::kCheckpoint;
  // The resolved config (every key with the value used) is what the run folder keeps and what
  // checkpoints are tied to: resuming with the original file or with DIR/config.toml both match.
  const std::string resolved = resolved_run_config(settings.spec, settings.scene, settings.solver, settings.loop);
  const std::uint64_t fp = fingerprint(resolved);
  const std::optional<Checkpoint> ckpt = prepare_run_folder(settings, options, resolved, fp);
  auto sims = std::make_shared<SimulatorPool>(settings.spec, settings.scene, settings.solver);
  const LoopConfig& lc = settings.loop;
  OuterLoop loop(lc, make_rollout_pool(sims, lc, options.threads, options.ranks, options.machine_ranks));
  double wall_before = 0.0;
  if (ckpt) {
    try {
      loop.restore(ckpt->loop);
    } catch (const std::invalid_argument& e) {
      throw InputError("checkpoint " + ckpt_path.string() + ": " + e.what());
    }
    wall_before = ckpt->wall_s;
  }
  Logs logs(dir, ckpt ? &ckpt->logs : nullptr, lc.codesign.distribution.beta_schedule == BetaSchedule::Entropy);
  // Training episodes ended by a numerical failure so far (episodes.csv holds those before a resume).
  std::int64_t numerical = count_numerical_failures((dir / run_file::kEpisodes).string());
  const std::unique_ptr<io::Telemetry> telemetry = io::make_telemetry(options.telemetry_url);
  // The run's timestep at the start of the current iteration, for the training-time telemetry.
  std::atomic<std::int64_t> iteration_start_t{loop.timesteps()};
  PublishMeter meter;
  observe_training(loop, *telemetry, options, iteration_start_t, meter);
  auto report_telemetry = [&](RunResult& r) {
    r.telemetry_messages = meter.messages.load();
    r.telemetry_s = 1e-9 * static_cast<double>(meter.ns.load());
  };

  const CodesignConfig& c = lc.codesign;
  const std::int64_t T = c.total_timesteps;
  const std::int64_t t0 = loop.timesteps();
  const bool tty = options.progress && ::isatty(::fileno(stdout));
  double last_print = -1e9;
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count(); };
  // keep: also write the same state to this file (the copies kept at T1 and T2, which
  // `codesign evaluate --at` reads); written before checkpoint.bin so a kill between the two
  // leaves a checkpoint.bin that still precedes the crossing and so writes the copy again.
  auto checkpoint = [&](const fs::path& keep = {}) {
    Checkpoint k;
    k.config_fingerprint = fp;
    k.wall_s = wall_before + elapsed();
    k.loop = loop.state();
    k.logs = logs.flush();
    if (!keep.empty()) save_checkpoint(keep.string(), k);
    save_checkpoint(ckpt_path.string(), k);
  };
  std::int64_t last_ckpt = loop.timesteps();
  RunResult result;
  // A signal that asked to stop: one line on stderr saying where the run is and how to go on.
  auto stopped = [&](int sig, const std::string& where) {
    if (tty) std::printf("\n");
    std::fflush(stdout);
    std::fprintf(stderr, "codesign: %s: %s; checkpoint.bin holds t = %lld of %lld; continue with: "
                 "codesign --config %s -o %s --resume\n",
                 signal_name(sig).c_str(), where.c_str(), static_cast<long long>(loop.timesteps()),
                 static_cast<long long>(T), (dir / run_file::kConfig).string().c_str(), dir.string().c_str());
    result.stop_signal = sig;
    result.timesteps = loop.timesteps();
    result.wall_s = elapsed();
    report_telemetry(result);
    return result;
  };
  while (!loop.finished()) {
    const std::int64_t t_before = loop.timesteps();
    iteration_start_t.store(t_before, std::memory_order_relaxed);
    const IterationReport rep = loop.iterate();
    const double el = elapsed();
    const double rate = static_cast<double>(rep.t - t0) / std::max(el, 1e-9);
    const DistributionSummary summary = summarize(loop.distribution(), rep.t);
    log_iteration(logs, rep, loop.distribution(), summary, rate);
    for (const EpisodeRecord& e : rep.episodes) numerical += is_numerical_failure(e.reason) ? 1 : 0;
    if (telemetry->enabled()) {
      const PublishMeter::Scope timed(meter, static_cast<std::int64_t>(rep.episodes.size()) + 2);
      publish_iteration(*telemetry, rep, summary, rate);
    }
    // The first iteration to reach T1 or T2 is kept in a file of its own as well.
    fs::path keep;
    for (const KeptCheckpoint& kc : kept_checkpoints(c))
      if (t_before < kc.t && rep.t >= kc.t) keep = dir / kc.file;
    if (!keep.empty() || rep.t - last_ckpt >= c.checkpoint_every || loop.finished()) {
      checkpoint(keep);
      last_ckpt = rep.t;
    }
    if (options.progress && (el - last_print >= (tty ? 0.5 : 10.0) || loop.finished())) {
      last_print = el;
      const DesignDistribution& d = loop.distribution();
      const int best = c.baseline == Baseline::SingleDesign ? c.single_design_index : d.leading_design();
      const double mean_first = std::accumulate(rep.returns.begin(), rep.returns.end(), 0.0) /
                                static_cast<double>(std::max<std::size_t>(1, rep.returns.size()));
      const std::string failures = numerical > 0 ? " | numerical failures " + std::to_string(numerical) : "";
      std::printf("%st %lld/%lld (%.1f%%) | %.0f steps/s | ETA %s | %s | mean return %.2f | best %s R^ %.2f%s%s",
                  tty ? "\r" : "", static_cast<long long>(rep.t), static_cast<long long>(T),
                  100.0 * static_cast<double>(rep.t) / static_cast<double>(T), rate,
                  duration_text(static_cast<double>(T - rep.t) / std::max(rate, 1e-9)).c_str(), to_string(d.phase(rep.t)),
                  mean_first, design_label(best).c_str(), d.state().score[best], failures.c_str(),
                  tty ? "   " : "\n");
      std::fflush(stdout);
    }
    // The flag a SIGTERM / SIGINT set during this iteration (stop_signals.hpp).
    if (const int sig = stop_signal(); sig != 0 && !loop.finished()) {
      if (last_ckpt != loop.timesteps()) checkpoint();
      return stopped(sig, "stopped after the iteration ending at t = " + std::to_string(rep.t));
    }
    if (options.stop_after >= 0 && rep.t >= options.stop_after && !loop.finished()) {
      checkpoint();
      result.timesteps = rep.t;
      result.wall_s = elapsed();
      report_telemetry(result);
      return result;
    }
  }
  if (tty) std::printf("\n");
  if (const std::string note = rollout_sharing_note(loop.envs()); !note.empty())
    std::printf("codesign: %s\n", note.c_str());
  if (last_ckpt != loop.timesteps()) checkpoint();
  // A signal now (or during the evaluation, checked after each design) stops before result.toml:
  // training is complete and checkpointed, so --resume only runs the evaluation again.
  const std::string in_evaluation = "stopped during the final evaluation (training is complete)";
  if (const int sig = stop_signal(); sig != 0) return stopped(sig, in_evaluation);

  // ---- final evaluation: d* and the runner-up with the deterministic final policy
  const DesignDistribution& dist = loop.distribution();
  const FinalDesigns finals = final_designs(dist, c);
  const EpisodeSetup& best = finals.best;
  // The final policy as policy.bin will hold it: the model and its frozen observation
  // normalisation, acting as every later reader of the file acts (rl::Policy).
  // One controller per episode: a recurrent policy's state starts at zero in each.
  const auto final_policy = std::make_shared<const rl::Policy>(loop.policy_contents());
  const ControllerFactory policy = policy_factory(final_policy);
  EvaluationOptions eo;
  eo.episodes = c.eval_episodes;
  const std::size_t eval_threads = options.evaluation_threads > 0 ? options.evaluation_threads : options.threads;
  eo.threads = eval_threads;
  const DesignEvaluation eb = evaluate_feedback(policy, sims, lc.task, best, eo);
  write_evaluation(dir / run_file::kEvalDir, "best", eb);
  if (telemetry->enabled()) {
    const PublishMeter::Scope timed(meter, static_cast<std::int64_t>(eb.trace.size()));
    publish_trace(*telemetry, eb, loop.timesteps());
  }
  if (const int sig = stop_signal(); sig != 0) return stopped(sig, in_evaluation);
  std::optional<DesignEvaluation> er;
  if (finals.runner) {
    er = evaluate_feedback(policy, sims, lc.task, *finals.runner, eo);
    write_evaluation(dir / run_file::kEvalDir, "runner_up", *er);
    if (telemetry->enabled()) {
      const PublishMeter::Scope timed(meter, static_cast<std::int64_t>(er->trace.size()));
      publish_trace(*telemetry, *er, loop.timesteps());
    }
  }
  if (const int sig = stop_signal(); sig != 0) return stopped(sig, in_evaluation);
  // The reference for d*: its best constant base angle, tuned on phases no test shares.
  std::optional<FixedThetaTuning> fixed;
  if (c.fixed_theta_phases > 0) {
    fixed = tune_fixed_theta(sims, lc.task, best, FixedThetaConfig{}, c.fixed_theta_phases, c.eval_episodes,
                             eval_threads);
    if (const int sig = stop_signal(); sig != 0) return stopped(sig, in_evaluation);
  }
  rl::save_policy(dir / run_file::kPolicy, final_policy->contents());
  result.wall_s = elapsed();
  const double wall_total = wall_before + result.wall_s;
  ResultFile rr;
  rr.eval_episodes = c.eval_episodes;
  rr.best = result_design(eb);
  if (er) rr.runner_up = result_design(*er);
  if (fixed)
    rr.fixed_theta = ResultFixedTheta{fixed->theta0_rad, c.fixed_theta_phases, fixed->test.mean_return,
                                      fixed->test.std_return, fixed->test.mean_band_fraction};
  rr.run.timesteps = loop.timesteps();
  rr.run.iterations = loop.iteration();
  rr.run.seed = c.seed;
  rr.run.observation = to_string(lc.task.observation);
  rr.run.baseline = to_string(c.baseline);
  rr.run.numerical_failures = numerical;
  rr.run.wall_s = wall_total;
  write_result(dir, rr);
  print_result(dir, rr, eb, fixed, er);
  result.completed = true;
  result.timesteps = loop.timesteps();
  report_telemetry(result);
  if (telemetry->enabled())
    std::printf("codesign: telemetry: %lld messages, %.3f s spent publishing (%.2f %% of this session's wall time)\n",
                static_cast<long long>(result.telemetry_messages), result.telemetry_s,
                100.0 * result.telemetry_s / std::max(result.wall_s, 1e-9));
  return result;
}

}  // namespace codesign::run
