// `codesign train-gym --config configs/pendulum.toml [--seed N] [--out DIR] [--force]`
//
// Trains PPO on Pendulum-v1 and evaluates the deterministic policy on seeds disjoint from
// training (run/gym_run.hpp says what the output directory holds).
#include <cstdint>
#include <memory>
#include <string>

#include "commands.hpp"
#include "run/gym_run.hpp"

namespace codesign::app {

namespace {

struct TrainGymCliOptions {
  std::string config;
  std::int64_t seed = 0;
  run::GymRunOptions run;
  const CLI::Option* seed_option = nullptr;
};

}  // namespace

void add_train_gym_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<TrainGymCliOptions>();
  CLI::App* cmd = root.add_subcommand(
      "train-gym", "Train PPO on Pendulum-v1 (re-implemented Gymnasium dynamics) and evaluate it");
  cmd->add_option("--config", opt->config, "TOML config ([env], [ppo], [train])")->required();
  opt->seed_option =
      cmd->add_option("--seed", opt->seed, "Seed, overrides [env] seed (>= 0)");
  cmd->add_option("--out", opt->run.out, "Output directory, overrides [train] output_dir");
  cmd->add_flag("--force", opt->run.force, "Overwrite the results of an earlier run in the directory");
  cmd->callback([&run, opt] {
    run = [opt] {
      run::GymRunOptions o = opt->run;
      if (opt->seed_option->count() > 0) o.seed = opt->seed;
      run::train_gym(opt->config, o);
      return 0;
    };
  });
}

}  // namespace codesign::app
