#pragma once
// `codesign evaluate --run DIR [--at final|t1|t2] [--designs A-B] [--phases N]`: the deterministic
// policy of one state of a co-design run, tested on every design of a range, each at the
// pressures that state gives it, ranked (docs/codesign.md, "Evaluating a run's state on every
// design").
//
// The state is a checkpoint of the run folder: checkpoint.bin (`final`: the latest, the end of
// training once the run is complete) or the copies kept at T1 and T2 (checkpoint_t1.bin,
// checkpoint_t2.bin; checkpoint.hpp). Its policy is what policy.bin would hold at that point (the
// model and its frozen observation normalisation); its distribution gives each design j its
// pressures: map(μ_j), the median of q_cont(·|j) — except the design the distribution has
// collapsed to, which is tested at the p* the run fixed, as the run's own final evaluation does.
// Each design runs `phases` episodes at the evaluation phases 2π(k + ½)/phases (evaluation.hpp),
// in parallel on `threads` threads; with phases = codesign.eval_episodes the d* row of the final
// state is the run's own [best] test return, to the bit.
//
// With `pressures_of` = another run folder (`--pressures-of RUN`), each design is tested at the
// pressures that run's state at the same `at` gives it (the same rule: map(μ_j), or p* for its
// collapsed design) instead of this run's: the policy of one seed on the design answers of another
// (a cross-seed check, fair to a d* whose p* the evaluated run never tried). The other
// run's leading design is reported as `pressures_d*` beside this run's d* and runner-up. Output
// then goes to DIR/evaluate/<at>_pressures_of_<basename of RUN>/.
//
// Output, in DIR/evaluate/<at>/:
//   evaluate.toml   what was evaluated (the checkpoint, its t, phases, the design range)
//   designs.csv     one row per design as it finishes (design order), appended and flushed: a
//                   stopped evaluation continues after its last whole row when run again
//   ranking.csv     the same rows by test return, best first, with rank and role (d*, runner_up:
//                   the state's leading design and the next by R̂)
//   ranking.png     mean ± 95 % interval against rank, d* and the runner-up marked (gnuplot)
// The interval is mean ± 1.96·s/√N (s the sample std over the N phases): the normal
// approximation of a confidence interval for the mean over plate phases, fair for N ≥ 30.
// The folder is locked while it is written (io::RunLock), so a second evaluation of the same
// state waits for nothing and is refused; the run folder itself is only read (a live run may go
// on beside it).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "run/run_settings.hpp"

namespace codesign::run {

struct RunEvaluationOptions {
  std::string dir;               // the run folder
  std::string at = "final";      // "final", "t1" or "t2"
  int first_design = 0;          // inclusive range, within 0..109
  int last_design = 109;
  int phases = 0;                // episodes per design; 0: the run's codesign.eval_episodes
  std::size_t threads = 0;       // 0: all cores
  bool force = false;            // start afresh even if the folder holds another evaluation
  bool progress = true;          // a line per design on stdout
  std::string plots_dir;         // folder of evaluate_ranking.gp ("" = none: no PNG)
  std::string pressures_of;      // "" or another run folder whose state at `at` gives the pressures
};

struct RunEvaluationRow {
  int design = 0;
  double p1_kPa = 0.0, p2_kPa = 0.0;
  double q = 0.0;                // q_disc(j) at the state's t
  double score = 0.0;            // R̂_j
  std::int64_t samples = 0;      // times the run sampled j up to that state
  double mean_return = 0.0, std_return = 0.0;  // over the phases (std: population, as evaluation.hpp)
  double ci95 = 0.0;             // half-width of the 95 % interval of the mean
  double band_fraction = 0.0;
  int episodes = 0;
  double seconds = 0.0;          // wall time of this design's episodes
  int rank = 0;                  // 1 = best test return (ranking only)
  std::string role;              // "d*", "runner_up", "pressures_d*" or "" (ranking only)
};

struct RunEvaluationSummary {
  std::string folder;            // DIR/evaluate/<at>
  std::int64_t t = 0;            // the evaluated state's timestep
  int leading_design = -1, runner_up = -1;
  int pressures_leading_design = -1;      // the leading design of the `pressures_of` run's state (-1: none given)
  std::int64_t pressures_t = -1;          // that state's timestep
  std::vector<RunEvaluationRow> ranking;  // best first
  int designs_run = 0, designs_before = 0;
  double wall_s = 0.0;
  bool figure = false;           // ranking.png drawn
  std::string figure_message;    // why not, when it was not
};

// Throws InputError naming the file and the defect: no such run folder or checkpoint, a
// checkpoint of another config, an `at` other than final/t1/t2, a design range outside 0..109 or
// reversed, phases < 2, a folder that holds an evaluation with other settings (without force); a
// `pressures_of` folder without config.toml or without the checkpoint of `at`.
RunEvaluationSummary evaluate_run(const RunSettings& settings, const RunEvaluationOptions& options);

// `codesign evaluate`: reads DIR/config.toml (InputError if it is missing), evaluate_run, and
// prints the ten best designs and where d* and the runner-up rank.
void evaluate_run_folder(const RunEvaluationOptions& options);

// One design of a run's state as `evaluate` tests it: its probability q_disc(j) and its test
// pressures (map(μ_j), or p* for the design the distribution has collapsed to).
struct StateDesign {
  int design = 0;
  double q = 0.0;
  double p1_kPa = 0.0, p2_kPa = 0.0;
};
// Every design of the state `at` of a run folder, most probable first (ties: lower index); no
// episode runs. InputError as evaluate_run for a missing checkpoint or one of another config.
std::vector<StateDesign> state_designs(const RunSettings& settings, const std::string& dir, const std::string& at);

// The checkpoint file of `at` in a run folder ("final" -> checkpoint.bin); InputError otherwise.
std::string checkpoint_file_of(const std::string& at);

// The folder under DIR/evaluate/ an evaluation writes: `at`, or `<at>_pressures_of_<name>` with
// the basename of the `pressures_of` run folder.
std::string evaluation_folder_name(const RunEvaluationOptions& options);

}  // namespace codesign::run
