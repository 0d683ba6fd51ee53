#include "run/refine_run.hpp"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "base/errors.hpp"
#include "core/policy_controller.hpp"
#include "core/refine.hpp"
#include "io/formats/run_lock.hpp"
#include "rl/policy_file.hpp"
#include "run/folder_lock.hpp"
#include "run/run_config.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

namespace fs = std::filesystem;

void refine_run(const RefineRunOptions& o) {
  const fs::path dir(o.run);
  // It rewrites DIR/result.toml: not while a run writes the folder.
  const std::unique_ptr<io::RunLock> lock = lock_run_folder(o.run, /*only_if_exists=*/true);
  for (const char* f : {run_file::kConfig, run_file::kPolicy, run_file::kResult})
    if (!fs::exists(dir / f))
      throw InputError(dir.string() + ": has no " + f + "; refine needs a finished co-design run folder");
  const RunConfig setup = read_run_config((dir / run_file::kConfig).string());
  const std::string result_path = (dir / run_file::kResult).string();
  const std::optional<ResultDesign> best = read_result_design(dir, "best", setup.task.pressure_max_kPa);
  if (!best) throw InputError(result_path + ": has no [best] design");
  const int design = best->setup.design;
  const std::vector<double> p{best->setup.p1_kPa, best->setup.p2_kPa};
  const std::shared_ptr<const rl::Policy> loaded = core::load_task_policy(dir / run_file::kPolicy, setup.task);
  core::RefineConfig rc;
  rc.tuning_phases = o.phases;
  rc.test_episodes = setup.codesign.eval_episodes;
  rc.search.method = core::local_method_from_name(o.method);
  rc.search.starts = o.starts;
  rc.search.max_evals = o.max_evals;
  if (rc.search.max_evals < rc.search.starts)
    throw InputError("--max-evals: " + std::to_string(o.max_evals) + " is below --starts (" +
                     std::to_string(o.starts) + "); allowed [starts, 10000]");
  auto sims = std::make_shared<core::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  const core::ControllerFactory pi = core::policy_factory(loaded);  // one controller per episode
  std::printf("refine: %s: j%d, p* = [%g, %g] kPa; NLopt %s, %d starts, %d evaluations of %d tuning phases; "
              "test on the run's %d evaluation phases\n",
              dir.string().c_str(), design, p[0], p[1], o.method.c_str(), o.starts, o.max_evals, o.phases,
              rc.test_episodes);
  std::fflush(stdout);
  const core::RefineResult r =
      core::refine_pressures(pi, sims, setup.task, design, {p[0], p[1]}, rc, static_cast<std::size_t>(o.threads));
  std::printf("refine: before p = [%.4g, %.4g] kPa: tuning return %.2f; test return %.2f +- %.2f over %zu episodes\n",
              r.p_before[0], r.p_before[1], r.tuning_before, r.test_before.mean_return, r.test_before.std_return,
              r.test_before.returns.size());
  std::printf("refine: after  p = [%.4g, %.4g] kPa: tuning return %.2f; test return %.2f +- %.2f over %zu episodes "
              "(%d evaluations)\n",
              r.p_after[0], r.p_after[1], r.tuning_after, r.test_after.mean_return, r.test_after.std_return,
              r.test_after.returns.size(), r.evaluations);
  write_refined_result(dir, r);
  std::printf("refine: wrote [refined] into %s\n", result_path.c_str());
}

}  // namespace codesign::run
