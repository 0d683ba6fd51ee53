#include "run/sweep_run.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "base/duration_text.hpp"
#include "core/design_sweep.hpp"
#include "run/sweep_folder.hpp"
#include "io/formats/gnuplot.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;

// One PNG per controller from the heat-map tables (a warning, not an error, if gnuplot is missing
// or fails: the tables are the result).
void plot_heatmaps(const fs::path& dir, const core::SweepConfig& sweep, const std::string& plots_dir) {
  const fs::path script = fs::path(plots_dir) / "sweep_heatmap.gp";
  for (core::SweepController c : sweep.controllers) {
    const std::string name = core::to_string(c);
    const fs::path f1 = dir / ("heatmap_n1_" + name + ".dat"), f2 = dir / ("heatmap_n2_" + name + ".dat");
    if (!fs::exists(f1) || !fs::exists(f2)) continue;
    io::GnuplotCall call;
    call.script = script.string();
    call.set("file_n1", f1.string());
    call.set("file_n2", f2.string());
    call.set("outfile", (dir / ("heatmap_" + name + ".png")).string());
    call.set("controller", name);
    if (!fs::exists(script)) {
      std::printf("sweep: warning: %s not found (pass --plots DIR): no heat-map PNGs\n", script.string().c_str());
      return;
    }
    const io::GnuplotOutcome r = io::run_gnuplot(call);
    if (r.ok())
      std::printf("sweep: wrote %s\n", (dir / ("heatmap_" + name + ".png")).string().c_str());
    else
      std::printf("sweep: warning: %s\n", r.message().c_str());
  }
}

}  // namespace

void run_design_sweep(const RunConfig& setup, const SweepRunOptions& o) {
  auto sims = std::make_shared<core::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  SweepOptions so;
  so.dir = o.out;
  // The design range is part of what a restart must match.
  so.config_text = o.config_text + "\n# --designs " + std::to_string(setup.sweep.first_design) + "-" +
                   std::to_string(setup.sweep.last_design) + "\n";
  so.force = o.force;
  so.threads = static_cast<std::size_t>(o.threads);
  so.report_only = o.report_only;
  const core::PidTuningConfig& pc = setup.pid;
  std::printf("sweep: designs %d..%d, pressures_kPa [", setup.sweep.first_design, setup.sweep.last_design);
  for (std::size_t i = 0; i < setup.sweep.pressures_kPa.size(); ++i)
    std::printf("%s%g", i ? ", " : "", setup.sweep.pressures_kPa[i]);
  std::printf("] (two chambers: every pair); tuning on %d plate phases, testing on %d others; PID: NLopt %s, "
              "%d starts, %d evaluations; fixed theta: %d scan points + %d evaluations\n",
              pc.tuning_phases, pc.test_episodes, core::to_string(pc.search.method), pc.search.starts,
              pc.search.max_evals, setup.sweep.fixed_theta.scan_points, setup.sweep.fixed_theta.max_evals);
  std::fflush(stdout);
  const SweepSummary s = run_sweep(sims, setup.task, setup.sweep, pc, so);
  std::printf("sweep: %d rows run now, %d before, %d of %d in all; this call took %s\n", s.rows_run,
              s.rows_done_before, static_cast<int>(s.rows.size()), s.rows_total, duration_text(s.wall_s).c_str());
  // Summary per controller: best design, median, and the best few.
  for (core::SweepController c : setup.sweep.controllers) {
    std::vector<const core::SweepRow*> rows;
    for (const core::SweepRow& r : s.rows)
      if (r.controller == c) rows.push_back(&r);
    if (rows.empty()) continue;
    std::stable_sort(rows.begin(), rows.end(),
                     [](const core::SweepRow* a, const core::SweepRow* b) { return a->test_return > b->test_return; });
    const core::SweepRow& b = *rows.front();
    std::printf("sweep: %-11s best j%d p=[%g, %g]: %.2f +- %.2f over %d test episodes; median %.2f; worst %.2f "
                "(%zu rows)\n",
                core::to_string(c), b.point.design, b.point.p1_kPa, b.point.p2_kPa, b.test_return, b.test_std,
                b.test_episodes, rows[rows.size() / 2]->test_return, rows.back()->test_return, rows.size());
    std::printf("sweep: %-11s top 5:", core::to_string(c));
    for (std::size_t i = 0; i < std::min<std::size_t>(5, rows.size()); ++i)
      std::printf(" j%d %.2f", rows[i]->point.design, rows[i]->test_return);
    std::printf("\n");
  }
  plot_heatmaps(fs::path(o.out), setup.sweep, o.plots_dir);
  std::printf("sweep: wrote %s\n", (fs::path(o.out) / "sweep.csv").string().c_str());
}

}  // namespace codesign::run
