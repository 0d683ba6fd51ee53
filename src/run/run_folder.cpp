#include "run/run_folder.hpp"

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "base/errors.hpp"
#include "fem/design.hpp"
#include "io/formats/atomic_file.hpp"
#include "io/formats/csv_log.hpp"
#include "io/formats/csv_table.hpp"
#include "io/config/toml_reader.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/core)

namespace fs = std::filesystem;

namespace {

std::string num(double v) { return io::CsvLog::num(v); }

void write_design_table(std::ostream& out, const std::string& section, const ResultDesign& d) {
  const fem::Design g = fem::design_from_index(d.setup.design);
  out << "[" << section << "]\n"
      << "design = " << d.setup.design << "\n"
      << "n = " << g.n << "\n"
      << "l_mm = " << num(g.chamber_length_mm) << "\n"
      << "w_mm = " << num(g.wall_mm) << "\n"
      << "pressures_kPa = [" << num(d.setup.p1_kPa) << ", " << num(d.setup.p2_kPa) << "]\n"
      << "test_return = " << num(d.test_return) << "   # mean over the evaluation episodes\n"
      << "test_return_std = " << num(d.test_return_std) << "\n"
      << "test_episodes = " << d.test_episodes << "\n"
      << "band_fraction = " << num(d.band_fraction) << "   # decisions with F inside the band\n\n";
}

}  // namespace

ResultDesign result_design(const DesignEvaluation& e) {
  ResultDesign d;
  d.setup = e.setup;
  d.test_return = e.mean_return;
  d.test_return_std = e.std_return;
  d.test_episodes = static_cast<int>(e.returns.size());
  d.band_fraction = e.mean_band_fraction;
  return d;
}

void write_result(const fs::path& run_dir, const ResultFile& r) {
  io::write_file_atomically((run_dir / run_file::kResult).string(), [&](std::ostream& out) {
    out << "# codesign result: d* and the runner-up, each evaluated with the deterministic final policy over "
        << r.eval_episodes << " episodes\n# (plate phases 2*pi*(k + 1/2)/" << r.eval_episodes << ").\n\n";
    write_design_table(out, "best", r.best);
    if (r.runner_up) write_design_table(out, "runner_up", *r.runner_up);
    if (const auto& f = r.fixed_theta)
      out << "[best_fixed_theta]   # d* at p* with the base held at the best constant angle (no controller)\n"
          << "theta0_deg = " << num(f->theta0_rad * 180.0 / std::numbers::pi) << "   # tuned on "
          << f->tuning_phases << " plate phases 2*pi*(i + 0.618...)/" << f->tuning_phases << "\n"
          << "test_return = " << num(f->test_return) << "   # over the same test episodes as [best]\n"
          << "test_return_std = " << num(f->test_return_std) << "\n"
          << "band_fraction = " << num(f->band_fraction) << "\n\n";
    out << "[run]\n"
        << "timesteps = " << r.run.timesteps << "\n"
        << "iterations = " << r.run.iterations << "\n"
        << "seed = " << r.run.seed << "\n"
        << "observation = \"" << r.run.observation << "\"\n"
        << "baseline = \"" << r.run.baseline << "\"\n"
        << "numerical_failures = " << r.run.numerical_failures
        << "   # training episodes ended by a numerical failure (episodes.csv)\n"
        << "wall_s = " << num(r.run.wall_s) << "   # wall-clock: the only field that differs between reruns\n";
  });
}

std::optional<ResultDesign> read_result_design(const fs::path& run_dir, const std::string& which,
                                               double pressure_max_kPa) {
  io::TableReader root = io::TableReader::from_file((run_dir / run_file::kResult).string());
  if (!root.has(which)) return std::nullopt;
  io::TableReader t = root.table(which);
  if (!t.has("design")) t.fail("design", "missing");
  ResultDesign d;
  d.setup.design = static_cast<int>(t.integer("design", 0, 0, fem::kDesignCount - 1));
  const std::vector<double> p = t.numbers("pressures_kPa", {0.0, 0.0}, 0.0, pressure_max_kPa, 2, 2);
  d.setup.p1_kPa = p[0];
  d.setup.p2_kPa = p[1];
  d.test_return = t.number("test_return", 0.0, -1e12, 1e12);
  d.test_return_std = t.number("test_return_std", 0.0, 0.0, 1e12);
  d.test_episodes = static_cast<int>(t.integer("test_episodes", 0, 0, 1000000));
  d.band_fraction = t.number("band_fraction", 0.0, 0.0, 1.0);
  return d;
}

std::string with_refined_table(const std::string& text, const RefineResult& r) {
  std::string base = text;
  // Remove an earlier [refined] table: from its header line to the next table header or the end.
  std::size_t at = base.rfind("\n[refined]");
  if (at != std::string::npos) ++at;
  else if (base.rfind("[refined]", 0) == 0) at = 0;
  if (at != std::string::npos) {
    const std::size_t next = base.find("\n[", at);
    base.erase(at, next == std::string::npos ? std::string::npos : next + 1 - at);
  }
  if (!base.empty() && base.back() != '\n') base += '\n';
  // One blank line before the table (an erased earlier table left its blank line in place).
  const bool blank = base.empty() || base.ends_with("\n\n");
  std::ostringstream o;
  o << (blank ? "" : "\n") << "[refined]   # codesign refine: p* polished by NLopt (" << to_string(r.config.search.method)
    << ") with the policy and j* fixed\n"
    << "design = " << r.design << "\n"
    << "pressures_kPa_before = [" << num(r.p_before[0]) << ", " << num(r.p_before[1]) << "]\n"
    << "pressures_kPa = [" << num(r.p_after[0]) << ", " << num(r.p_after[1]) << "]\n"
    << "tuning_phases = " << r.config.tuning_phases << "   # plate phases 2*pi*(i + 0.618...)/n, searched on\n"
    << "tuning_return_before = " << num(r.tuning_before) << "\n"
    << "tuning_return = " << num(r.tuning_after) << "\n"
    << "evaluations = " << r.evaluations << "\n"
    << "test_episodes = " << r.test_after.returns.size() << "   # plate phases 2*pi*(k + 1/2)/n, never searched on\n"
    << "test_return_before = " << num(r.test_before.mean_return) << "\n"
    << "test_return_before_std = " << num(r.test_before.std_return) << "\n"
    << "test_return = " << num(r.test_after.mean_return) << "\n"
    << "test_return_std = " << num(r.test_after.std_return) << "\n"
    << "band_fraction = " << num(r.test_after.mean_band_fraction) << "\n";
  return base + o.str();
}

void write_refined_result(const fs::path& run_dir, const RefineResult& r) {
  const std::string path = (run_dir / run_file::kResult).string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string out = with_refined_table(text.str(), r);
  io::write_file_atomically(path, [&](std::ostream& o) { o << out; }, true);
}

void write_evaluation(const fs::path& dir, const std::string& which, const DesignEvaluation& e,
                      const ForceEstimator* estimator) {
  fs::create_directories(dir);
  io::write_file_atomically((dir / (which + ".csv")).string(), [&](std::ostream& out) {
    out << "episode,phase_rad,return,decisions,band_fraction,reason\n";
    for (std::size_t k = 0; k < e.returns.size(); ++k)
      out << k << ',' << num(evaluation_phase(static_cast<int>(k), static_cast<int>(e.returns.size()))) << ','
          << num(e.returns[k]) << ',' << e.decisions[k] << ',' << num(e.band_fraction[k]) << ',' << e.reasons[k]
          << '\n';
  });
  io::write_file_atomically((dir / (which + "_trace.csv")).string(), [&](std::ostream& out) {
    out << "decision,t_s,theta_rad,F_mN,strain,tip_x_mm,tip_y_mm,tip_z_mm,plate_z_mm,action"
        << (estimator ? ",F_hat_mN\n" : "\n");
    for (const TraceRow& r : e.trace) {
      out << r.decision << ',' << num(r.t_s) << ',' << num(r.theta_rad) << ',' << num(r.force_mN) << ','
          << num(r.strain) << ',' << num(r.tip_mm.x()) << ',' << num(r.tip_mm.y()) << ',' << num(r.tip_mm.z()) << ','
          << num(r.plate_z_mm) << ',' << num(r.action);
      if (estimator) out << ',' << num(estimator->force_mN(r.strain, r.theta_rad));
      out << '\n';
    }
  });
}

std::optional<EvaluationTrace> read_evaluation_trace(const fs::path& run_dir, const std::string& which) {
  const fs::path file = run_dir / run_file::kEvalDir / (which + "_trace.csv");
  if (!fs::exists(file)) return std::nullopt;
  EvaluationTrace out;
  const io::CsvTable t = io::read_csv(file.string());
  const std::size_t ct = t.column("t_s"), cth = t.column("theta_rad"), cf = t.column("F_mN");
  for (std::size_t r = 0; r < t.rows(); ++r) out.points.push_back({t.number(r, ct), t.number(r, cth), t.number(r, cf)});
  out.first_return = NAN;
  const fs::path episodes = run_dir / run_file::kEvalDir / (which + ".csv");
  if (fs::exists(episodes)) {
    const io::CsvTable e = io::read_csv(episodes.string());
    if (e.rows() > 0) out.first_return = e.number(0, e.column("return"));
  }
  return out;
}

std::string run_folder_name(const std::string& dir) {
  std::filesystem::path p = std::filesystem::path(dir).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p.filename().string();
}

}  // namespace codesign::run
