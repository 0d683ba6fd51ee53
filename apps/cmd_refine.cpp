// `codesign refine --run DIR [--phases N] [--starts N] [--max-evals N] [--method M] [--threads N]`
//
// Polishes p* of a finished co-design run (src/codesign/refine.hpp): reads DIR/config.toml (the
// resolved config), DIR/policy.bin and DIR/result.toml's [best]; keeps the policy and j* fixed;
// NLopt searches p in [0, p_max] (p2 = 0 for one chamber) on tuning phases; tests p* before and
// after on the run's evaluation phases; appends a [refined] table to DIR/result.toml, leaving the
// rest of the file byte for byte as it was.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "base/errors.hpp"
#include "codesign/policy_controller.hpp"
#include "codesign/refine.hpp"
#include "run/run.hpp"
#include "run/run_config.hpp"
#include "run/run_folder.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "io/run_lock.hpp"
#include "rl/policy_file.hpp"

namespace codesign::app {

namespace {

namespace fs = std::filesystem;

struct RefineCliOptions {
  std::string run;
  int phases = 4;
  int starts = 2;
  int max_evals = 20;
  std::string method = "bobyqa";
  int threads = 0;
};

int run_refine(const RefineCliOptions& o) {
  const fs::path dir(o.run);
  // It rewrites DIR/result.toml: not while a run writes the folder.
  const std::unique_ptr<io::RunLock> lock = run::lock_run_folder(o.run, /*only_if_exists=*/true);
  for (const char* f : {run::run_file::kConfig, run::run_file::kPolicy, run::run_file::kResult})
    if (!fs::exists(dir / f))
      throw InputError(dir.string() + ": has no " + f + "; refine needs a finished co-design run folder");
  const run::RunConfig setup = run::read_run_config((dir / run::run_file::kConfig).string());
  const std::string result_path = (dir / run::run_file::kResult).string();
  const std::optional<run::ResultDesign> best =
      run::read_result_design(dir, "best", setup.task.pressure_max_kPa);
  if (!best) throw InputError(result_path + ": has no [best] design");
  const int design = best->setup.design;
  const std::vector<double> p{best->setup.p1_kPa, best->setup.p2_kPa};
  const std::shared_ptr<const rl::Policy> loaded = coopt::load_task_policy(dir / run::run_file::kPolicy, setup.task);
  coopt::RefineConfig rc;
  rc.tuning_phases = o.phases;
  rc.test_episodes = setup.codesign.eval_episodes;
  rc.search.method = coopt::local_method_from_name(o.method);
  rc.search.starts = o.starts;
  rc.search.max_evals = o.max_evals;
  if (rc.search.max_evals < rc.search.starts)
    throw InputError("--max-evals: " + std::to_string(o.max_evals) + " is below --starts (" +
                     std::to_string(o.starts) + "); allowed [starts, 10000]");
  auto sims = std::make_shared<coopt::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  const coopt::ControllerFactory pi = coopt::policy_factory(loaded);  // one controller per episode
  std::printf("refine: %s: j%d, p* = [%g, %g] kPa; NLopt %s, %d starts, %d evaluations of %d tuning phases; "
              "test on the run's %d evaluation phases\n",
              dir.string().c_str(), design, p[0], p[1], o.method.c_str(), o.starts, o.max_evals, o.phases,
              rc.test_episodes);
  std::fflush(stdout);
  const coopt::RefineResult r =
      coopt::refine_pressures(pi, sims, setup.task, design, {p[0], p[1]}, rc, static_cast<std::size_t>(o.threads));
  std::printf("refine: before p = [%.4g, %.4g] kPa: tuning return %.2f; test return %.2f +- %.2f over %zu episodes\n",
              r.p_before[0], r.p_before[1], r.tuning_before, r.test_before.mean_return, r.test_before.std_return,
              r.test_before.returns.size());
  std::printf("refine: after  p = [%.4g, %.4g] kPa: tuning return %.2f; test return %.2f +- %.2f over %zu episodes "
              "(%d evaluations)\n",
              r.p_after[0], r.p_after[1], r.tuning_after, r.test_after.mean_return, r.test_after.std_return,
              r.test_after.returns.size(), r.evaluations);
  run::write_refined_result(dir, r);
  std::printf("refine: wrote [refined] into %s\n", result_path.c_str());
  return 0;
}

}  // namespace

void add_refine_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<RefineCliOptions>();
  CLI::App* cmd = root.add_subcommand("refine", "Polish p* of a finished co-design run with NLopt (policy, j* fixed)");
  cmd->add_option("--run", opt->run, "run folder (config.toml, policy.bin, result.toml)")->required();
  cmd->add_option("--phases", opt->phases, "tuning plate phases per evaluation (default 4)")->check(CLI::Range(1, 1000));
  cmd->add_option("--starts", opt->starts, "NLopt starts (default 2)")->check(CLI::Range(1, 100));
  cmd->add_option("--max-evals", opt->max_evals, "evaluations over all starts (default 20)")
      ->check(CLI::Range(1, 10000));
  cmd->add_option("--method", opt->method, "bobyqa (default), cobyla, neldermead or sbplx")
      ->check(CLI::IsMember({"bobyqa", "cobyla", "neldermead", "sbplx"}));
  add_threads_option(*cmd, opt->threads);
  cmd->callback([opt, &run] { run = [opt] { return run_refine(*opt); }; });
}

}  // namespace codesign::app
