#pragma once
// `codesign sim` (docs/physics.md): the open-loop scenario of [sim] (core::run_open_loop_scenario)
// on a fresh simulator, recorded in a folder DIR:
//   DIR/trace.csv         t, theta (rad), F_mN, eps, tip_x, tip_y, tip_z (mm, world), plate_z,
//                         status: after the settle and after every step
//   DIR/frame_NNNNNN.vtu  ParaView frames of the deformed body (world positions, axial strain per
//                         tet) after the settle (000000) and every N steps (N > 0)
#include <string>

#include "run/run_config.hpp"

namespace codesign::run {

struct SimRunOptions {
  std::string out = "runs/sim";  // DIR
  int vtk_every = -1;            // -1: [sim] vtk_every
  bool force = false;            // overwrite an earlier trace.csv
};

// Runs and records the scenario and prints a summary. Returns 0, or 3 when a numerical failure
// ended the scenario early (its row carries the status; the reason is printed on stderr).
// Throws InputError, before any step, if DIR holds trace.csv and `force` is off, or cannot be
// created.
int run_sim(const RunConfig& config, const SimRunOptions& options);

}  // namespace codesign::run
