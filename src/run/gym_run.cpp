#include "run/gym_run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "base/errors.hpp"
#include "base/seconds_since.hpp"
#include "io/config/gym_config.hpp"
#include "rl/pendulum.hpp"
#include "rl/policy_file.hpp"
#include "rl/trainer.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;

constexpr const char* kOutputs[] = {"config.toml", "metrics.csv", "eval.csv",
                                    "policy.cdspol", "summary.txt", "checkpoints"};

void prepare_output_dir(const fs::path& dir, bool force) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(dir.string() + ": output path exists and is not a directory");
  for (const char* name : kOutputs) {
    if (fs::exists(dir / name, ec) && !force)
      throw InputError(dir.string() + ": already holds the results of an earlier run (" +
                           name + "); choose another --out or pass --force to overwrite them");
  }
  if (force) fs::remove_all(dir / "checkpoints", ec);
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create output directory: " + ec.message());
}

std::ofstream open_output(const fs::path& path) {
  std::ofstream f(path, std::ios::trunc);
  if (!f) throw InputError(path.string() + ": cannot write");
  return f;
}

std::string format_duration(double s) {
  char buf[32];
  if (s < 120.0) std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 7200.0) std::snprintf(buf, sizeof buf, "%.1f min", s / 60.0);
  else std::snprintf(buf, sizeof buf, "%.1f h", s / 3600.0);
  return buf;
}

rl::EnvFactory make_env_factory(const io::GymTrainConfig& cfg) {
  // env.name is validated to be "pendulum" by the config reader.
  rl::PendulumConfig p;
  p.max_episode_steps = cfg.max_episode_steps;
  return rl::pendulum_factory(p);
}

// The config at `config_path` with --seed in place of [env] seed. Throws InputError for a negative
// --seed or a seed beyond the last one with evaluation seeds of its own.
io::GymTrainConfig read_gym_config(const std::string& config_path, const GymRunOptions& opt) {
  io::GymTrainConfig cfg = io::load_gym_config(config_path);
  if (opt.seed) {
    if (*opt.seed < 0) throw InputError("--seed: must be >= 0, got " + std::to_string(*opt.seed));
    cfg.trainer.seed = static_cast<std::uint64_t>(*opt.seed);
  }
  if (cfg.trainer.seed > rl::kMaxEvalTrainSeed)
    throw InputError("seed (--seed or [env] seed): value " + std::to_string(cfg.trainer.seed) +
                     " is out of range for train-gym; allowed [0, " +
                     std::to_string(rl::kMaxEvalTrainSeed) +
                     "] (2^43 - 1, the largest seed with disjoint evaluation seeds)");
  return cfg;
}

// Whole rollouts of n_envs x n_steps until total_timesteps is reached.
struct RolloutPlan {
  std::int64_t rollout_steps = 0;
  std::int64_t rollouts = 0;
  std::int64_t total_steps() const { return rollouts * rollout_steps; }
};

RolloutPlan plan_rollouts(const rl::TrainerConfig& tc) {
  const std::int64_t rollout = static_cast<std::int64_t>(tc.n_envs) * tc.ppo.n_steps;
  return {rollout, (tc.total_timesteps + rollout - 1) / rollout};
}

void print_plan(const io::GymTrainConfig& cfg, const RolloutPlan& plan, const fs::path& out) {
  const rl::TrainerConfig& tc = cfg.trainer;
  std::printf("train-gym: %s, %d envs x %d steps per rollout, %lld rollouts (%lld steps), seed %llu"
              " -> %s\n",
              cfg.env_name.c_str(), tc.n_envs, tc.ppo.n_steps, static_cast<long long>(plan.rollouts),
              static_cast<long long>(plan.total_steps()),
              static_cast<unsigned long long>(tc.seed), out.string().c_str());
  std::fflush(stdout);
}

std::ofstream open_metrics(const fs::path& out) {
  std::ofstream metrics = open_output(out / "metrics.csv");
  metrics << "iteration,timesteps,elapsed_s,steps_per_s,collect_s,update_s,episodes,"
             "mean_return,mean_length,pg_loss,value_loss,entropy_loss,approx_kl,clip_fraction,"
             "explained_variance,grad_norm,ent_coef,epochs_done,early_stopped,log_std_mean\n";
  return metrics;
}

// One row of metrics.csv.
std::string metrics_row(const rl::TrainProgress& p, double log_std_mean) {
  const double nan = std::nan("");
  const rl::PpoStats& s = p.stats;
  char row[512];
  std::snprintf(row, sizeof row,
                "%d,%lld,%.3f,%.1f,%.4f,%.4f,%lld,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,"
                "%.6g,%.6g,%d,%d,%.6g\n",
                p.iteration, static_cast<long long>(p.timesteps), p.elapsed_s, p.steps_per_s,
                p.collect_s, p.update_s, static_cast<long long>(p.episodes),
                p.mean_return.value_or(nan), p.mean_length.value_or(nan), s.pg_loss,
                s.value_loss, s.entropy_loss, s.approx_kl, s.clip_fraction,
                s.explained_variance, s.grad_norm, s.ent_coef, s.epochs_done,
                s.early_stopped ? 1 : 0, log_std_mean);
  return row;
}

// The progress line: steps so far, speed, the time left at that speed and the mean return.
void print_progress(const rl::TrainProgress& p, std::int64_t total_steps, std::size_t stats_window) {
  const double eta =
      p.steps_per_s > 0.0 ? static_cast<double>(total_steps - p.timesteps) / p.steps_per_s : 0.0;
  char ret[32] = "n/a";
  if (p.mean_return) std::snprintf(ret, sizeof ret, "%.1f", *p.mean_return);
  std::printf("  steps %8lld/%lld (%3.0f%%)  %7.0f steps/s  ETA %-8s  mean return (last %zu "
              "ep) %s\n",
              static_cast<long long>(p.timesteps), static_cast<long long>(total_steps),
              100.0 * static_cast<double>(p.timesteps) / static_cast<double>(total_steps),
              p.steps_per_s, format_duration(eta).c_str(), stats_window, ret);
  std::fflush(stdout);
}

// Trains until the total timesteps, writing metrics.csv as it goes, a progress line every
// log_every_iterations and a checkpoint every checkpoint_every_iterations (if > 0).
void train(rl::Trainer& trainer, const io::GymTrainConfig& cfg, const RolloutPlan& plan, const fs::path& out) {
  std::ofstream metrics = open_metrics(out);
  if (cfg.checkpoint_every_iterations > 0) fs::create_directories(out / "checkpoints");
  trainer.learn([&](const rl::TrainProgress& p) {
    metrics << metrics_row(p, static_cast<double>(trainer.log_std().mean())) << std::flush;
    if (p.iteration % cfg.log_every_iterations == 0 || trainer.finished())
      print_progress(p, plan.total_steps(), cfg.trainer.stats_window);
    if (cfg.checkpoint_every_iterations > 0 &&
        p.iteration % cfg.checkpoint_every_iterations == 0) {
      rl::save_policy(out / "checkpoints" / ("policy_" + std::to_string(p.timesteps) + ".cdspol"),
                      trainer.policy_contents());
    }
  });
}

// The trained policy's deterministic episodes from `eval_seed` on; with save_policy it is written
// to policy.cdspol and the file evaluated again (a warning if it acts otherwise).
rl::EvalResult evaluate_trained(const rl::Trainer& trainer, const rl::EnvFactory& factory,
                                const io::GymTrainConfig& cfg, std::uint64_t eval_seed, const fs::path& out) {
  // The trained policy as its file's reader acts (one Policy::Episode per episode: a recurrent
  // policy starts each from a zero state).
  const rl::Policy trained(trainer.policy_contents());
  rl::EvalResult eval = rl::evaluate(trained, factory, cfg.eval_episodes, eval_seed);
  if (cfg.save_policy) {
    const fs::path policy_path = out / "policy.cdspol";
    rl::save_policy(policy_path, trained.contents());
    // The file must reproduce the evaluation exactly (same float32 weights, same arithmetic).
    const rl::Policy policy = rl::Policy::load(policy_path);
    const rl::EvalResult again = rl::evaluate(policy, factory, cfg.eval_episodes, eval_seed);
    if (again.returns != eval.returns)
      std::fprintf(stderr, "train-gym: warning: the saved policy evaluates to %.3f, the trained "
                           "model to %.3f\n", again.mean_return, eval.mean_return);
  }
  return eval;
}

void write_eval_csv(const rl::EvalResult& eval, std::uint64_t eval_seed, const fs::path& out) {
  std::ofstream eval_csv = open_output(out / "eval.csv");
  eval_csv << "episode,seed,return,length\n";
  for (std::size_t k = 0; k < eval.returns.size(); ++k) {
    char row[128];
    std::snprintf(row, sizeof row, "%zu,%llu,%.6f,%d\n", k,
                  static_cast<unsigned long long>(eval_seed + k), eval.returns[k],
                  eval.lengths[k]);
    eval_csv << row;
  }
}

// What summary.txt and the closing line report.
struct RunSummary {
  std::uint64_t eval_seed = 0;
  double train_s = 0.0, wall_s = 0.0;
};

void write_summary(const rl::Trainer& trainer, const io::GymTrainConfig& cfg, const rl::EvalResult& eval,
                   const RunSummary& run, const fs::path& out) {
  std::ofstream summary = open_output(out / "summary.txt");
  char text[1024];
  std::snprintf(text, sizeof text,
                "env = %s\nseed = %llu\ntimesteps = %lld\nepisodes = %lld\n"
                "eval_episodes = %d\neval_seed_first = %llu\neval_seed_last = %llu\n"
                "eval_mean_return = %.3f\n"
                "eval_std_return = %.3f\ntrain_wall_s = %.3f\nwall_s = %.3f\n",
                cfg.env_name.c_str(), static_cast<unsigned long long>(cfg.trainer.seed),
                static_cast<long long>(trainer.num_timesteps()),
                static_cast<long long>(trainer.num_episodes()), cfg.eval_episodes,
                static_cast<unsigned long long>(run.eval_seed),
                static_cast<unsigned long long>(run.eval_seed + eval.returns.size() - 1),
                eval.mean_return, eval.std_return,
                run.train_s, run.wall_s);
  summary << text;
}

void print_final(const io::GymTrainConfig& cfg, const rl::EvalResult& eval, const RunSummary& run,
                 const fs::path& out) {
  std::printf("final eval: mean return %.1f ± %.1f (population std) over %d deterministic "
              "episodes, seeds %llu..%llu\n"
              "wall time %.1f s (training %.1f s); results in %s\n",
              eval.mean_return, eval.std_return, cfg.eval_episodes,
              static_cast<unsigned long long>(run.eval_seed),
              static_cast<unsigned long long>(run.eval_seed + eval.returns.size() - 1), run.wall_s,
              run.train_s, out.string().c_str());
}

}  // namespace

void train_gym(const std::string& config_path, const GymRunOptions& opt) {
  const auto t_start = std::chrono::steady_clock::now();
  const io::GymTrainConfig cfg = read_gym_config(config_path, opt);
  const fs::path out = opt.out.empty() ? fs::path(cfg.output_dir) : fs::path(opt.out);
  prepare_output_dir(out, opt.force);
  fs::copy_file(config_path, out / "config.toml", fs::copy_options::overwrite_existing);

  const rl::EnvFactory factory = make_env_factory(cfg);
  const RolloutPlan plan = plan_rollouts(cfg.trainer);
  print_plan(cfg, plan, out);
  rl::Trainer trainer(factory, cfg.trainer);
  train(trainer, cfg, plan, out);

  RunSummary run;
  run.train_s = seconds_since(t_start);
  run.eval_seed = rl::eval_seed_first(cfg.trainer.seed, cfg.eval_episodes);
  const rl::EvalResult eval = evaluate_trained(trainer, factory, cfg, run.eval_seed, out);
  write_eval_csv(eval, run.eval_seed, out);
  run.wall_s = seconds_since(t_start);
  write_summary(trainer, cfg, eval, run, out);
  print_final(cfg, eval, run, out);
}

}  // namespace codesign::run
