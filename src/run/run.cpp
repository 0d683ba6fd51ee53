#include "run/run.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "base/errors.hpp"
#include "core/failure_count.hpp"
#include "io/formats/run_lock.hpp"
#include "rl/policy_file.hpp"
#include "run/checkpoint.hpp"
#include "run/codesign_tables_writer.hpp"
#include "run/distribution_summary.hpp"
#include "run/final_evaluation.hpp"
#include "run/final_result.hpp"
#include "run/prepare_folder.hpp"
#include "run/progress_line.hpp"
#include "run/rollout_backend.hpp"
#include "run/run_folder.hpp"
#include "run/run_logs.hpp"
#include "run/run_telemetry.hpp"
#include "run/stop_signals.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;

// Why a session ended before result.toml: a signal (and where the run was), or stop_after.
struct Stop {
  int signal = 0;  // 0: options.stop_after was reached
  std::string where;
};

// One session of a run in its folder: from the folder prepared (and the state restored from its
// checkpoint) through training and the final evaluation to result.toml, or to a stop.
class Session {
 public:
  Session(const RunSettings& settings, const RunOptions& options);
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Algorithm 1 until total_timesteps: logs and telemetry after every iteration, a checkpoint
  // every checkpoint_every decisions, at T1 and T2 (kept in files of their own too) and at the end.
  std::optional<Stop> train();
  // The final evaluation with the final policy (final_evaluation.hpp).
  std::optional<Stop> evaluate();
  // policy.bin and result.toml, the closing lines.
  RunResult write_results();
  // A stop's line on stderr (for a signal) and what the session did.
  RunResult stopped(const Stop& stop);

 private:
  double elapsed_s() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  }
  // Writes the state to checkpoint.bin, and first to `keep` when given (a kill between the two
  // leaves a checkpoint.bin before the crossing of T1 or T2, which writes the copy again).
  void save(const fs::path& keep = {});
  void checkpoint_if_due(std::int64_t t_before, std::int64_t t_after);
  RunResult session_result(std::int64_t timesteps) const;

  const RunSettings& settings_;
  const RunOptions& options_;
  const std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  const fs::path dir_;
  // The resolved config (every key with the value used) is what the run folder keeps and what
  // checkpoints are tied to: resuming with the original file or with DIR/config.toml both match.
  const std::string resolved_config_;
  const std::uint64_t fingerprint_;
  const std::optional<Checkpoint> checkpoint_;
  const std::shared_ptr<core::SimulatorPool> sims_;
  core::OuterLoop loop_;
  const double wall_before_s_;  // the run's wall time in earlier sessions
  RunLogs logs_;
  std::int64_t numerical_failures_;
  RunTelemetry telemetry_;
  ProgressLine progress_;
  std::int64_t last_checkpoint_t_;
  std::shared_ptr<const rl::Policy> final_policy_;
  std::optional<FinalEvaluation> evaluation_;
};

// The loop continues from the checkpoint's state; returns the wall time of the sessions before.
double restore(core::OuterLoop& loop, const std::optional<Checkpoint>& ckpt, const fs::path& dir) {
  if (!ckpt) return 0.0;
  try {
    loop.restore(ckpt->loop);
  } catch (const std::invalid_argument& e) {
    throw InputError("checkpoint " + (dir / run_file::kCheckpoint).string() + ": " + e.what());
  }
  return ckpt->wall_s;
}

Session::Session(const RunSettings& settings, const RunOptions& options)
    : settings_(settings),
      options_(options),
      dir_(options.dir),
      resolved_config_(resolved_run_config(settings.spec, settings.scene, settings.solver, settings.loop)),
      fingerprint_(fingerprint(resolved_config_)),
      checkpoint_(prepare_run_folder(settings, dir_, options.resume, options.force, resolved_config_, fingerprint_)),
      sims_(std::make_shared<core::SimulatorPool>(settings.spec, settings.scene, settings.solver)),
      loop_(settings.loop, make_rollout_pool(sims_, settings.loop, options.threads, options.ranks, options.machine_ranks)),
      wall_before_s_(restore(loop_, checkpoint_, dir_)),
      logs_(dir_, checkpoint_ ? &checkpoint_->logs : nullptr,
            settings.loop.codesign.distribution.beta_schedule == core::BetaSchedule::Entropy,
            settings.loop.task.randomize.enabled(), settings.loop.task.randomize.wall_mm > 0.0),
      // Training episodes ended by a numerical failure so far (episodes.csv holds those before a resume).
      numerical_failures_(RunLogs::numerical_failures_logged(dir_)),
      telemetry_(options.telemetry_url, options.telemetry_train_every),
      progress_(options.progress),
      last_checkpoint_t_(loop_.timesteps()) {
  telemetry_.observe_training(loop_);
}

void Session::save(const fs::path& keep) {
  Checkpoint k;
  k.config_fingerprint = fingerprint_;
  k.wall_s = wall_before_s_ + elapsed_s();
  k.loop = loop_.state();
  k.logs = logs_.flush();
  if (!keep.empty()) save_checkpoint(keep.string(), k);
  save_checkpoint((dir_ / run_file::kCheckpoint).string(), k);
  last_checkpoint_t_ = loop_.timesteps();
}

void Session::checkpoint_if_due(std::int64_t t_before, std::int64_t t_after) {
  // The first iteration to reach T1 or T2 is kept in a file of its own as well.
  fs::path keep;
  for (const KeptCheckpoint& kc : kept_checkpoints(settings_.loop.codesign))
    if (t_before < kc.t && t_after >= kc.t) keep = dir_ / kc.file;
  if (!keep.empty() || t_after - last_checkpoint_t_ >= settings_.loop.codesign.checkpoint_every || loop_.finished())
    save(keep);
}

std::optional<Stop> Session::train() {
  const std::int64_t t0 = loop_.timesteps();
  while (!loop_.finished()) {
    const std::int64_t t_before = loop_.timesteps();
    telemetry_.start_iteration(t_before);
    const core::IterationReport rep = loop_.iterate();
    const double elapsed = elapsed_s();
    const double steps_per_s = static_cast<double>(rep.t - t0) / std::max(elapsed, 1e-9);
    const DistributionSummary summary = summarize(loop_.distribution(), rep.t);
    logs_.write_iteration(rep, loop_.distribution(), summary, steps_per_s);
    for (const core::EpisodeRecord& e : rep.episodes) numerical_failures_ += core::is_numerical_failure(e.reason);
    telemetry_.publish_iteration(rep, summary, steps_per_s);
    checkpoint_if_due(t_before, rep.t);
    progress_.iteration(rep, loop_.distribution(), settings_.loop.codesign, elapsed, steps_per_s, numerical_failures_,
                        loop_.finished());
    // The flag a SIGTERM / SIGINT set during this iteration (stop_signals.hpp).
    if (const int sig = stop_signal(); sig != 0 && !loop_.finished()) {
      if (last_checkpoint_t_ != loop_.timesteps()) save();
      return Stop{sig, "stopped after the iteration ending at t = " + std::to_string(rep.t)};
    }
    if (options_.stop_after >= 0 && rep.t >= options_.stop_after && !loop_.finished()) {
      save();
      return Stop{};
    }
  }
  progress_.end_line();
  if (const std::string note = rollout_sharing_note(loop_.envs()); !note.empty())
    std::printf("codesign: %s\n", note.c_str());
  if (last_checkpoint_t_ != loop_.timesteps()) save();
  return std::nullopt;
}

std::optional<Stop> Session::evaluate() {
  // A signal now (or during the evaluation, checked after each design) stops before result.toml:
  // training is complete and checkpointed, so --resume only runs the evaluation again.
  const std::string in_evaluation = "stopped during the final evaluation (training is complete)";
  if (const int sig = stop_signal(); sig != 0) return Stop{sig, in_evaluation};
  // The final policy as policy.bin will hold it: the model and its frozen observation
  // normalisation, acting as every later reader of the file acts (rl::Policy).
  final_policy_ = std::make_shared<const rl::Policy>(loop_.policy_contents());
  const std::size_t threads = options_.evaluation_threads > 0 ? options_.evaluation_threads : options_.threads;
  evaluation_ = evaluate_final(loop_.distribution(), settings_.loop, final_policy_, sims_, threads, dir_, telemetry_,
                               loop_.timesteps());
  if (evaluation_->stop_signal != 0) return Stop{evaluation_->stop_signal, in_evaluation};
  return std::nullopt;
}

RunResult Session::write_results() {
  rl::save_policy(dir_ / run_file::kPolicy, final_policy_->contents());
  RunResult result = session_result(loop_.timesteps());
  const ResultFile file = final_result(*evaluation_, settings_.loop, loop_.timesteps(), loop_.iteration(),
                                       numerical_failures_, wall_before_s_ + result.wall_s);
  write_result(dir_, file);
  print_result(dir_, file, *evaluation_);
  result.completed = true;
  if (telemetry_.enabled())
    std::printf("codesign: telemetry: %lld messages, %.3f s spent publishing (%.2f %% of this session's wall time)\n",
                static_cast<long long>(result.telemetry_messages), result.telemetry_s,
                100.0 * result.telemetry_s / std::max(result.wall_s, 1e-9));
  return result;
}

RunResult Session::stopped(const Stop& stop) {
  RunResult result = session_result(loop_.timesteps());
  if (stop.signal == 0) return result;
  progress_.end_line();
  std::fflush(stdout);
  print_run_stopped(stop.signal, stop.where, loop_.timesteps(), settings_.loop.codesign.total_timesteps,
                    options_.dir);
  result.stop_signal = stop.signal;
  return result;
}

RunResult Session::session_result(std::int64_t timesteps) const {
  RunResult r;
  r.timesteps = timesteps;
  r.wall_s = elapsed_s();
  r.telemetry_messages = telemetry_.messages();
  r.telemetry_s = telemetry_.seconds();
  return r;
}

}  // namespace

RunResult run_codesign(const RunSettings& settings, const RunOptions& options) {
  // Taken before anything in DIR is looked at: a refused run reads and changes nothing.
  const std::unique_ptr<io::RunLock> own_lock = options.lock ? nullptr : lock_run_folder(options.dir, options.resume);
  Session session(settings, options);
  if (const std::optional<Stop> stop = session.train()) return session.stopped(*stop);
  if (const std::optional<Stop> stop = session.evaluate()) return session.stopped(*stop);
  return session.write_results();
}

}  // namespace codesign::run
