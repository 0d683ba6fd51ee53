#include "verify_job.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "base/duration_text.hpp"
#include "base/errors.hpp"
#include "io/config/toml_reader.hpp"
#include "io/formats/run_lock.hpp"
#include "io/formats/csv_log.hpp"
#include "run/folder_lock.hpp"
#include "run/run.hpp"
#include "run/run_config.hpp"
#include "run/run_folder.hpp"
#include "run/run_settings.hpp"
#include "run/stop_signals.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;

// The specialist's config: the run's resolved config with the design fixed and the budget set.
std::string specialist_config(const fs::path& run_config, const DesignAtPressures& at, std::int64_t timesteps,
                              int seed) {
  using io::CsvLog;
  return "# A specialist of `codesign verify --specialists`: the run's config, trained on one design alone\n"
         "extends = \"" + fs::absolute(run_config).string() + "\"\n\n[codesign]\nbaseline = \"single_design\"\n" +
         "single_design_index = " + std::to_string(at.design) + "\nsingle_design_p1_kPa = " + CsvLog::num(at.p1_kPa) +
         "\nsingle_design_p2_kPa = " + CsvLog::num(at.p2_kPa) + "\ntotal_timesteps = " + std::to_string(timesteps) +
         "\nseed = " + std::to_string(seed) + "\n";
}

}  // namespace

int run_verify_job(const VerifyJobOptions& o) {
  VerifyOptions vo = o.verify;
  if (o.specialists) {
    const fs::path dir(vo.dir), folder = dir / "verify" / "specialists";
    const StopSignals signals;
    for (const VerifySubject& s : verify_plan(vo)) {
      // The run's own designs; another run's d* has a policy of its own run already.
      if (s.controller != kControllerPolicy || s.name.rfind("d*_of_", 0) == 0) continue;
      for (const int seed : o.specialist_seeds) {
        const std::string name = "j" + std::to_string(s.at.design) + "_s" + std::to_string(seed);
        const fs::path out = folder / name, toml = folder / (name + ".toml");
        if (!fs::exists(out / run_file::kResult)) {
          fs::create_directories(folder);
          std::ofstream(toml) << specialist_config(dir / run_file::kConfig, s.at, o.specialist_timesteps, seed);
          const RunConfig config = read_run_config(toml.string());
          const bool resume = fs::exists(out / run_file::kCheckpoint);
          std::printf("verify: specialist %s (%s) %s for %lld decisions\n", name.c_str(), s.name.c_str(),
                      resume ? "resumes" : "trains", static_cast<long long>(o.specialist_timesteps));
          std::fflush(stdout);
          const std::unique_ptr<io::RunLock> lock = lock_run_folder(out.string(), /*only_if_exists=*/resume);
          RunOptions ro;
          ro.lock = lock.get();
          ro.dir = out.string();
          ro.resume = resume;
          ro.threads = vo.threads;
          ro.progress = vo.progress;
          const RunResult r = run_codesign(run_settings(config, io::TableReader::input_text(toml.string())), ro);
          if (r.stop_signal != 0) return 128 + r.stop_signal;
          if (!r.completed) return 4;
        }
        vo.specialists.push_back({"own_" + name, (out / run_file::kPolicy).string(), s.at, seed});
      }
    }
  }
  const VerifySummary s = verify_run(vo);
  std::printf("verify: %d cells run now, %d before -> %s/report.md\n", s.cells_run, s.cells_before, s.folder.c_str());
  if (s.episodes_run > 0)
    std::printf("verify: %s wall, %.0f s of CPU, for %d episodes (%.2f s of CPU each, the PIDs' tuning included)\n",
                duration_text(s.wall_s).c_str(), s.cpu_s, s.episodes_run, s.cpu_s / s.episodes_run);
  if (!s.figure_message.empty()) std::printf("verify: no verify.png: %s\n", s.figure_message.c_str());
  return 0;
}

}  // namespace codesign::run
