#pragma once
// The run's CSV logs (docs/run_folder.md, "Files"): episodes.csv, ppo.csv, distribution.csv,
// q_disc.csv and sampled.csv, opened together, cut back together to a checkpoint on --resume,
// and given their rows of each iteration together.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "core/design_distribution.hpp"
#include "core/outer_loop.hpp"
#include "io/formats/csv_log.hpp"
#include "run/distribution_summary.hpp"

namespace codesign::run {

class RunLogs {
 public:
  // New logs in DIR, or (resume: the checkpoint's byte length of each log) the logs of DIR cut
  // back to those lengths. The cut happens only once every log fits its length, so a resume that
  // fails leaves every file as it was. distribution.csv has a target_entropy column after entropy
  // under the entropy schedule; under the ramp its columns are those of runs from before the
  // schedule existed. physics: episodes.csv carries each episode's physics draw (physics_columns(),
  // before the reason, which stays last), for runs under [randomize]; walls: and the cast wall's
  // offset after them, for runs that draw it.
  RunLogs(const std::filesystem::path& dir, const std::map<std::string, std::uint64_t>* resume, bool target_entropy,
          bool physics = false, bool walls = false);

  // The rows of one iteration: its episodes, its PPO update, the distribution after it (its
  // summary and every design's q_disc) and the designs it sampled with their q_cont after it.
  void write_iteration(const core::IterationReport& rep, const core::DesignDistribution& dist,
                       const DistributionSummary& summary, double steps_per_s);

  // Writes what is buffered; returns each log's byte length (what a checkpoint records).
  std::map<std::string, std::uint64_t> flush();

  // Rows of DIR/episodes.csv whose reason is a numerical failure (0 if there is no such file): the
  // count a resumed run starts from.
  static std::int64_t numerical_failures_logged(const std::filesystem::path& dir);

 private:
  bool physics_ = false, walls_ = false;
  std::unique_ptr<io::CsvLog> episodes_, ppo_, distribution_, q_, sampled_;
};

}  // namespace codesign::run
