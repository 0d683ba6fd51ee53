// `codesign render`: PNG frames of any design, pressure and controller (docs/rendering.md).
//
//   codesign render --run runs/NAME -o DIR [--which best|runner_up|both]
//       the first evaluation episode of d* / the runner-up (both: side by side) with the run's
//       final policy, from the run folder's config.toml, result.toml and policy.bin
//   codesign render --config run.toml -o DIR [--design J] [--pressures P1,P2] [--policy FILE]
//                   [--phase-deg X] [--compare J [--compare-pressures P1,P2]]
//       one episode of the whisker task (design and pressures default to [sim]; without
//       --policy the base is held still), optionally beside a second design
//   codesign render --config run.toml -o DIR --sim [--compare J]
//       the open-loop [sim] scenario of `codesign sim` (its θ schedule), re-simulated
//   size and camera: --width --height --azimuth --elevation --fov --zoom, frames: --every N;
//   defaults from the config's [render] table.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "codesign/evaluation.hpp"
#include "codesign/policy_controller.hpp"
#include "commands.hpp"
#include "fem/design.hpp"
#include "io/run_lock.hpp"
#include "run/episode_render.hpp"
#include "run/run.hpp"
#include "run/run_config.hpp"
#include "run/run_folder.hpp"

namespace codesign::app {

namespace {

namespace fs = std::filesystem;

struct RenderCliOptions {
  std::string config, run, out, which = "best", policy;
  std::optional<int> design, compare;
  std::vector<double> pressures, compare_pressures;
  std::optional<double> phase_deg;
  bool sim = false, force = false;
  std::optional<int> width, height, every;
  std::optional<double> azimuth, elevation, fov, zoom;
};

void check_pressures(const std::vector<double>& p, const char* flag, double pmax) {
  if (p.empty()) return;
  if (p.size() != 2) throw InputError(std::string("command line: ") + flag + ": give two pressures P1,P2 in kPa");
  for (double v : p)
    if (!(v >= 0.0 && v <= pmax))
      throw InputError(std::string("command line: ") + flag + ": pressure " + std::to_string(v) +
                       " kPa is out of range; allowed [0, " + std::to_string(pmax) + "]");
}

int run_render(const RenderCliOptions& o) {
  if (o.config.empty() == o.run.empty()) throw InputError("command line: give exactly one of --config and --run");
  const fs::path run_dir(o.run);
  const std::string config = o.run.empty() ? o.config : (run_dir / "config.toml").string();
  const run::RunConfig setup = run::read_run_config(config);
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
  const std::unique_ptr<io::RunLock> lock = o.run.empty() ? nullptr : run::lock_run_folder_for_output(o.run, o.out);
  // Refuse before simulating (write_frames checks again before writing).
  std::error_code ec;
  if (!o.force && fs::exists(fs::path(o.out) / "frame_0000.png", ec))
    throw InputError(o.out + ": already holds frame_0000.png of an earlier render; choose another folder or pass "
                     "--force");

  auto sims = std::make_shared<coopt::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  const coopt::TaskConfig& task = setup.task;
  const int eval_n = setup.codesign.eval_episodes;
  const double phase = o.phase_deg ? *o.phase_deg * std::numbers::pi / 180.0 : coopt::evaluation_phase(0, eval_n);
  std::vector<std::vector<run::RecordedFrame>> seqs;
  if (!o.run.empty()) {
    const std::shared_ptr<const rl::Policy> policy =
        coopt::load_task_policy(o.policy.empty() ? run_dir / run::run_file::kPolicy : fs::path(o.policy), task);
    std::vector<std::string> whiches;
    if (o.which == "both")
      whiches = {"best", "runner_up"};
    else
      whiches = {o.which};
    for (const std::string& w : whiches) {
      const std::optional<run::ResultDesign> result = run::read_result_design(run_dir, w);
      if (!result)
        throw InputError((run_dir / run::run_file::kResult).string() + ": has no [" + w + "] design");
      coopt::EpisodeSetup s = result->setup;
      s.plate_phase_rad = phase;
      seqs.push_back(run::record_episode(sims, task, s, coopt::episode_controller(policy), rc.every_steps,
                                           (w == "best" ? "d*: " : "runner-up: ") +
                                               run::design_title(s.design, s.p1_kPa, s.p2_kPa)));
    }
  } else {
    const std::shared_ptr<const rl::Policy> policy = o.policy.empty() ? nullptr : coopt::load_task_policy(o.policy, task);
    const io::SimScenario& sc = setup.scenario;
    std::vector<std::pair<int, std::vector<double>>> designs;
    designs.push_back({o.design.value_or(sc.design), o.pressures.empty() ? sc.pressures_kPa : o.pressures});
    if (o.compare)
      designs.push_back({*o.compare, o.compare_pressures.empty() ? designs[0].second : o.compare_pressures});
    for (const auto& [j, p] : designs) {
      if (j < 0 || j >= fem::kDesignCount)
        throw InputError("command line: design " + std::to_string(j) + " is out of range; allowed [0, " +
                         std::to_string(fem::kDesignCount - 1) + "]");
      const std::string title = run::design_title(j, p[0], p[1]);
      if (o.sim) {
        io::SimScenario s = sc;
        s.design = j;
        s.pressures_kPa = p;
        seqs.push_back(run::record_scenario(sims, task, s, rc.every_steps, "sim: " + title));
      } else {
        coopt::EpisodeSetup s{j, p[0], p[1], phase, 0.0};
        seqs.push_back(run::record_episode(sims, task, s,
                                             policy ? coopt::episode_controller(policy) : coopt::Controller{},
                                             rc.every_steps,
                                             (o.policy.empty() ? "base held: " : "policy: ") + title));
      }
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  const int n = run::write_frames(o.out, seqs, rc, o.force);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("render: %d frames (%dx%d, %zu panel%s) in %.2f s (%.1f frames/s incl. PNG) -> %s\n", n, rc.width,
              rc.height, seqs.size(), seqs.size() > 1 ? "s" : "", s, n / std::max(s, 1e-9), o.out.c_str());
  return 0;
}

}  // namespace

void add_render_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<RenderCliOptions>();
  CLI::App* cmd = root.add_subcommand("render", "Render an episode (or two side by side) as numbered PNG frames");
  cmd->add_option("--config", opt->config, "run config (TOML): simulator, [task], [sim], [render]");
  cmd->add_option("--run", opt->run, "a finished run folder: render its d* / runner-up with its policy");
  cmd->add_option("-o,--out", opt->out, "output folder for frame_NNNN.png and frames.csv")->required();
  cmd->add_option("--which", opt->which, "with --run: best, runner_up, or both (side by side)")
      ->check(CLI::IsMember({"best", "runner_up", "both"}));
  cmd->add_option("--design", opt->design, "design index j (default [sim] design)");
  cmd->add_option("--pressures", opt->pressures, "chamber pressures P1,P2 in kPa (default [sim] pressures_kPa)")
      ->delimiter(',');
  cmd->add_option("--policy", opt->policy, "policy file (policy.bin) driving the base; default: base held still");
  cmd->add_option("--phase-deg", opt->phase_deg, "plate phase in degrees (default: the first evaluation episode's)")
      ->check(CLI::Range(-360.0, 360.0));
  cmd->add_option("--compare", opt->compare, "a second design j, rendered beside the first");
  cmd->add_option("--compare-pressures", opt->compare_pressures, "its pressures P1,P2 in kPa (default: the first's)")
      ->delimiter(',');
  cmd->add_flag("--sim", opt->sim, "re-simulate the open-loop [sim] scenario of `codesign sim` instead of the task");
  cmd->add_option("--width", opt->width, "image width in pixels [64, 4096]");
  cmd->add_option("--height", opt->height, "image height in pixels [64, 4096]");
  cmd->add_option("--azimuth", opt->azimuth, "camera azimuth in degrees (0: looking along +y)");
  cmd->add_option("--elevation", opt->elevation, "camera elevation in degrees");
  cmd->add_option("--fov", opt->fov, "vertical field of view in degrees");
  cmd->add_option("--zoom", opt->zoom, "> 1: closer than the automatic framing");
  cmd->add_option("--every", opt->every, "a frame every N simulation steps");
  cmd->add_flag("--force", opt->force, "replace the frames of an earlier render in the output folder");
  cmd->callback([opt, &run] { run = [opt] { return run_render(*opt); }; });
}

}  // namespace codesign::app
