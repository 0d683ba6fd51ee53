#pragma once
// The paper's figures (Figs. 2a–2d and 3) from a run folder (run.hpp lists its files).
//
// C++ prepares the data, gnuplot only draws: make_figures() reads the run's CSVs, result.toml and
// config.toml (and those of comparison runs), writes small whitespace-separated data files into
// RUN/figures/data/ (each with a '#' header naming its columns and units), then runs one gnuplot
// script per figure from the plots folder (plots/*.gp in the source tree, editable by users),
// which writes RUN/figures/<fig>.png. RUN/figures/gnuplot_commands.txt lists the gnuplot command
// line of every figure, so a user can edit a script and draw it again by hand.
//
//   fig2a  reward of every sampled design (sampled.csv: the first episode of each environment and
//          iteration, the return Algorithm 2 sees) over timesteps; moving average over the last
//          `window` samples and best so far (drawn once per update: the value after its last
//          sample); the running mean of d*'s own samples; phase boundaries
//   fig2b  μ1 and σ1 (μ2, σ2 for two chambers) of q_cont(d*) in kPa over updates (after each
//          update, from sampled.csv rows of d*, carried forward between samples of d*); final p*
//   fig2c  reward distributions of the top designs (d* and the runner-up): histograms of their
//          sampled returns, each normalised to fractions of that design's samples
//   fig2d  moving average of the sampled returns over timesteps (once per update): this run and
//          every --compare run
//   fig3   F over the first evaluation episode (eval/<which>_trace.csv) with F_t ± tolerance, and θ,
//          for d*, the runner-up, and the d* of every comparison run whose observation is no_feedback
//
// d* and the runner-up come from result.toml; for a run still in progress (no result.toml), d* is
// the leading design of the last row of distribution.csv, the runner-up the first other design of
// its top-3, and fig3 is skipped (no evaluation yet).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/codesign_config.hpp"
#include "core/task_config.hpp"
#include "io/formats/gnuplot.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

// ---- data preparation (pure functions, tested against hand-computed values)

// y[i] = mean of x[max(0, i-window+1) .. i] (the trailing window; shorter at the start).
std::vector<double> trailing_mean(const std::vector<double>& x, std::size_t window);
// y[i] = max of x[0 .. i].
std::vector<double> running_max(const std::vector<double>& x);

// Indices of the last element of every run of equal consecutive keys: {5, 5, 7, 7, 7, 9} → {1, 4, 5}.
// Used to plot a moving mean once per update (the value after the update's last sample).
std::vector<std::size_t> last_of_each_run(const std::vector<std::int64_t>& keys);

struct PhaseSpan {
  std::string name;   // exploration, transition, exploitation
  double start = 0, end = 0;
};
// The phases of Algorithm 2 (t < t1 exploration, t1 ≤ t < t2 transition, t ≥ t2 exploitation)
// that overlap [0, t_end], clipped to it; a phase of zero length is left out.
std::vector<PhaseSpan> phase_spans(double t1, double t2, double t_end);

// Histograms of several samples on common bins: `bins` equal bins spanning the smallest to the
// largest value of all samples (a single value: one bin of width 1 centred on it); the last bin
// includes its upper edge. fractions[s][b] = share of sample s in bin b (0 for an empty sample).
struct Histogram {
  std::vector<double> edges;                   // bins + 1 values
  std::vector<std::vector<double>> fractions;  // [sample][bin]
};
Histogram histogram(const std::vector<std::vector<double>>& samples, std::size_t bins);

// ---- a run folder as the figures need it

struct SampleRow {    // one row of sampled.csv
  std::int64_t k = 0, t = 0;
  int design = 0;
  double episode_return = 0;
  double mu_kPa[2] = {0, 0}, sigma_kPa[2] = {0, 0};
};
struct UpdateRow {    // one row of distribution.csv
  std::int64_t k = 0, t = 0;
  std::string phase;
  std::vector<int> top;  // top1_j .. top3_j
  int best_design = 0;
};
struct EvalDesign {   // a [best] / [runner_up] table of result.toml
  int design = 0;
  double pressures_kPa[2] = {0, 0};
  double test_return = 0;
};
struct RunFigureData {
  std::string dir;
  core::ObservationSet observation = core::ObservationSet::Paper;  // [task] observation
  core::Baseline baseline = core::Baseline::None;                  // [codesign] baseline
  double target_force_mN = 20, tolerance_fraction = 0.2;
  double exploration_end = 0, exploitation_start = 0;   // T1, T2
  std::vector<SampleRow> samples;
  std::vector<UpdateRow> updates;
  std::optional<EvalDesign> best, runner_up;
  std::vector<TracePoint> best_trace, runner_up_trace;   // empty when absent
  double best_trace_return = 0, runner_up_trace_return = 0;  // the traced episode's return

  int leading_design() const;                 // d*: result.toml, else the last update's best
  std::optional<int> second_design() const;   // the runner-up, if any
  // "co-design", "no-feedback", "single-design" (with "proprioceptive" added when that is the
  // observation), the default label of the run in figures.
  std::string default_label() const;
};

// Reads DIR's config.toml, sampled.csv, distribution.csv and, when present, result.toml and
// eval/*_trace.csv + eval/*.csv. Throws codesign::InputError naming the file (and line/column)
// for a missing folder or file, a missing column or a malformed value.
RunFigureData read_run_figure_data(const std::string& dir);

// ---- the figures

struct FigureOptions {
  std::string run_dir;
  std::string plots_dir;                                  // folder with fig2a.gp ... fig3.gp
  std::vector<std::pair<std::string, std::string>> compare;  // (label, run folder) for fig2d/fig3
  std::size_t window = 100;                               // moving-average window (samples)
  std::size_t bins = 20;                                  // fig2c histogram bins
  std::string gnuplot = "gnuplot";                        // executable
  // Throws InputError: empty run_dir or plots_dir, window or bins 0 or above 100000, a label
  // that is empty or holds a character other than letters, digits, '_', '-', '.', '+', or repeats.
  void validate() const;
};

struct FigureOutcome {
  std::string name;        // fig2a ...
  std::string png;         // RUN/figures/<name>.png
  bool drawn = false;
  std::string message;     // why not drawn ("" if drawn)
};

struct FiguresReport {
  std::vector<FigureOutcome> figures;
  bool gnuplot_missing = false;
  std::size_t drawn() const;
};

// Writes RUN/figures/data/*.dat and the gnuplot calls without running them (validates first,
// reads every input before writing anything: a bad input leaves an earlier figures/ untouched).
// Figures that cannot be drawn (fig3 without evaluation traces) are returned with drawn=false
// and a reason, and no call. Used by make_figures and by tests.
struct PreparedFigures {
  std::vector<std::pair<FigureOutcome, std::optional<io::GnuplotCall>>> figures;
};
PreparedFigures prepare_figures(const FigureOptions& options);

// prepare_figures, then gnuplot for each figure: PNG to RUN/figures/<name>.png.tmp, renamed onto
// <name>.png when gnuplot succeeds. A missing gnuplot or a failing script is reported in the
// outcome (gnuplot_missing, drawn=false, message), not thrown.
FiguresReport make_figures(const FigureOptions& options);

// `codesign figures`: make_figures under the run folder's lock (run.hpp, lock_run_folder), a line
// per figure on stdout. Returns 0 when every figure the data allows was drawn, 1 when gnuplot is
// missing or a script failed (the data files are written all the same).
int figures_of_run(const FigureOptions& options);

// The end of `codesign run` (under the run's own lock): the figures with default options from
// the scripts in `plots_dir`; any problem is a warning on stderr, never an error. False when a
// figure was not drawn.
bool draw_run_figures(const std::string& run_dir, const std::string& plots_dir);

}  // namespace codesign::run
