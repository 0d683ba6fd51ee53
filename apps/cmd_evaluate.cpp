// `codesign evaluate --run DIR [--at final|t1|t2] [--designs A-B] [--phases N] [--threads N] [--force] [--plots DIR]`
//
// The deterministic policy of a run's state (its latest checkpoint, or those kept at T1 and T2)
// tested on every design of the range at the pressures that state gives it, ranked, into
// DIR/evaluate/<at>/ (src/run/run_evaluation.hpp). Run the same command again to continue a
// stopped evaluation.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "base/duration_text.hpp"
#include "base/errors.hpp"
#include "run/run_config.hpp"
#include "run/run_evaluation.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "fem/design.hpp"

namespace codesign::app {

namespace {

namespace fs = std::filesystem;

#ifndef CODESIGN_PLOTS_DIR
#define CODESIGN_PLOTS_DIR "plots"
#endif

struct EvaluateCliOptions {
  std::string run;
  std::string at = "final";
  std::string designs;
  int phases = 0;
  int threads = 0;
  bool force = false;
  std::string plots = CODESIGN_PLOTS_DIR;
};

int run_evaluate(const EvaluateCliOptions& o) {
  const fs::path dir(o.run);
  if (!fs::exists(dir / "config.toml"))
    throw InputError(dir.string() + ": has no config.toml; evaluate needs a co-design run folder");
  run::RunEvaluationOptions eo;
  eo.dir = o.run;
  eo.at = o.at;
  run::checkpoint_file_of(o.at);  // a bad --at before the config is read
  if (!o.designs.empty()) std::tie(eo.first_design, eo.last_design) = parse_design_range(o.designs);
  eo.phases = o.phases;
  eo.threads = static_cast<std::size_t>(o.threads);
  eo.force = o.force;
  eo.plots_dir = o.plots;
  const run::RunConfig setup = run::read_run_config((dir / "config.toml").string());
  run::RunSettings s;
  s.spec = setup.spec;
  s.scene = setup.scene;
  s.solver = setup.solver;
  s.loop = {setup.task, setup.codesign, setup.ppo};
  std::printf("evaluate: %s at %s: designs %d..%d, %d plate phases each\n", o.run.c_str(), o.at.c_str(),
              eo.first_design, eo.last_design, o.phases > 0 ? o.phases : setup.codesign.eval_episodes);
  std::fflush(stdout);
  const run::RunEvaluationSummary r = run::evaluate_run(s, eo);
  const auto find = [&](int j) {
    return std::find_if(r.ranking.begin(), r.ranking.end(), [j](const run::RunEvaluationRow& x) { return x.design == j; });
  };
  std::printf("evaluate: t = %lld; %d designs run now, %d before; this call took %s\n", static_cast<long long>(r.t),
              r.designs_run, r.designs_before, duration_text(r.wall_s).c_str());
  std::printf("evaluate: top %zu by test return (mean +- 95 %% interval over the phases):\n",
              std::min<std::size_t>(10, r.ranking.size()));
  for (std::size_t i = 0; i < std::min<std::size_t>(10, r.ranking.size()); ++i) {
    const run::RunEvaluationRow& x = r.ranking[i];
    std::printf("  %3d  %-24s p=[%.4g, %.4g] kPa  %6.2f +- %.2f  q %.4f%s%s\n", x.rank,
                fem::design_label(x.design).c_str(), x.p1_kPa, x.p2_kPa, x.mean_return, x.ci95, x.q,
                x.role.empty() ? "" : "  ", x.role.c_str());
  }
  for (const auto& [j, role] : {std::pair{r.leading_design, "d* (leading design)"}, std::pair{r.runner_up, "runner-up"}}) {
    const auto it = find(j);
    if (j < 0) continue;
    if (it == r.ranking.end())
      std::printf("evaluate: %s %s is outside the evaluated range\n", role, fem::design_label(j).c_str());
    else
      std::printf("evaluate: %s %s ranks %d of %zu: %.2f +- %.2f\n", role, fem::design_label(j).c_str(), it->rank,
                  r.ranking.size(), it->mean_return, it->ci95);
  }
  std::printf("evaluate: wrote %s/ranking.csv%s\n", r.folder.c_str(), r.figure ? " and ranking.png" : "");
  if (!r.figure) std::printf("evaluate: warning: no ranking.png: %s\n", r.figure_message.c_str());
  return 0;
}

}  // namespace

void add_evaluate_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<EvaluateCliOptions>();
  CLI::App* cmd = root.add_subcommand(
      "evaluate", "Test a run's policy (latest state, or at T1 / T2) on every design at its pressures, ranked");
  cmd->add_option("--run", opt->run, "run folder (config.toml and its checkpoints)")->required();
  cmd->add_option("--at", opt->at, "which state: final (checkpoint.bin, default), t1 or t2 (the kept checkpoints)")
      ->check(CLI::IsMember({"final", "t1", "t2"}));
  add_designs_option(*cmd, opt->designs, "all 110");
  cmd->add_option("--phases", opt->phases, "plate phases (episodes) per design (default: the run's eval_episodes)")
      ->check(CLI::Range(2, 100000));
  cmd->add_flag("--force", opt->force, "replace an evaluation of this state made with other settings");
  cmd->add_option("--plots", opt->plots, "folder of evaluate_ranking.gp (default: " CODESIGN_PLOTS_DIR ")");
  add_threads_option(*cmd, opt->threads);
  cmd->callback([opt, &run] { run = [opt] { return run_evaluate(*opt); }; });
}

}  // namespace codesign::app
