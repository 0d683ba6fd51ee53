#pragma once
// `codesign verify --run RUN` (docs/verify.md): a certificate of a finished co-design run for the
// robot it is meant for. This part tests the run's final policy on d* at p* under a fixed suite
// of held-out physics — nominal; Young's modulus ±20 %; the refined mesh; plate amplitude ×0.5
// and ×1.5; strain gain ±10 %; strain noise — each over `phases` test plate phases
// 2π(k + ½)/phases, and writes RUN/verify/: conditions.csv (a row per condition, appended as each
// finishes, so a stopped verify resumes), verify.toml (what was verified) and report.md.
#include <cstddef>
#include <string>
#include <vector>

#include "core/physics_randomization.hpp"

namespace codesign::run {

struct VerifyOptions {
  std::string dir;          // the run folder
  int phases = 100;         // test episodes per condition
  std::size_t threads = 0;  // 0: all cores
  bool force = false;       // replace a verify of the run made with other settings
  bool progress = true;
};

// One held-out condition: a physics draw applied to every test episode, or the refined mesh.
struct VerifyCondition {
  std::string name;
  std::string what;  // one line for the report
  core::PhysicsDraw physics;
  bool refined_mesh = false;
};
// The suite, in the order the report lists it.
std::vector<VerifyCondition> verify_suite();

struct VerifyRow {
  std::string condition;
  double mean_return = 0.0, std_return = 0.0, ci95 = 0.0, band_fraction = 0.0;
  int episodes = 0;
};

struct VerifySummary {
  std::string folder;           // RUN/verify
  int design = 0;               // d*
  double p1_kPa = 0.0, p2_kPa = 0.0;
  std::vector<VerifyRow> rows;  // in suite order
  int conditions_run = 0, conditions_before = 0;
};

// Throws InputError naming the file: no run folder, config.toml, result.toml or policy.bin; a
// folder holding a verify with other settings (without force).
VerifySummary verify_run(const VerifyOptions& options);

}  // namespace codesign::run
