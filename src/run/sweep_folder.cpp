#include "run/sweep_folder.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "base/duration_text.hpp"
#include "base/errors.hpp"
#include "base/seconds_since.hpp"
#include "fem/design.hpp"
#include "io/formats/atomic_file.hpp"
#include "io/formats/csv_log.hpp"
#include "rl/thread_pool.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's sweep types (src/core)

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

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The rows DIR/sweep.csv holds of a sweep of this config (a half-written last line cut, unless
// only reporting: a sweep may still be appending); none, with sweep.csv removed, when `force`
// starts afresh. DIR is created. Another config's sweep without `force` (or with report_only), or
// a sweep.csv of the previous version to append to, is an InputError.
std::vector<SweepRow> open_sweep_folder(const fs::path& dir, const SweepOptions& options) {
  const fs::path csv = dir / "sweep.csv", cfg = dir / "sweep.config.toml";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create output directory: " + ec.message());
  std::vector<SweepRow> done;
  if (!fs::exists(csv, ec)) return done;
  std::ifstream in(cfg, std::ios::binary);
  std::string earlier((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const bool same = in.good() || in.eof() ? earlier == options.config_text : false;
  if (!same && (!options.force || options.report_only))
    throw InputError(dir.string() + ": holds sweep.csv of a sweep with another config (" + cfg.string() +
                     (options.report_only ? "); report with that config"
                                          : "); choose another -o or pass --force to start afresh"));
  if (!same || (options.force && !options.report_only)) {
    fs::remove(csv);
    return done;
  }
  done = read_sweep_csv(csv.string());
  if (options.report_only) return done;
  std::ifstream head(csv, std::ios::binary);
  std::string first;
  std::getline(head, first);
  if (first == sweep_csv_header_without_fit())
    throw InputError(csv.string() + ": is a sweep.csv of the previous version (no fit_r2, fit_rms_mN columns); "
                     "report it with --report, or choose another -o or pass --force to start afresh");
  fs::resize_file(csv, slurp(csv).rfind('\n') + 1);
  return done;
}

// A design at one pressure pair with the controllers it still needs.
struct Unit {
  SweepPoint point;
  std::vector<SweepController> todo;
};

std::vector<Unit> pending_units(const SweepConfig& sweep, const std::set<RowKey>& have) {
  std::vector<Unit> units;
  for (const SweepPoint& p : sweep_points(sweep)) {
    Unit u{p, {}};
    for (SweepController c : sweep.controllers)
      if (!have.count(key(p, c))) u.todo.push_back(c);
    if (!u.todo.empty()) units.push_back(u);
  }
  return units;
}

// The units in a spread-out order (a stride coprime to their count), so a sweep stopped early has
// covered the whole l × w × n grid coarsely rather than its first designs only.
std::vector<Unit> spread_out(std::vector<Unit> units) {
  if (units.size() <= 2) return units;
  std::size_t stride = units.size() * 5 / 11 + 1;
  while (std::gcd(stride, units.size()) != 1) ++stride;
  std::vector<Unit> spread(units.size());
  for (std::size_t i = 0; i < units.size(); ++i) spread[i] = units[i * stride % units.size()];
  return spread;
}

// Runs the units on the pool, each row appended to csv as it finishes; returns the rows run.
int run_units(const std::vector<Unit>& units, const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
              const SweepConfig& sweep, const PidTuningConfig& pid, const fs::path& csv, rl::ThreadPool& pool,
              bool progress, std::chrono::steady_clock::time_point t_start) {
  std::FILE* f = std::fopen(csv.c_str(), "ab");
  if (!f) throw InputError(csv.string() + ": cannot open for appending");
  std::mutex mutex;
  int rows_run = 0;
  std::size_t units_done = 0;
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
        ++rows_run;
        char buf[96];
        std::snprintf(buf, sizeof buf, " %s %.2f", to_string(c), r.test_return);
        line_summary += buf;
      }
      std::lock_guard lock(mutex);
      ++units_done;
      if (progress) {
        const double el = seconds_since(t_start);
        const double eta = el / static_cast<double>(units_done) * static_cast<double>(units.size() - units_done);
        std::printf("sweep: %zu/%zu | %s elapsed | ETA %s | j%d p=[%g, %g]:%s\n", units_done, units.size(),
                    duration_text(el).c_str(), duration_text(eta).c_str(), u.point.design, u.point.p1_kPa,
                    u.point.p2_kPa, line_summary.c_str());
        std::fflush(stdout);
      }
    });
  } catch (...) {
    std::fclose(f);
    throw;
  }
  std::fclose(f);
  return rows_run;
}

}  // namespace

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
  const fs::path csv = dir / "sweep.csv";
  const std::vector<SweepRow> done = open_sweep_folder(dir, options);
  SweepSummary summary;
  summary.rows_total = static_cast<int>(sweep_points(sweep).size() * sweep.controllers.size());
  std::error_code ec;
  if (options.report_only) {
    if (!fs::exists(csv, ec)) throw InputError(dir.string() + ": has no sweep.csv to report on");
    summary.rows = done;
    summary.rows_done_before = static_cast<int>(done.size());
    write_heatmaps(dir, summary.rows, sweep);
    summary.wall_s = seconds_since(t_start);
    return summary;
  }
  if (!fs::exists(csv, ec)) {
    io::write_file_atomically((dir / "sweep.config.toml").string(), [&](std::ostream& out) { out << options.config_text; });
    io::write_file_atomically(csv.string(), [&](std::ostream& out) { out << sweep_csv_header() << '\n'; });
  }
  std::set<RowKey> have;
  for (const SweepRow& r : done) have.insert(key(r.point, r.controller));
  summary.rows_done_before = static_cast<int>(have.size());
  const std::vector<Unit> units = spread_out(pending_units(sweep, have));

  rl::ThreadPool pool(options.threads);
  if (options.progress) {
    std::printf("sweep: %zu designs x pressures to run (%d of %d rows done before), %zu threads\n", units.size(),
                summary.rows_done_before, summary.rows_total, pool.size());
    std::fflush(stdout);
  }
  summary.rows_run = run_units(units, sims, task, sweep, pid, csv, pool, options.progress, t_start);
  summary.rows = read_sweep_csv(csv.string());
  write_heatmaps(dir, summary.rows, sweep);
  summary.wall_s = seconds_since(t_start);
  return summary;
}

}  // namespace codesign::run
