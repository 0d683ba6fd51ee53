#pragma once
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
#include <optional>
#include <string>
#include <vector>

namespace codesign::run {

// The flags of `codesign render`, as given (unset: the config's value).
struct RenderRunOptions {
  std::string config, run, out, which = "best", policy;
  std::optional<int> design, compare;
  std::vector<double> pressures, compare_pressures;
  std::optional<double> phase_deg;
  bool sim = false, force = false;
  std::optional<int> width, height, every;
  std::optional<double> azimuth, elevation, fov, zoom;
};

// Checks the options against each other and the config (exactly one of config and run; no
// --sim with a policy; pressures in [0, p_max]; a design in [0, 109]; an output folder without
// earlier frames unless force), then records the episodes and writes the frames
// (episode_render.hpp). Bad input is an InputError naming the flag before any episode.
void render_frames(const RenderRunOptions& options);

}  // namespace codesign::run
