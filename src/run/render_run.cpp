#include "run/render_run.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>

#include "base/errors.hpp"
#include "core/evaluation.hpp"
#include "core/policy_controller.hpp"
#include "fem/design.hpp"
#include "io/formats/run_lock.hpp"
#include "rl/policy_file.hpp"
#include "run/episode_render.hpp"
#include "run/folder_lock.hpp"
#include "run/run_config.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;

void check_pressures(const std::vector<double>& p, const char* flag, double pmax) {
  if (p.empty()) return;
  if (p.size() != 2) throw InputError(std::string("command line: ") + flag + ": give two pressures P1,P2 in kPa");
  for (double v : p)
    if (!(v >= 0.0 && v <= pmax))
      throw InputError(std::string("command line: ") + flag + ": pressure " + std::to_string(v) +
                       " kPa is out of range; allowed [0, " + std::to_string(pmax) + "]");
}

}  // namespace

void render_frames(const RenderRunOptions& o) {
  if (o.config.empty() == o.run.empty()) throw InputError("command line: give exactly one of --config and --run");
  const fs::path run_dir(o.run);
  const std::string config = o.run.empty() ? o.config : (run_dir / run_file::kConfig).string();
  const RunConfig setup = read_run_config(config);
  io::RenderConfig rc = setup.render;
  if (o.width) rc.width = *o.width;
  if (o.height) rc.height = *o.height;
  if (o.every) rc.every_steps = *o.every;
  if (o.azimuth) rc.azimuth_deg = *o.azimuth;
  if (o.elevation) rc.elevation_deg = *o.elevation;
  if (o.fov) rc.fov_deg = *o.fov;
  if (o.zoom) rc.zoom = *o.zoom;
  rc.validate("command line");
  const double pmax = setup.task.pressure_max_kPa;
  check_pressures(o.pressures, "--pressures", pmax);
  check_pressures(o.compare_pressures, "--compare-pressures", pmax);
  if (o.sim && !o.policy.empty()) throw InputError("command line: --sim replays the [sim] scenario; it takes no --policy");
  if (!o.run.empty() && (o.sim || o.design || o.compare || !o.pressures.empty()))
    throw InputError("command line: with --run the designs come from result.toml; --design, --pressures, "
                     "--compare and --sim go with --config");

  // Frames written into a run folder: not while a run writes it.
  const std::unique_ptr<io::RunLock> lock = o.run.empty() ? nullptr : lock_run_folder_for_output(o.run, o.out);
  // Refuse before simulating (write_frames checks again before writing).
  std::error_code ec;
  if (!o.force && fs::exists(fs::path(o.out) / "frame_0000.png", ec))
    throw InputError(o.out + ": already holds frame_0000.png of an earlier render; choose another folder or pass "
                     "--force");

  auto sims = std::make_shared<core::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  const core::TaskConfig& task = setup.task;
  const int eval_n = setup.codesign.eval_episodes;
  const double phase = o.phase_deg ? *o.phase_deg * std::numbers::pi / 180.0 : core::evaluation_phase(0, eval_n);
  std::vector<std::vector<RecordedFrame>> seqs;
  if (!o.run.empty()) {
    const std::shared_ptr<const rl::Policy> policy =
        core::load_task_policy(o.policy.empty() ? run_dir / run_file::kPolicy : fs::path(o.policy), task);
    std::vector<std::string> whiches;
    if (o.which == "both")
      whiches = {"best", "runner_up"};
    else
      whiches = {o.which};
    for (const std::string& w : whiches) {
      const std::optional<ResultDesign> result = read_result_design(run_dir, w);
      if (!result)
        throw InputError((run_dir / run_file::kResult).string() + ": has no [" + w + "] design");
      core::EpisodeSetup s = result->setup;
      s.plate_phase_rad = phase;
      seqs.push_back(record_episode(sims, task, s, core::episode_controller(policy), rc.every_steps,
                                    (w == "best" ? "d*: " : "runner-up: ") +
                                        design_title(s.design, s.p1_kPa, s.p2_kPa)));
    }
  } else {
    const std::shared_ptr<const rl::Policy> policy = o.policy.empty() ? nullptr : core::load_task_policy(o.policy, task);
    const fem::SimScenario& sc = setup.scenario;
    std::vector<std::pair<int, std::vector<double>>> designs;
    designs.push_back({o.design.value_or(sc.design), o.pressures.empty() ? sc.pressures_kPa : o.pressures});
    if (o.compare)
      designs.push_back({*o.compare, o.compare_pressures.empty() ? designs[0].second : o.compare_pressures});
    for (const auto& [j, p] : designs) {
      if (j < 0 || j >= fem::kDesignCount)
        throw InputError("command line: design " + std::to_string(j) + " is out of range; allowed [0, " +
                         std::to_string(fem::kDesignCount - 1) + "]");
      const std::string title = design_title(j, p[0], p[1]);
      if (o.sim) {
        fem::SimScenario s = sc;
        s.design = j;
        s.pressures_kPa = p;
        seqs.push_back(record_scenario(sims, task, s, rc.every_steps, "sim: " + title));
      } else {
        core::EpisodeSetup s{j, p[0], p[1], phase, 0.0};
        seqs.push_back(record_episode(sims, task, s,
                                      policy ? core::episode_controller(policy) : core::Controller{},
                                      rc.every_steps, (o.policy.empty() ? "base held: " : "policy: ") + title));
      }
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  const int n = write_frames(o.out, seqs, rc, o.force);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("render: %d frames (%dx%d, %zu panel%s) in %.2f s (%.1f frames/s incl. PNG) -> %s\n", n, rc.width,
              rc.height, seqs.size(), seqs.size() > 1 ? "s" : "", s, n / std::max(s, 1e-9), o.out.c_str());
}

}  // namespace codesign::run
