#pragma once
// `codesign verify --run RUN` (docs/verify.md): a certificate of a finished co-design run for the
// robot it is meant for. The run's final policy on d* at p*, on the runner-up, on the next designs
// of the run's own order and on two bodies outside that group (verify_subjects.hpp), on the d* of
// other runs (`with`), and two PIDs on d* tuned on nominal tuning phases — each under a fixed
// suite of held-out physics: nominal; Young's modulus ±20 %; the refined mesh; plate amplitude
// ×0.5 and ×1.5; strain gain ±10 %; strain noise. Each cell runs `phases` plate phases: the test
// phases 2π(k + ½)/phases, or the validation phases 2π(k + ¼)/phases that experiments compare
// settings on, so that the test phases stay held out.
//
// RUN/verify/ (RUN/verify_validation/ for the validation phases): conditions.csv (a row per subject and condition, appended as each finishes, so a
// stopped verify resumes), verify.toml (what was verified), report.md (verify_report.hpp),
// verify.dat and verify.png (each subject's return per condition with its 95 % interval).
#include <cstddef>
#include <string>
#include <vector>

#include "core/physics_randomization.hpp"
#include "run/verify_report.hpp"
#include "run/verify_subjects.hpp"

namespace codesign::run {

struct VerifyOptions {
  std::string dir;          // the run folder
  int phases = 100;         // episodes per subject and condition
  std::string phase_set = "test";  // "test" or "validation"
  int next = 2;             // designs of the run's order after d* and the runner-up
  bool baselines = true;    // the two PIDs on d*
  std::vector<std::string> with;   // other run folders whose d* this run's policy is tested on
  std::vector<std::string> conditions;  // names of the suite's conditions to run (empty: all)
  std::size_t threads = 0;  // 0: all cores
  bool force = false;       // replace a verify of the run made with other settings
  bool progress = true;
  std::string plots_dir;    // folder of verify.gp ("": no figure)
  // Policies trained on one subject's design alone (the specialists, trained by the caller: the
  // verify job of apps/), tested as subjects of their own after the run's policy subjects.
  struct Specialist {
    std::string name;         // "own_j40_s1"
    std::string policy_file;
    DesignAtPressures at;
    int seed = 1;
  };
  std::vector<Specialist> specialists;
};

// One held-out condition: a physics draw applied to every episode, or the refined mesh.
struct VerifyCondition {
  std::string name;
  std::string what;  // one line for the report
  core::PhysicsDraw physics;
  bool refined_mesh = false;
};
// The suite, in the order the report lists it.
std::vector<VerifyCondition> verify_suite();

struct VerifySummary {
  std::string folder;            // RUN/verify
  std::vector<VerifySubject> subjects;
  std::vector<VerifyRow> rows;   // subject-major, suite order within a subject
  int cells_run = 0, cells_before = 0;  // this call's cells: run now, and found done
  int episodes_run = 0;          // episodes of the cells run now (the PIDs' tuning not counted)
  double wall_s = 0.0;           // of this call
  double cpu_s = 0.0;            // CPU time of this call, all threads
  std::string figure_message;    // why verify.png was not drawn ("" when it was)
};

// What a verify of the run tests, in report order (without running anything). Throws as
// verify_run.
std::vector<VerifySubject> verify_plan(const VerifyOptions& options);

// The conditions of the suite named (all for an empty list), in suite order; InputError naming
// --conditions and the allowed names for a name not in the suite.
std::vector<VerifyCondition> chosen_conditions(const std::vector<std::string>& names);

// Throws InputError naming the file or flag: no run folder, config.toml, result.toml or
// policy.bin; a `with` folder without result.toml; a phase set other than test/validation; a
// folder holding a verify with other settings (without force).
VerifySummary verify_run(const VerifyOptions& options);

}  // namespace codesign::run
