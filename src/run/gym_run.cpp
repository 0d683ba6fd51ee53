#include "run/gym_run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "base/errors.hpp"
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

}  // namespace

void train_gym(const std::string& config_path, const GymRunOptions& opt) {
  const auto t_start = std::chrono::steady_clock::now();
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
  const fs::path out = opt.out.empty() ? fs::path(cfg.output_dir) : fs::path(opt.out);
  prepare_output_dir(out, opt.force);
  fs::copy_file(config_path, out / "config.toml", fs::copy_options::overwrite_existing);

  const rl::EnvFactory factory = make_env_factory(cfg);
  const rl::TrainerConfig& tc = cfg.trainer;
  const std::int64_t rollout = static_cast<std::int64_t>(tc.n_envs) * tc.ppo.n_steps;
  const std::int64_t rollouts = (tc.total_timesteps + rollout - 1) / rollout;
  std::printf("train-gym: %s, %d envs x %d steps per rollout, %lld rollouts (%lld steps), seed %llu"
              " -> %s\n",
              cfg.env_name.c_str(), tc.n_envs, tc.ppo.n_steps, static_cast<long long>(rollouts),
              static_cast<long long>(rollouts * rollout),
              static_cast<unsigned long long>(tc.seed), out.string().c_str());
  std::fflush(stdout);

  rl::Trainer trainer(factory, tc);
  std::ofstream metrics = open_output(out / "metrics.csv");
  metrics << "iteration,timesteps,elapsed_s,steps_per_s,collect_s,update_s,episodes,"
             "mean_return,mean_length,pg_loss,value_loss,entropy_loss,approx_kl,clip_fraction,"
             "explained_variance,grad_norm,ent_coef,epochs_done,early_stopped,log_std_mean\n";
  if (cfg.checkpoint_every_iterations > 0) fs::create_directories(out / "checkpoints");

  trainer.learn([&](const rl::TrainProgress& p) {
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
                  s.early_stopped ? 1 : 0,
                  static_cast<double>(trainer.log_std().mean()));
    metrics << row << std::flush;

    const bool last = trainer.finished();
    if (p.iteration % cfg.log_every_iterations == 0 || last) {
      const double eta = p.steps_per_s > 0.0 ? static_cast<double>(rollouts * rollout -
                                                                   p.timesteps) /
                                                   p.steps_per_s
                                             : 0.0;
      char ret[32] = "n/a";
      if (p.mean_return) std::snprintf(ret, sizeof ret, "%.1f", *p.mean_return);
      std::printf("  steps %8lld/%lld (%3.0f%%)  %7.0f steps/s  ETA %-8s  mean return (last %zu "
                  "ep) %s\n",
                  static_cast<long long>(p.timesteps), static_cast<long long>(rollouts * rollout),
                  100.0 * static_cast<double>(p.timesteps) /
                      static_cast<double>(rollouts * rollout),
                  p.steps_per_s, format_duration(eta).c_str(), tc.stats_window, ret);
      std::fflush(stdout);
    }
    if (cfg.checkpoint_every_iterations > 0 &&
        p.iteration % cfg.checkpoint_every_iterations == 0) {
      rl::save_policy(out / "checkpoints" / ("policy_" + std::to_string(p.timesteps) + ".cdspol"),
                      trainer.policy_contents());
    }
  });
  const double train_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

  const std::uint64_t eval_seed = rl::eval_seed_first(tc.seed, cfg.eval_episodes);
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

  std::ofstream eval_csv = open_output(out / "eval.csv");
  eval_csv << "episode,seed,return,length\n";
  for (std::size_t k = 0; k < eval.returns.size(); ++k) {
    char row[128];
    std::snprintf(row, sizeof row, "%zu,%llu,%.6f,%d\n", k,
                  static_cast<unsigned long long>(eval_seed + k), eval.returns[k],
                  eval.lengths[k]);
    eval_csv << row;
  }

  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  std::ofstream summary = open_output(out / "summary.txt");
  char text[1024];
  std::snprintf(text, sizeof text,
                "env = %s\nseed = %llu\ntimesteps = %lld\nepisodes = %lld\n"
                "eval_episodes = %d\neval_seed_first = %llu\neval_seed_last = %llu\n"
                "eval_mean_return = %.3f\n"
                "eval_std_return = %.3f\ntrain_wall_s = %.3f\nwall_s = %.3f\n",
                cfg.env_name.c_str(), static_cast<unsigned long long>(tc.seed),
                static_cast<long long>(trainer.num_timesteps()),
                static_cast<long long>(trainer.num_episodes()), cfg.eval_episodes,
                static_cast<unsigned long long>(eval_seed),
                static_cast<unsigned long long>(eval_seed + eval.returns.size() - 1),
                eval.mean_return, eval.std_return,
                train_s, wall_s);
  summary << text;
  std::printf("final eval: mean return %.1f ± %.1f (population std) over %d deterministic "
              "episodes, seeds %llu..%llu\n"
              "wall time %.1f s (training %.1f s); results in %s\n",
              eval.mean_return, eval.std_return, cfg.eval_episodes,
              static_cast<unsigned long long>(eval_seed),
              static_cast<unsigned long long>(eval_seed + eval.returns.size() - 1), wall_s,
              train_s, out.string().c_str());
}

}  // namespace codesign::run
