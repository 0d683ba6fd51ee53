// `codesign figures --run runs/NAME [--compare LABEL=DIR ...] [--plots DIR] [--window N] [--bins N]
//                   [--gnuplot PATH]`
//
// The paper's Figs. 2a–2d and 3 from a run folder (run/figures.hpp): data files into
// RUN/figures/data/, then gnuplot draws RUN/figures/fig2a.png ... fig3.png with the scripts of
// plots/ (this source tree's, compiled in as CODESIGN_PLOTS_DIR, or --plots DIR).
// Exit status: 0 when every figure the data allows was drawn, 1 when gnuplot is missing or a
// script failed (the data files are written all the same), 2 for bad input.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "run/figures.hpp"
#include "commands.hpp"

#ifndef CODESIGN_PLOTS_DIR
#define CODESIGN_PLOTS_DIR "plots"
#endif

namespace codesign::app {

namespace {

struct FiguresCliOptions {
  std::string run;
  std::vector<std::string> compare;
  std::string plots = CODESIGN_PLOTS_DIR;
  std::size_t window = 100;
  std::size_t bins = 20;
  std::string gnuplot = "gnuplot";
};

run::FigureOptions to_options(const FiguresCliOptions& c) {
  run::FigureOptions o;
  o.run_dir = c.run;
  o.plots_dir = c.plots;
  o.window = c.window;
  o.bins = c.bins;
  o.gnuplot = c.gnuplot;
  for (const std::string& s : c.compare) {
    const std::size_t eq = s.find('=');
    if (eq == std::string::npos) {
      throw InputError("figures: --compare '" + s + "': expected LABEL=DIR, e.g. --compare single=runs/single");
    }
    o.compare.emplace_back(s.substr(0, eq), s.substr(eq + 1));
  }
  return o;
}

}  // namespace

void add_figures_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<FiguresCliOptions>();
  CLI::App* cmd = root.add_subcommand("figures", "The paper's Figs. 2a-2d and 3 as PNGs from a run folder (gnuplot)");
  cmd->add_option("--run", opt->run, "run folder written by `codesign run`")->required();
  cmd->add_option("--compare", opt->compare,
                  "LABEL=DIR: another run for Fig. 2d (and Fig. 3 if its observation is no_feedback); repeatable");
  cmd->add_option("--plots", opt->plots, "folder of the gnuplot scripts (default: " CODESIGN_PLOTS_DIR ")");
  cmd->add_option("--window", opt->window, "moving-average window in sampled designs (paper: 100)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--bins", opt->bins, "histogram bins of Fig. 2c")->check(CLI::Range(1, 100000));
  cmd->add_option("--gnuplot", opt->gnuplot, "gnuplot executable (name on PATH or path)");
  cmd->callback([opt, &run] { run = [opt] { return run::figures_of_run(to_options(*opt)); }; });
}

}  // namespace codesign::app
