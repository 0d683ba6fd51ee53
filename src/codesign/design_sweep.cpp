#include "codesign/design_sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <numeric>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "base/duration_text.hpp"
#include "base/errors.hpp"
#include "fem/design.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_log.hpp"
#include "rl/thread_pool.hpp"

namespace codesign::core {

namespace {

namespace fs = std::filesystem;
using io::CsvLog;

using RowKey = std::tuple<int, double, double, int>;
RowKey key(const SweepPoint& p, SweepController c) { return {p.design, p.p1_kPa, p.p2_kPa, static_cast<int>(c)}; }

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

double to_double(const std::string& s, const std::string& path) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) throw InputError(path + ": bad number '" + s + "' in a row");
  return v;
}

// Heat-map tables: l × w of the best test return over the pressure grid, per chamber count and
// controller (gnuplot `with image` layout: one block per l, blank line between blocks).
void write_heatmaps(const fs::path& dir, const std::vector<SweepRow>& rows, const SweepConfig& sweep) {
  for (int n : {1, 2})
    for (SweepController c : sweep.controllers) {
      std::map<int, const SweepRow*> best;  // design -> row
      for (const SweepRow& r : rows) {
        if (r.controller != c || fem::design_from_index(r.point.design).n != n) continue;
        auto it = best.find(r.point.design);
        if (it == best.end() || r.test_return > it->second->test_return) best[r.point.design] = &r;
      }
      if (best.empty()) continue;
      const std::string name = "heatmap_n" + std::to_string(n) + "_" + to_string(c) + ".dat";
      io::write_file_atomically((dir / name).string(), [&](std::ostream& out) {
        out << "# " << to_string(c) << ", n = " << n
            << ": best test return over the pressure grid (NaN: not run yet); columns l_mm w_mm test_return "
               "design p1_kPa p2_kPa\n";
        // Every design of this chamber count, NaN where the sweep has no row yet (an unfinished
        // sweep), so the grid stays regular.
        double last_l = -1.0;
        for (int j = 0; j < fem::kDesignCount; ++j) {
          const fem::Design d = fem::design_from_index(j);
          if (d.n != n) continue;
          if (last_l >= 0.0 && d.chamber_length_mm != last_l) out << '\n';
          last_l = d.chamber_length_mm;
          const auto it = best.find(j);
          out << d.chamber_length_mm << ' ' << d.wall_mm << ' '
              << (it == best.end() ? std::string("NaN") : CsvLog::num(it->second->test_return)) << ' ' << j << ' '
              << (it == best.end() ? std::string("NaN") : CsvLog::num(it->second->point.p1_kPa)) << ' '
              << (it == best.end() ? std::string("NaN") : CsvLog::num(it->second->point.p2_kPa)) << '\n';
        }
      });
    }
}

}  // namespace

void FixedThetaConfig::validate() const {
  if (scan_points < 3) throw std::invalid_argument("sweep: fixed_theta_scan_points must be >= 3");
  if (max_evals < 1) throw std::invalid_argument("sweep: fixed_theta_max_evals must be >= 1");
}

FixedThetaTuning tune_fixed_theta(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                  const EpisodeSetup& setup, const FixedThetaConfig& config, int tuning_phases,
                                  int test_episodes, std::size_t threads) {
  config.validate();
  const double lim = sims->scene().theta_limit_deg * std::numbers::pi / 180.0;
  EvaluationOptions tuning;
  tuning.episodes = tuning_phases;
  tuning.phase_offset = kTuningPhaseOffset;
  tuning.threads = threads;
  tuning.trace_first = false;
  FixedThetaTuning out;
  auto value = [&](double th) {
    EpisodeSetup s = setup;
    s.theta0_rad = th;
    ++out.evaluations;
    return evaluate_design(nullptr, sims, task, s, tuning).mean_return;
  };
  const double lo = -0.95 * lim, hi = 0.95 * lim, step = (hi - lo) / (config.scan_points - 1);
  double best_th = 0.0, best_v = -HUGE_VAL;
  for (int i = 0; i < config.scan_points; ++i) {
    const double th = lo + i * step, v = value(th);
    if (v > best_v) best_v = v, best_th = th;
  }
  SearchOptions so;
  so.method = LocalMethod::Cobyla;
  so.starts = 1;
  so.max_evals = config.max_evals;
  so.xtol_rel = 1e-3;
  so.ftol_abs = 1e-4;
  const SearchBox box{{std::max(lo, best_th - step)}, {std::min(hi, best_th + step)}};
  const SearchResult r = maximise([&](const std::vector<double>& x) { return value(x[0]); }, box, so,
                                  std::vector<double>{best_th});
  if (r.value > best_v) best_v = r.value, best_th = r.x[0];
  out.theta0_rad = best_th;
  out.tuning_return = best_v;
  EvaluationOptions test;
  test.episodes = test_episodes;
  test.threads = threads;
  EpisodeSetup s = setup;
  s.theta0_rad = best_th;
  out.test = evaluate_design(nullptr, sims, task, s, test);
  return out;
}

namespace {

PidSignal signal_of(SweepController c) {
  return c == SweepController::PidForce ? PidSignal::Force
         : c == SweepController::PidStrain ? PidSignal::Strain
                                           : PidSignal::Estimate;
}

}  // namespace

SweepController sweep_controller_from_name(const std::string& name) {
  if (const std::optional<SweepController> c = value_of(kSweepControllerNames, name)) return *c;
  throw std::invalid_argument("unknown sweep controller '" + name + "'; allowed: " + names_list(kSweepControllerNames));
}

void SweepConfig::validate() const {
  if (pressures_kPa.empty()) throw std::invalid_argument("sweep: pressures_kPa must not be empty");
  for (double p : pressures_kPa)
    if (!(p >= 0.0 && std::isfinite(p))) throw std::invalid_argument("sweep: pressures must be finite and >= 0");
  if (controllers.empty()) throw std::invalid_argument("sweep: controllers must not be empty");
  fixed_theta.validate();
  if (first_design < 0 || last_design >= fem::kDesignCount || first_design > last_design)
    throw std::invalid_argument("sweep: designs must be a range within 0..109");
}

std::vector<SweepPoint> sweep_points(const SweepConfig& config) {
  std::vector<SweepPoint> out;
  for (int j = config.first_design; j <= config.last_design; ++j) {
    const int n = fem::design_from_index(j).n;
    for (double p1 : config.pressures_kPa) {
      if (n == 1) {
        out.push_back({j, p1, 0.0});
        continue;
      }
      for (double p2 : config.pressures_kPa) out.push_back({j, p1, p2});
    }
  }
  return out;
}

SweepRow sweep_one(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task, const SweepPoint& point,
                   SweepController controller, const SweepConfig& sweep, const PidTuningConfig& pid) {
  const auto t0 = std::chrono::steady_clock::now();
  const EpisodeSetup setup{point.design, point.p1_kPa, point.p2_kPa, 0.0, 0.0};
  SweepRow row;
  row.point = point;
  row.controller = controller;
  const DesignEvaluation* test = nullptr;
  FixedThetaTuning ft;
  PidTuningResult pt;
  if (controller == SweepController::FixedTheta) {
    ft = tune_fixed_theta(sims, task, setup, sweep.fixed_theta, pid.tuning_phases, pid.test_episodes);
    row.theta0_rad = ft.theta0_rad;
    row.tuning_return = ft.tuning_return;
    row.evaluations = ft.evaluations;
    test = &ft.test;
  } else {
    pt = tune_whisker_pid(sims, task, setup, signal_of(controller), pid);
    if (controller == SweepController::PidEstimate) {
      row.fit_r2 = pt.estimator.fit.r2;
      row.fit_rms_mN = pt.estimator.fit.rms_mN;
    }
    row.gains = pt.pid.gains;
    row.setpoint = pt.pid.setpoint;
    row.tuning_return = pt.tuning_return;
    row.evaluations = pt.evaluations;
    test = &pt.test;
  }
  row.test_return = test->mean_return;
  row.test_std = test->std_return;
  row.band_fraction = test->mean_band_fraction;
  row.test_episodes = static_cast<int>(test->returns.size());
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return row;
}

std::string sweep_csv_header_without_fit() {
  return "j,n,l_mm,w_mm,p1_kPa,p2_kPa,controller,theta0_rad,kp,ki,kd,setpoint,tuning_return,evaluations,"
         "test_return,test_return_std,test_episodes,band_fraction,seconds";
}

std::string sweep_csv_header() { return sweep_csv_header_without_fit() + ",fit_r2,fit_rms_mN"; }

std::string sweep_csv_line(const SweepRow& r) {
  const fem::Design d = fem::design_from_index(r.point.design);
  std::ostringstream o;
  o << r.point.design << ',' << d.n << ',' << CsvLog::num(d.chamber_length_mm) << ',' << CsvLog::num(d.wall_mm) << ','
    << CsvLog::num(r.point.p1_kPa) << ',' << CsvLog::num(r.point.p2_kPa) << ',' << to_string(r.controller) << ','
    << CsvLog::num(r.theta0_rad) << ',' << CsvLog::num(r.gains.kp) << ',' << CsvLog::num(r.gains.ki) << ','
    << CsvLog::num(r.gains.kd) << ',' << CsvLog::num(r.setpoint) << ',' << CsvLog::num(r.tuning_return) << ','
    << r.evaluations << ',' << CsvLog::num(r.test_return) << ',' << CsvLog::num(r.test_std) << ','
    << r.test_episodes << ',' << CsvLog::num(r.band_fraction) << ',' << CsvLog::num(r.seconds) << ','
    << CsvLog::num(r.fit_r2) << ',' << CsvLog::num(r.fit_rms_mN);
  return o.str();
}

std::vector<SweepRow> read_sweep_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<SweepRow> rows;
  std::size_t pos = 0;
  bool header = true;
  std::size_t cells = 21;
  while (pos < text.size()) {
    const std::size_t nl = text.find('\n', pos);
    if (nl == std::string::npos) break;  // a half-written last line: ignored
    const std::string line = text.substr(pos, nl - pos);
    pos = nl + 1;
    if (header) {
      if (line == sweep_csv_header_without_fit())
        cells = 19;
      else if (line != sweep_csv_header())
        throw InputError(path + ": not a sweep.csv of this version (header differs)");
      header = false;
      continue;
    }
    const std::vector<std::string> c = split(line);
    if (c.size() != cells)
      throw InputError(path + ": a row has " + std::to_string(c.size()) + " cells, expected " + std::to_string(cells));
    SweepRow r;
    r.point = {static_cast<int>(to_double(c[0], path)), to_double(c[4], path), to_double(c[5], path)};
    try {
      r.controller = sweep_controller_from_name(c[6]);
    } catch (const std::invalid_argument& e) {
      throw InputError(path + ": " + e.what());
    }
    r.theta0_rad = to_double(c[7], path);
    r.gains = {to_double(c[8], path), to_double(c[9], path), to_double(c[10], path)};
    r.setpoint = to_double(c[11], path);
    r.tuning_return = to_double(c[12], path);
    r.evaluations = static_cast<int>(to_double(c[13], path));
    r.test_return = to_double(c[14], path);
    r.test_std = to_double(c[15], path);
    r.test_episodes = static_cast<int>(to_double(c[16], path));
    r.band_fraction = to_double(c[17], path);
    r.seconds = to_double(c[18], path);
    if (cells == 21) r.fit_r2 = to_double(c[19], path), r.fit_rms_mN = to_double(c[20], path);
    rows.push_back(r);
  }
  return rows;
}

SweepSummary run_sweep(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task, const SweepConfig& sweep,
                       const PidTuningConfig& pid, const SweepOptions& options) {
  sweep.validate();
  pid.validate();
  const auto t_start = std::chrono::steady_clock::now();
  const fs::path dir(options.dir);
  const fs::path csv = dir / "sweep.csv", cfg = dir / "sweep.config.toml";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create output directory: " + ec.message());
  // Resume only a sweep of the same config.
  std::vector<SweepRow> done;
  if (fs::exists(csv, ec)) {
    std::ifstream in(cfg, std::ios::binary);
    std::string earlier((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const bool same = in.good() || in.eof() ? earlier == options.config_text : false;
    if (!same && (!options.force || options.report_only))
      throw InputError(dir.string() + ": holds sweep.csv of a sweep with another config (" + cfg.string() +
                       (options.report_only ? "); report with that config"
                                            : "); choose another -o or pass --force to start afresh"));
    if (same && (!options.force || options.report_only)) {
      done = read_sweep_csv(csv.string());
      if (!options.report_only) {
        std::ifstream head(csv, std::ios::binary);
        std::string first;
        std::getline(head, first);
        if (first == sweep_csv_header_without_fit())
          throw InputError(csv.string() + ": is a sweep.csv of the previous version (no fit_r2, fit_rms_mN columns); "
                           "report it with --report, or choose another -o or pass --force to start afresh");
      }
      // Cut a half-written last line, so appends start on a fresh line (not when only reporting:
      // a sweep may still be appending).
      if (!options.report_only) {
        std::ifstream whole(csv, std::ios::binary);
        std::string text((std::istreambuf_iterator<char>(whole)), std::istreambuf_iterator<char>());
        fs::resize_file(csv, text.rfind('\n') + 1);
      }
    } else {
      fs::remove(csv);
    }
  }
  if (options.report_only) {
    if (!fs::exists(csv, ec)) throw InputError(dir.string() + ": has no sweep.csv to report on");
    SweepSummary summary;
    summary.rows = done;
    summary.rows_done_before = static_cast<int>(done.size());
    summary.rows_total = static_cast<int>(sweep_points(sweep).size() * sweep.controllers.size());
    write_heatmaps(dir, summary.rows, sweep);
    summary.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    return summary;
  }
  if (!fs::exists(csv, ec)) {
    io::write_file_atomically(cfg.string(), [&](std::ostream& out) { out << options.config_text; });
    io::write_file_atomically(csv.string(), [&](std::ostream& out) { out << sweep_csv_header() << '\n'; });
  }
  std::set<RowKey> have;
  for (const SweepRow& r : done) have.insert(key(r.point, r.controller));

  const std::vector<SweepPoint> points = sweep_points(sweep);
  struct Unit {
    SweepPoint point;
    std::vector<SweepController> todo;
  };
  std::vector<Unit> units;
  SweepSummary summary;
  summary.rows_total = static_cast<int>(points.size() * sweep.controllers.size());
  for (const SweepPoint& p : points) {
    Unit u{p, {}};
    for (SweepController c : sweep.controllers)
      if (!have.count(key(p, c))) u.todo.push_back(c);
    if (!u.todo.empty()) units.push_back(u);
  }
  summary.rows_done_before = static_cast<int>(have.size());
  // Run the units in a spread-out order (a stride coprime to their count), so a sweep stopped
  // early has covered the whole l × w × n grid coarsely rather than its first designs only.
  if (units.size() > 2) {
    std::size_t stride = units.size() * 5 / 11 + 1;
    while (std::gcd(stride, units.size()) != 1) ++stride;
    std::vector<Unit> spread(units.size());
    for (std::size_t i = 0; i < units.size(); ++i) spread[i] = units[i * stride % units.size()];
    units = std::move(spread);
  }

  std::FILE* f = std::fopen(csv.c_str(), "ab");
  if (!f) throw InputError(csv.string() + ": cannot open for appending");
  std::mutex mutex;
  std::vector<SweepRow> fresh;
  std::size_t units_done = 0;
  rl::ThreadPool pool(options.threads);
  if (options.progress) {
    std::printf("sweep: %zu designs x pressures to run (%d of %d rows done before), %zu threads\n", units.size(),
                summary.rows_done_before, summary.rows_total, pool.size());
    std::fflush(stdout);
  }
  try {
    pool.parallel_for(units.size(), [&](std::size_t i) {
      const Unit& u = units[i];
      std::string line_summary;
      for (SweepController c : u.todo) {
        const SweepRow r = sweep_one(sims, task, u.point, c, sweep, pid);
        const std::string line = sweep_csv_line(r) + "\n";
        std::lock_guard lock(mutex);
        if (std::fwrite(line.data(), 1, line.size(), f) != line.size() || std::fflush(f) != 0)
          throw std::runtime_error(csv.string() + ": write failed");
        fresh.push_back(r);
        char buf[96];
        std::snprintf(buf, sizeof buf, " %s %.2f", to_string(c), r.test_return);
        line_summary += buf;
      }
      std::lock_guard lock(mutex);
      ++units_done;
      if (options.progress) {
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
        const double eta = el / static_cast<double>(units_done) * static_cast<double>(units.size() - units_done);
        std::printf("sweep: %zu/%zu | %s elapsed | ETA %s | j%d p=[%g, %g]:%s\n", units_done, units.size(),
                    duration_text(el).c_str(), duration_text(eta).c_str(), u.point.design, u.point.p1_kPa, u.point.p2_kPa,
                    line_summary.c_str());
        std::fflush(stdout);
      }
    });
  } catch (...) {
    std::fclose(f);
    throw;
  }
  std::fclose(f);
  summary.rows_run = static_cast<int>(fresh.size());
  summary.rows = read_sweep_csv(csv.string());
  write_heatmaps(dir, summary.rows, sweep);
  summary.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return summary;
}

}  // namespace codesign::core
