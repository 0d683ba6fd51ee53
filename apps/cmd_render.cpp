// `codesign render`: PNG frames of any design, pressure and controller (docs/rendering.md,
// run/render_run.hpp).
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
#include <memory>

#include "commands.hpp"
#include "run/render_run.hpp"

namespace codesign::app {

void add_render_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<run::RenderRunOptions>();
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
  cmd->callback([opt, &run] {
    run = [opt] {
      run::render_frames(*opt);
      return 0;
    };
  });
}

}  // namespace codesign::app
