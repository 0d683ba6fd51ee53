#include "run/figures.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include "base/errors.hpp"
#include "core/design_distribution.hpp"
#include "fem/design.hpp"
#include "io/formats/atomic_file.hpp"
#include "io/formats/csv_table.hpp"
#include "io/formats/run_lock.hpp"
#include "run/folder_lock.hpp"
#include "run/run_config.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/core)

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Pure data preparation

std::vector<double> trailing_mean(const std::vector<double>& x, std::size_t window) {
  if (window == 0) throw std::invalid_argument("trailing_mean: window must be at least 1");
  std::vector<double> y(x.size());
  double sum = 0;  // recomputed from scratch every `window` steps, so rounding cannot drift
  for (std::size_t i = 0; i < x.size(); ++i) {
    const std::size_t first = i + 1 >= window ? i + 1 - window : 0;
    if (i % window == 0) {
      sum = 0;
      for (std::size_t k = first; k <= i; ++k) sum += x[k];
    } else {
      sum += x[i];
      if (i >= window) sum -= x[i - window];
    }
    y[i] = sum / static_cast<double>(i - first + 1);
  }
  return y;
}

std::vector<double> running_max(const std::vector<double>& x) {
  std::vector<double> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) y[i] = i == 0 ? x[0] : std::max(y[i - 1], x[i]);
  return y;
}

std::vector<std::size_t> last_of_each_run(const std::vector<std::int64_t>& keys) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (i + 1 == keys.size() || keys[i + 1] != keys[i]) out.push_back(i);
  return out;
}

std::vector<PhaseSpan> phase_spans(double t1, double t2, double t_end) {
  const PhaseSpan all[3] = {{to_string(Phase::Exploration), 0.0, t1},
                            {to_string(Phase::Transition), t1, t2},
                            {to_string(Phase::Exploitation), t2, t_end}};
  std::vector<PhaseSpan> out;
  for (const PhaseSpan& p : all) {
    const double s = std::clamp(p.start, 0.0, t_end), e = std::clamp(p.end, 0.0, t_end);
    if (e > s) out.push_back({p.name, s, e});
  }
  return out;
}

Histogram histogram(const std::vector<std::vector<double>>& samples, std::size_t bins) {
  if (bins == 0) throw std::invalid_argument("histogram: bins must be at least 1");
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& s : samples)
    for (const double v : s) lo = std::min(lo, v), hi = std::max(hi, v);
  Histogram h;
  if (!(lo <= hi)) lo = 0, hi = 1;               // no values at all
  if (lo == hi) lo -= 0.5, hi += 0.5, bins = 1;  // one distinct value: one bin of width 1
  const double width = (hi - lo) / static_cast<double>(bins);
  for (std::size_t b = 0; b <= bins; ++b) h.edges.push_back(b == bins ? hi : lo + width * static_cast<double>(b));
  for (const auto& s : samples) {
    std::vector<double> f(bins, 0.0);
    for (const double v : s) {
      auto b = static_cast<std::size_t>(std::floor((v - lo) / width));
      b = std::min(b, bins - 1);
      // Rounding of (v - lo)/width must not put a value on the wrong side of a stored edge.
      while (b > 0 && v < h.edges[b]) --b;
      while (b + 1 < bins && v >= h.edges[b + 1]) ++b;
      f[b] += 1.0;
    }
    if (!s.empty())
      for (double& x : f) x /= static_cast<double>(s.size());
    h.fractions.push_back(std::move(f));
  }
  return h;
}

// ---------------------------------------------------------------------------------------------
// Reading a run folder

namespace {

using fem::design_label;

int design_cell(const io::CsvTable& t, std::size_t r, std::size_t c) {
  const std::int64_t j = t.integer(r, c);
  if (j < 0 || j >= fem::kDesignCount) {
    throw InputError(t.path() + ": line " + std::to_string(r + 2) + ", column '" + t.columns()[c] + "': design " +
                     std::to_string(j) + " is out of range; allowed [0, " + std::to_string(fem::kDesignCount - 1) +
                     "]");
  }
  return static_cast<int>(j);
}

std::optional<EvalDesign> read_eval_design(const fs::path& dir, const std::string& key) {
  const std::optional<ResultDesign> r = read_result_design(dir, key);
  if (!r) return std::nullopt;
  EvalDesign d;
  d.design = r->setup.design;
  d.pressures_kPa[0] = r->setup.p1_kPa;
  d.pressures_kPa[1] = r->setup.p2_kPa;
  d.test_return = r->test_return;
  return d;
}

// The traced first test episode of `which` and its return, when the run folder has them.
void read_trace(const fs::path& dir, const std::string& which, std::vector<TracePoint>& trace, double& ret) {
  if (std::optional<EvaluationTrace> t = read_evaluation_trace(dir, which)) {
    trace = std::move(t->points);
    ret = t->first_return;
  }
}

}  // namespace

int RunFigureData::leading_design() const {
  if (best) return best->design;
  return updates.back().best_design;
}

std::optional<int> RunFigureData::second_design() const {
  if (best) {
    if (runner_up) return runner_up->design;
    return std::nullopt;
  }
  if (baseline == Baseline::SingleDesign) return std::nullopt;
  for (const int j : updates.back().top)
    if (j != leading_design()) return j;
  return std::nullopt;
}

std::string RunFigureData::default_label() const {
  std::string l = baseline == Baseline::SingleDesign          ? "single-design"
                  : observation == ObservationSet::NoFeedback ? "no-feedback"
                                                 : "co-design";
  if (observation == ObservationSet::Proprioceptive) l += " (proprioceptive)";
  return l;
}

RunFigureData read_run_figure_data(const std::string& dir_name) {
  const fs::path dir(dir_name);
  if (!fs::is_directory(dir)) throw InputError(dir_name + ": no such run folder");
  RunFigureData d;
  d.dir = dir_name;

  const fs::path config = dir / run_file::kConfig;
  if (!fs::exists(config))
    throw InputError(config.string() + ": missing (a run folder written by `codesign run` holds it)");
  {
    // The run's resolved config, through the one reader of the run config (every key is explicit
    // there, so no default of this file decides a figure).
    const RunConfig c = read_run_config(config.string());
    d.target_force_mN = c.task.target_force_mN;
    d.tolerance_fraction = c.task.tolerance_fraction;
    d.observation = c.task.observation;
    d.exploration_end = static_cast<double>(c.codesign.distribution.exploration_end);
    d.exploitation_start = static_cast<double>(c.codesign.distribution.exploitation_start);
    d.baseline = c.codesign.baseline;
  }

  {
    const io::CsvTable t = io::read_csv((dir / run_file::kSampled).string());
    const std::size_t ck = t.column("k"), ct = t.column("t"), cj = t.column("j"), cr = t.column("return"),
                      cm1 = t.column("mu1_kPa"), cm2 = t.column("mu2_kPa"), cs1 = t.column("sigma1_kPa"),
                      cs2 = t.column("sigma2_kPa");
    if (t.rows() == 0) throw InputError(t.path() + ": no sampled designs yet (the run has not finished an iteration)");
    for (std::size_t r = 0; r < t.rows(); ++r) {
      SampleRow s;
      s.k = t.integer(r, ck);
      s.t = t.integer(r, ct);
      s.design = design_cell(t, r, cj);
      s.episode_return = t.number(r, cr);
      s.mu_kPa[0] = t.number(r, cm1);
      s.mu_kPa[1] = t.number(r, cm2);
      s.sigma_kPa[0] = t.number(r, cs1);
      s.sigma_kPa[1] = t.number(r, cs2);
      d.samples.push_back(s);
    }
  }
  {
    const io::CsvTable t = io::read_csv((dir / run_file::kDistribution).string());
    const std::size_t ck = t.column("k"), ct = t.column("t"), cp = t.column("phase"), cb = t.column("best_j");
    const std::size_t tops[3] = {t.column("top1_j"), t.column("top2_j"), t.column("top3_j")};
    if (t.rows() == 0) throw InputError(t.path() + ": no distribution updates yet");
    for (std::size_t r = 0; r < t.rows(); ++r) {
      UpdateRow u;
      u.k = t.integer(r, ck);
      u.t = t.integer(r, ct);
      u.phase = t.cell(r, cp);
      if (!value_of(kPhaseNames, u.phase)) {
        throw InputError(t.path() + ": line " + std::to_string(r + 2) + ", column 'phase': '" + u.phase +
                         "'; allowed " + names_list(kPhaseNames));
      }
      for (const std::size_t c : tops) u.top.push_back(design_cell(t, r, c));
      u.best_design = design_cell(t, r, cb);
      d.updates.push_back(std::move(u));
    }
  }

  if (fs::exists(dir / run_file::kResult)) {
    d.best = read_eval_design(dir, "best");
    if (!d.best) throw InputError((dir / run_file::kResult).string() + ": has no [best] table");
    d.runner_up = read_eval_design(dir, "runner_up");
    read_trace(dir, "best", d.best_trace, d.best_trace_return);
    read_trace(dir, "runner_up", d.runner_up_trace, d.runner_up_trace_return);
  }
  return d;
}

// ---------------------------------------------------------------------------------------------
// The figures

void FigureOptions::validate() const {
  if (run_dir.empty()) throw InputError("figures: no run folder given (--run DIR)");
  if (plots_dir.empty()) throw InputError("figures: no plots folder given (--plots DIR)");
  if (window < 1 || window > 100000)
    throw InputError("figures: --window " + std::to_string(window) + " is out of range; allowed [1, 100000]");
  if (bins < 1 || bins > 100000)
    throw InputError("figures: --bins " + std::to_string(bins) + " is out of range; allowed [1, 100000]");
  std::set<std::string> labels;
  for (const auto& [label, dir] : compare) {
    const bool ok = !label.empty() && std::all_of(label.begin(), label.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == '+';
    });
    if (!ok) {
      throw InputError("figures: --compare label '" + label +
                       "' is not allowed; allowed: letters, digits, _ - . + (as in --compare single=runs/single)");
    }
    if (!labels.insert(label).second) throw InputError("figures: --compare label '" + label + "' given twice");
    if (dir.empty()) throw InputError("figures: --compare " + label + "= has no run folder");
  }
}

std::size_t FiguresReport::drawn() const {
  return static_cast<std::size_t>(std::count_if(figures.begin(), figures.end(), [](const FigureOutcome& f) {
    return f.drawn;
  }));
}

namespace {

const char* const kFigureNames[] = {"fig2a", "fig2b", "fig2c", "fig2d", "fig3"};

std::string g10(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string fixed(double v, int digits) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string pressures_text(const double p[2], int chambers) {
  return chambers == 1 ? "p = " + fixed(p[0], 3) + " kPa" : "p = (" + fixed(p[0], 3) + ", " + fixed(p[1], 3) + ") kPa";
}

std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (const char c : s) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}

// One data file: its text, written later (all files are built before any is written).
struct DataFile {
  std::string name;
  std::string text;
};

std::vector<double> returns_of(const RunFigureData& r) {
  std::vector<double> x;
  x.reserve(r.samples.size());
  for (const SampleRow& s : r.samples) x.push_back(s.episode_return);
  return x;
}

// What every figure is made from: the options, the run and the comparison runs, the folders, d*.
struct FigureInputs {
  const FigureOptions& options;
  const RunFigureData& run;
  const std::vector<std::pair<std::string, RunFigureData>>& others;
  fs::path plots, out_dir, data_dir;
  int dstar = 0, dstar_n = 1;  // d* and its number of chambers
  double t_end = 0;            // the run's last sampled timestep
  bool has_phases = true;      // not for the single-design baseline

  // The gnuplot call of figure `name` with the arguments every script takes.
  io::GnuplotCall base_call(const std::string& name) const {
    io::GnuplotCall c;
    c.executable = options.gnuplot;
    c.script = (plots / (name + ".gp")).string();
    c.set("plotsdir", plots.string());
    c.set("datadir", data_dir.string());
    c.set("outfile", (out_dir / (name + ".png")).string());
    return c;
  }
  FigureOutcome outcome(const std::string& name) const {
    FigureOutcome f;
    f.name = name;
    f.png = (out_dir / (name + ".png")).string();
    return f;
  }
};

// fig2a: every sampled return, moving average, best so far, d*'s running mean, phases
void add_fig2a(const FigureInputs& in, std::vector<DataFile>& files, PreparedFigures& prepared) {
  const FigureOptions& o = in.options;
  const RunFigureData& run = in.run;
  const int dstar = in.dstar;
  const double t_end = in.t_end;
  const bool has_phases = in.has_phases;
  const std::vector<double> x = returns_of(run);
  const std::vector<double> mean = trailing_mean(x, o.window), best = running_max(x);
  std::ostringstream s;
  s << "# fig2a: return of every sampled design (sampled.csv, in sample order)\n"
    << "# t [timesteps], k, j, return\n";
  std::vector<std::int64_t> ts;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const SampleRow& r = run.samples[i];
    s << r.t << ' ' << r.k << ' ' << r.design << ' ' << g10(x[i]) << '\n';
    ts.push_back(r.t);
  }
  files.push_back({"fig2a_samples.dat", s.str()});
  std::ostringstream sc;
  sc << "# fig2a: after each update's last sample: t [timesteps], moving mean over the last " << o.window
     << " samples, best so far\n";
  for (const std::size_t i : last_of_each_run(ts)) sc << ts[i] << ' ' << g10(mean[i]) << ' ' << g10(best[i]) << '\n';
  files.push_back({"fig2a_curves.dat", sc.str()});

  std::vector<double> xd;
  std::vector<std::int64_t> td;
  for (const SampleRow& r : run.samples)
    if (r.design == dstar) xd.push_back(r.episode_return), td.push_back(r.t);
  const std::vector<double> md = trailing_mean(xd, o.window);
  std::ostringstream sd;
  sd << "# fig2a: the samples of d* = " << design_label(dstar) << ", after each update that sampled it\n"
     << "# t [timesteps], running mean over its last " << o.window << " samples\n";
  for (const std::size_t i : last_of_each_run(td)) sd << td[i] << ' ' << g10(md[i]) << '\n';
  if (xd.empty()) sd << "# (d* was never sampled)\n";
  files.push_back({"fig2a_dstar.dat", sd.str()});

  std::ostringstream sp;
  sp << "# fig2a: phases of Algorithm 2 within the run, t [timesteps]: name, start, end\n";
  double t_transition = -1, t_exploitation = -1;
  if (has_phases) {
    for (const PhaseSpan& p : phase_spans(run.exploration_end, run.exploitation_start, t_end)) {
      sp << p.name << ' ' << g10(p.start) << ' ' << g10(p.end) << '\n';
      if (p.name == to_string(Phase::Transition)) t_transition = p.start;
      if (p.name == to_string(Phase::Exploitation)) t_exploitation = p.start;
    }
  }
  files.push_back({"fig2a_phases.dat", sp.str()});

  io::GnuplotCall c = in.base_call("fig2a");
  c.set("t_end", t_end);
  c.set("t_transition", t_transition);
  c.set("t_exploitation", t_exploitation);
  c.set("window", static_cast<double>(o.window));
  c.set("dstar_label", "d* = " + design_label(dstar));
  c.set("dstar_samples", static_cast<double>(xd.size()));
  c.set("run_label", run.default_label());
  prepared.figures.push_back({in.outcome("fig2a"), c});
}

// fig2b: q_cont of d* in kPa over updates (carried forward between samples of d*)
void add_fig2b(const FigureInputs& in, std::vector<DataFile>& files, PreparedFigures& prepared) {
  const RunFigureData& run = in.run;
  const int dstar_n = in.dstar_n;
  const int dstar = in.dstar;
  const bool has_phases = in.has_phases;
  std::ostringstream s;
  s << "# fig2b: q_cont of d* = " << design_label(dstar) << " after each update, in kPa (delta-method sigma)\n"
    << "# k, t [timesteps], mu1, sigma1, mu2, sigma2\n";
  std::size_t next = 0;
  bool seen = false;
  double cur[4] = {0, 0, 0, 0};
  std::int64_t k_transition = -1, k_exploitation = -1;
  for (const UpdateRow& u : run.updates) {
    if (u.phase == to_string(Phase::Transition) && k_transition < 0) k_transition = u.k;
    if (u.phase == to_string(Phase::Exploitation) && k_exploitation < 0) k_exploitation = u.k;
    for (; next < run.samples.size() && run.samples[next].k <= u.k; ++next) {
      const SampleRow& r = run.samples[next];
      if (r.design != dstar) continue;
      seen = true;
      cur[0] = r.mu_kPa[0], cur[1] = r.sigma_kPa[0], cur[2] = r.mu_kPa[1], cur[3] = r.sigma_kPa[1];
    }
    if (seen)
      s << u.k << ' ' << u.t << ' ' << g10(cur[0]) << ' ' << g10(cur[1]) << ' ' << g10(cur[2]) << ' '
        << g10(cur[3]) << '\n';
  }
  files.push_back({"fig2b.dat", s.str()});
  FigureOutcome f = in.outcome("fig2b");
  if (!seen) {
    f.message = "d* = " + design_label(dstar) + " was never sampled: no q_cont to plot";
    prepared.figures.push_back({f, std::nullopt});
  } else {
    io::GnuplotCall c = in.base_call("fig2b");
    const double p_star[2] = {run.best ? run.best->pressures_kPa[0] : cur[0],
                              run.best ? run.best->pressures_kPa[1] : cur[2]};
    c.set("chambers", static_cast<double>(dstar_n));
    c.set("k_end", static_cast<double>(run.updates.back().k));
    c.set("p_star1", p_star[0]);
    c.set("p_star2", p_star[1]);
    c.set("k_transition", has_phases ? static_cast<double>(k_transition) : -1.0);
    c.set("k_exploitation", has_phases ? static_cast<double>(k_exploitation) : -1.0);
    c.set("dstar_label", "d* = " + design_label(dstar) + ", p* = " +
                             (dstar_n == 1 ? fixed(p_star[0], 3) : fixed(p_star[0], 3) + ", " + fixed(p_star[1], 3)) +
                             " kPa");
    prepared.figures.push_back({f, c});
  }
}

// fig2c: reward distributions of the top designs
void add_fig2c(const FigureInputs& in, std::vector<DataFile>& files, PreparedFigures& prepared) {
  const FigureOptions& o = in.options;
  const RunFigureData& run = in.run;
  const int dstar = in.dstar;
  std::vector<int> designs{dstar};
  if (const std::optional<int> r = run.second_design()) designs.push_back(*r);
  std::vector<std::vector<double>> lists(designs.size());
  for (const SampleRow& r : run.samples)
    for (std::size_t i = 0; i < designs.size(); ++i)
      if (r.design == designs[i]) lists[i].push_back(r.episode_return);
  std::ostringstream sr;
  sr << "# fig2c: sampled returns of the top designs, one block per design (gnuplot index 0, 1, ...)\n";
  for (std::size_t i = 0; i < designs.size(); ++i) {
    if (i > 0) sr << "\n\n";
    sr << "# design " << design_label(designs[i]) << ": " << lists[i].size() << " samples\n";
    for (const double v : lists[i]) sr << g10(v) << '\n';
  }
  files.push_back({"fig2c_rewards.dat", sr.str()});
  const Histogram h = histogram(lists, o.bins);
  std::ostringstream sh;
  sh << "# fig2c: histogram of the sampled returns, fraction of each design's samples per bin\n"
     << "# bin low, bin high, bin centre";
  for (const int j : designs) sh << ", fraction j" << j;
  sh << '\n';
  for (std::size_t b = 0; b + 1 < h.edges.size(); ++b) {
    sh << g10(h.edges[b]) << ' ' << g10(h.edges[b + 1]) << ' ' << g10(0.5 * (h.edges[b] + h.edges[b + 1]));
    for (const auto& f : h.fractions) sh << ' ' << g10(f[b]);
    sh << '\n';
  }
  files.push_back({"fig2c_hist.dat", sh.str()});
  FigureOutcome f = in.outcome("fig2c");
  const bool any = std::any_of(lists.begin(), lists.end(), [](const auto& l) { return !l.empty(); });
  if (!any) {
    f.message = "the top designs were never sampled";
    prepared.figures.push_back({f, std::nullopt});
  } else {
    io::GnuplotCall c = in.base_call("fig2c");
    c.set("n_designs", static_cast<double>(designs.size()));
    c.set("bin_width", h.edges[1] - h.edges[0]);
    for (std::size_t i = 0; i < designs.size(); ++i) {
      double mean = 0;
      for (const double v : lists[i]) mean += v;
      mean = lists[i].empty() ? 0 : mean / static_cast<double>(lists[i].size());
      const std::string role = i == 0 ? "d* " : "runner-up ";
      c.set("label" + std::to_string(i), role + design_label(designs[i]) + ": " + std::to_string(lists[i].size()) +
                                             " samples, mean " + fixed(mean, 2));
    }
    prepared.figures.push_back({f, c});
  }
}

// fig2d: moving average of the sampled returns, this run and the comparison runs
void add_fig2d(const FigureInputs& in, std::vector<DataFile>& files, PreparedFigures& prepared) {
  const FigureOptions& o = in.options;
  const RunFigureData& run = in.run;
  const auto& others = in.others;
  std::vector<std::pair<std::string, const RunFigureData*>> runs{{run.default_label(), &run}};
  for (const auto& [label, r] : others) runs.emplace_back(label, &r);
  std::ostringstream s;
  s << "# fig2d: moving mean of the sampled returns over the last " << o.window
    << " samples, one block per run (gnuplot index 0, 1, ...)\n";
  io::GnuplotCall c = in.base_call("fig2d");
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const RunFigureData& r = *runs[i].second;
    const std::vector<double> m = trailing_mean(returns_of(r), o.window);
    std::vector<std::int64_t> ts;
    for (const SampleRow& row : r.samples) ts.push_back(row.t);
    if (i > 0) s << "\n\n";
    s << "# run " << runs[i].first << " (" << r.dir << "): t [timesteps], moving mean after the update's last sample\n";
    for (const std::size_t k : last_of_each_run(ts)) s << ts[k] << ' ' << g10(m[k]) << '\n';
    c.set("label" + std::to_string(i), runs[i].first);
  }
  files.push_back({"fig2d.dat", s.str()});
  c.set("n_runs", static_cast<double>(runs.size()));
  c.set("window", static_cast<double>(o.window));
  prepared.figures.push_back({in.outcome("fig2d"), c});
}

// fig3: F and θ over the first evaluation episode
void add_fig3(const FigureInputs& in, std::vector<DataFile>& files, PreparedFigures& prepared) {
  const RunFigureData& run = in.run;
  const auto& others = in.others;
  struct Curve {
    std::string label;
    const std::vector<TracePoint>* trace;
  };
  std::vector<Curve> curves;
  auto label_of = [](const std::string& role, const EvalDesign& e, double ret) {
    const int n = fem::design_from_index(e.design).n;
    std::string l = role + design_label(e.design) + ", " + pressures_text(e.pressures_kPa, n);
    if (std::isfinite(ret)) l += ": return " + fixed(ret, 2);
    return l;
  };
  if (run.best && !run.best_trace.empty())
    curves.push_back({label_of("d* ", *run.best, run.best_trace_return), &run.best_trace});
  if (run.runner_up && !run.runner_up_trace.empty())
    curves.push_back({label_of("runner-up ", *run.runner_up, run.runner_up_trace_return), &run.runner_up_trace});
  for (const auto& [label, r] : others)
    if (r.observation == ObservationSet::NoFeedback && r.best && !r.best_trace.empty())
      curves.push_back({label_of(label + ": d* ", *r.best, r.best_trace_return), &r.best_trace});
  std::ostringstream s;
  s << "# fig3: the first evaluation episode (eval/<which>_trace.csv), one block per curve (gnuplot index)\n";
  io::GnuplotCall c = in.base_call("fig3");
  double t_max = 0;
  for (std::size_t i = 0; i < curves.size(); ++i) {
    if (i > 0) s << "\n\n";
    s << "# " << curves[i].label << "\n# t [s], F [mN], theta [deg]\n";
    for (const TracePoint& p : *curves[i].trace) {
      s << g10(p.t_s) << ' ' << g10(p.force_mN) << ' ' << g10(p.theta_rad * 180.0 / std::numbers::pi) << '\n';
      t_max = std::max(t_max, p.t_s);
    }
    c.set("label" + std::to_string(i), curves[i].label);
  }
  files.push_back({"fig3.dat", s.str()});
  FigureOutcome f = in.outcome("fig3");
  if (curves.empty()) {
    f.message = "no evaluation traces (eval/best_trace.csv): the run has not finished";
    prepared.figures.push_back({f, std::nullopt});
  } else {
    c.set("n_curves", static_cast<double>(curves.size()));
    c.set("target_mN", run.target_force_mN);
    c.set("band_lo_mN", run.target_force_mN * (1.0 - run.tolerance_fraction));
    c.set("band_hi_mN", run.target_force_mN * (1.0 + run.tolerance_fraction));
    c.set("tolerance_percent", 100.0 * run.tolerance_fraction);
    c.set("t_max", t_max);
    prepared.figures.push_back({f, c});
  }
}

}  // namespace

PreparedFigures prepare_figures(const FigureOptions& o) {
  o.validate();
  const fs::path plots(o.plots_dir);
  for (const char* name : kFigureNames) {
    const fs::path script = plots / (std::string(name) + ".gp");
    if (!fs::is_regular_file(script)) {
      throw InputError(script.string() + ": gnuplot script missing; the scripts live in plots/ of the source tree "
                       "(give their folder with --plots DIR)");
    }
  }
  if (!fs::is_regular_file(plots / "style.gp"))
    throw InputError((plots / "style.gp").string() + ": gnuplot style file missing (--plots DIR)");

  // ---- read everything first
  const RunFigureData run = read_run_figure_data(o.run_dir);
  std::vector<std::pair<std::string, RunFigureData>> others;
  for (const auto& [label, dir] : o.compare) others.emplace_back(label, read_run_figure_data(dir));

  const fs::path out_dir = fs::path(o.run_dir) / run_file::kFiguresDir;
  const fs::path data_dir = out_dir / "data";
  std::vector<DataFile> files;
  PreparedFigures prepared;
  const int dstar = run.leading_design();
  const FigureInputs in{o,
                        run,
                        others,
                        plots,
                        out_dir,
                        data_dir,
                        dstar,
                        fem::design_from_index(dstar).n,
                        static_cast<double>(run.samples.back().t),
                        run.baseline != Baseline::SingleDesign};
  for (const auto add : {add_fig2a, add_fig2b, add_fig2c, add_fig2d, add_fig3}) add(in, files, prepared);

  // ---- write: data files, then the command list
  fs::create_directories(data_dir);
  for (const DataFile& f : files) {
    io::write_file_atomically((data_dir / f.name).string(), [&](std::ostream& out) { out << f.text; });
  }
  io::write_file_atomically((out_dir / "gnuplot_commands.txt").string(), [&](std::ostream& out) {
    out << "# The gnuplot command of each figure (written by `codesign figures`); edit the script, run the line.\n";
    for (const auto& [f, call] : prepared.figures) {
      if (!call) continue;
      bool first = true;
      for (const std::string& a : call->arguments()) {
        out << (first ? "" : " ") << shell_quoted(a);
        first = false;
      }
      out << '\n';
    }
  });
  return prepared;
}

FiguresReport make_figures(const FigureOptions& options) {
  PreparedFigures prepared = prepare_figures(options);
  FiguresReport report;
  const bool available = io::gnuplot_available(options.gnuplot);
  report.gnuplot_missing = !available;
  for (auto& [f, call] : prepared.figures) {
    if (call) {
      if (!available) {
        f.message = "gnuplot not found ('" + options.gnuplot + "'; install gnuplot-nox)";
      } else {
        const std::string tmp = f.png + ".tmp";
        for (io::GnuplotVariable& v : call->variables)
          if (v.name == "outfile") v.value = tmp;
        const io::GnuplotOutcome r = io::run_gnuplot(*call);
        std::error_code ec;
        if (r.ok() && fs::is_regular_file(tmp) && fs::file_size(tmp, ec) > 0) {
          fs::rename(tmp, f.png, ec);
          if (ec) f.message = "cannot rename " + tmp + ": " + ec.message();
          else f.drawn = true;
        } else {
          fs::remove(tmp, ec);
          f.message = r.ok() ? "gnuplot wrote no image to " + tmp : r.message();
          if (r.status == io::GnuplotOutcome::Status::not_found) report.gnuplot_missing = true;
        }
      }
    }
    report.figures.push_back(f);
  }
  return report;
}

int figures_of_run(const FigureOptions& o) {
  // It writes RUN/figures/: not while a run writes the folder (draw_run_figures runs under the run's lock).
  const std::unique_ptr<io::RunLock> lock = lock_run_folder(o.run_dir, /*only_if_exists=*/true);
  const FiguresReport report = make_figures(o);
  int failed = 0;
  for (const FigureOutcome& f : report.figures) {
    if (f.drawn) {
      std::printf("figures: %s\n", f.png.c_str());
    } else {
      std::printf("figures: %s not drawn: %s\n", f.name.c_str(), f.message.c_str());
      // A figure the data does not allow yet (no evaluation, d* never sampled) is not a failure.
      if (report.gnuplot_missing || f.message.rfind("gnuplot", 0) == 0) ++failed;
    }
  }
  std::printf("figures: %zu of %zu drawn; data in %s/figures/data/\n", report.drawn(), report.figures.size(),
              o.run_dir.c_str());
  return failed == 0 ? 0 : 1;
}

bool draw_run_figures(const std::string& run_dir, const std::string& plots_dir) {
  try {
    FigureOptions o;
    o.run_dir = run_dir;
    o.plots_dir = plots_dir;
    const FiguresReport report = make_figures(o);
    if (report.gnuplot_missing) {
      std::fprintf(stderr,
                   "codesign: warning: figures not drawn: gnuplot not found (install gnuplot-nox); "
                   "data in %s/figures/data/\n",
                   run_dir.c_str());
      return false;
    }
    std::string problems;
    for (const FigureOutcome& f : report.figures)
      if (!f.drawn) problems += (problems.empty() ? "" : "; ") + f.name + ": " + f.message;
    if (!problems.empty()) {
      std::fprintf(stderr, "codesign: warning: figures: %s\n", problems.c_str());
    }
    std::printf("codesign: figures: %zu PNGs in %s/figures/\n", report.drawn(), run_dir.c_str());
    return problems.empty();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "codesign: warning: figures not drawn: %s\n", e.what());
    return false;
  }
}

}  // namespace codesign::run
