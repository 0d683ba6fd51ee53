// `codesign bench telemetry [--config configs/quick.toml] [--iterations N] [--url URL] [--threads N]`
//
// What live telemetry costs a run. The same co-design run (the config's Algorithm 1, first N
// iterations, checkpoints and CSV logs included, no final evaluation) twice in temporary
// folders: with telemetry off, then on (default: an LCM log file in the temporary folder, i.e.
// every message encoded and written; or any URL, e.g. tcpq://127.0.0.1:7700). The run measures
// the wall time it spends filling, encoding and sending messages (RunResult::telemetry_s); the
// headline is that time as a share of the run's wall time (goal < 1 %). The ratio of the two wall
// times is printed too, but on a shared machine its noise exceeds the effect.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "base/errors.hpp"
#include "run/run.hpp"
#include "run/run_config.hpp"
#include "cli_options.hpp"
#include "commands.hpp"

namespace codesign::app {

namespace {

namespace fs = std::filesystem;

struct BenchTelemetryOptions {
  std::string config = "configs/quick.toml";
  int iterations = 10;
  std::string url;  // "" = a file:// log in the temporary folder
  int threads = 0;
};

// A fresh folder under the system's temporary directory, removed when this goes out of scope.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "codesign_bench_telemetry_XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("cannot create a temporary folder");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

int run_bench_telemetry(const BenchTelemetryOptions& o) {
  const run::RunConfig setup = run::read_run_config(o.config);
  std::ifstream in(o.config, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const run::RunSettings s = run::run_settings(setup, text.str());
  const std::int64_t per_iteration =
      static_cast<std::int64_t>(setup.codesign.designs_per_update) * setup.ppo.n_steps;
  const std::int64_t stop = per_iteration * o.iterations;
  if (stop >= setup.codesign.total_timesteps) {
    throw InputError(o.config + ": codesign.total_timesteps = " + std::to_string(setup.codesign.total_timesteps) +
                     " ends the run within --iterations " + std::to_string(o.iterations) +
                     "; allowed: fewer iterations than the run has");
  }

  TempDir tmp;
  const std::string url = o.url.empty() ? "file://" + (tmp.path() / "bench.lcm").string() + "?mode=w" : o.url;
  std::printf("bench telemetry: %s, %d iterations (%lld timesteps), train_decision_every %d, URL %s\n", o.config.c_str(),
              o.iterations, static_cast<long long>(stop), setup.telemetry_train_every, url.c_str());
  auto run = [&](const std::string& name, const std::string& telemetry_url) {
    run::RunOptions ro;
    ro.dir = (tmp.path() / name).string();
    ro.threads = static_cast<std::size_t>(o.threads);
    ro.progress = false;
    ro.stop_after = stop;
    ro.telemetry_url = telemetry_url;
    ro.telemetry_train_every = setup.telemetry_train_every;
    return run::run_codesign(s, ro);
  };
  const run::RunResult off = run("off", "");
  std::printf("  telemetry off: %.2f s\n", off.wall_s);
  const run::RunResult on = run("on", url);
  std::printf("  telemetry on:  %.2f s, %lld messages", on.wall_s, static_cast<long long>(on.telemetry_messages));
  const fs::path log = tmp.path() / "bench.lcm";
  std::error_code ec;
  if (o.url.empty() && fs::exists(log, ec)) std::printf(" (log file %.1f MB)", static_cast<double>(fs::file_size(log, ec)) / 1e6);
  std::printf("\n");
  const double share = on.telemetry_s / std::max(on.wall_s, 1e-9);
  std::printf("  publishing: %.4f s = %.3f %% of the run's wall time (%.1f us per message)   goal < 1 %%: %s\n",
              on.telemetry_s, 100.0 * share,
              1e6 * on.telemetry_s / static_cast<double>(std::max<std::int64_t>(1, on.telemetry_messages)),
              share < 0.01 ? "met" : "NOT met");
  std::printf("  wall time on / off: %.3f (noise of this machine included)\n", on.wall_s / std::max(off.wall_s, 1e-9));
  return 0;
}

}  // namespace

void add_bench_telemetry_command(CLI::App& bench, Runner& run) {
  auto opt = std::make_shared<BenchTelemetryOptions>();
  CLI::App* cmd = bench.add_subcommand("telemetry", "What live telemetry costs a co-design run (off vs on)");
  cmd->add_option("--config", opt->config, "run config (TOML)");
  cmd->add_option("--iterations", opt->iterations, "iterations of Algorithm 1 per run")->check(CLI::Range(1, 100000));
  cmd->add_option("--url", opt->url, "LCM URL for the run with telemetry (default: a file:// log in a temporary folder)");
  add_threads_option(*cmd, opt->threads, "rollout threads, counting the main one (0: all cores)");
  cmd->callback([opt, &run] { run = [opt] { return run_bench_telemetry(*opt); }; });
}

}  // namespace codesign::app
