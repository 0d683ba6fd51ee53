#pragma once
// The run folder's result files: result.toml and the evaluation CSVs, with the one writer and
// the one reader of each (docs/run_folder.md, "Files"). The run writes result.toml and
// eval/{best,runner_up}*.csv; `baseline pid` writes eval/<controller>*.csv in its folder;
// render, figures and refine read result.toml; refine appends its [refined] table.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/evaluation.hpp"
#include "core/force_estimator.hpp"
#include "core/refine.hpp"
#include "core/whisker_env.hpp"

namespace codesign::run {

// The names of a run folder's files and folders (docs/run_folder.md, "Files"): every
// module of the run layer opens them by these names.
namespace run_file {
inline constexpr const char* kConfig = "config.toml";             // the resolved config
inline constexpr const char* kConfigInput = "config.input.toml";  // the config file as given
inline constexpr const char* kCheckpoint = "checkpoint.bin";      // the latest state
inline constexpr const char* kCheckpointT1 = "checkpoint_t1.bin"; // the state kept at T1
inline constexpr const char* kCheckpointT2 = "checkpoint_t2.bin"; // the state kept at T2
inline constexpr const char* kEpisodes = "episodes.csv";          // the logs, a row per ...
inline constexpr const char* kPpo = "ppo.csv";                    //   PPO update
inline constexpr const char* kDistribution = "distribution.csv";  //   distribution update
inline constexpr const char* kQDisc = "q_disc.csv";               //   update, q_disc of every design
inline constexpr const char* kSampled = "sampled.csv";            //   sampled design
inline constexpr const char* kResult = "result.toml";
inline constexpr const char* kPolicy = "policy.bin";
inline constexpr const char* kEvalDir = "eval";             // <which>.csv, <which>_trace.csv
inline constexpr const char* kFramesDir = "frames";         // frames/<which>/frame_NNNN.png
inline constexpr const char* kFiguresDir = "figures";       // figures/*.png, figures/data/
inline constexpr const char* kEvaluateDir = "evaluate";     // evaluate/<at>/ of `codesign evaluate`
}  // namespace run_file

// One evaluated design of result.toml: [best] (d* at p*) or [runner_up].
struct ResultDesign {
  core::EpisodeSetup setup;  // design, p1_kPa, p2_kPa (the plate phase is not stored)
  double test_return = 0.0;      // mean over the test episodes
  double test_return_std = 0.0;
  int test_episodes = 0;
  double band_fraction = 0.0;    // decisions with F inside the band
};
ResultDesign result_design(const core::DesignEvaluation& e);

// [best_fixed_theta]: d* at p* with the base held at its best constant angle.
struct ResultFixedTheta {
  double theta0_rad = 0.0;
  int tuning_phases = 0;
  double test_return = 0.0, test_return_std = 0.0, band_fraction = 0.0;
};

// [run]: what produced the result.
struct ResultRun {
  std::int64_t timesteps = 0, iterations = 0;
  std::uint64_t seed = 0;
  std::string observation;  // task observation name
  std::string baseline;     // "none" | "single_design"
  std::int64_t numerical_failures = 0;
  double wall_s = 0.0;      // wall-clock: the only field that differs between reruns
};

// The contents of result.toml.
struct ResultFile {
  int eval_episodes = 0;  // the test plate phases 2π(k + 1/2)/eval_episodes
  ResultDesign best;
  std::optional<ResultDesign> runner_up;
  std::optional<ResultFixedTheta> fixed_theta;
  ResultRun run;
};

// Writes DIR/result.toml atomically.
void write_result(const std::filesystem::path& run_dir, const ResultFile& r);

// The name of a run folder as given: its last path component, "runs/b/" and "runs/b" alike
// naming "b".
std::string run_folder_name(const std::string& dir);

// Table `which` ("best" or "runner_up") of DIR/result.toml; nullopt when the file has no such
// table. A missing or unreadable file, or a key out of range, is an InputError naming the file
// and the key. Pressures must lie in [0, pressure_max_kPa] (refine passes the run's
// task.pressure_max_kPa; the default only rules out nonsense).
std::optional<ResultDesign> read_result_design(const std::filesystem::path& run_dir, const std::string& which,
                                               double pressure_max_kPa = 1e3);

// result.toml's text with the [refined] table of `r` appended (an earlier [refined] table is
// removed; all other bytes are kept as they are).
std::string with_refined_table(const std::string& result_toml, const core::RefineResult& r);

// Appends (or replaces) the [refined] table of DIR/result.toml, keeping the rest of its text.
void write_refined_result(const std::filesystem::path& run_dir, const core::RefineResult& r);

// DIR/<which>.csv (one row per test episode: phase, return, decisions, band fraction, end
// reason) and DIR/<which>_trace.csv (the first test episode decision by decision: time, θ, F,
// strain, tip position, plate height, action; with an estimator also F̂(ε, θ) as F_hat_mN).
// DIR is the run folder's eval/ folder; it is created when missing.
void write_evaluation(const std::filesystem::path& dir, const std::string& which, const core::DesignEvaluation& e,
                      const core::ForceEstimator* estimator = nullptr);

// One row of eval/<which>_trace.csv as the figures read it.
struct TracePoint {
  double t_s = 0, theta_rad = 0, force_mN = 0;
};
// The first test episode of `which` in the run folder: eval/<which>_trace.csv row by row, and that
// episode's return (row 0 of eval/<which>.csv; NaN when that file is missing or empty). nullopt
// when the trace file is missing; a malformed file is an InputError naming it.
struct EvaluationTrace {
  std::vector<TracePoint> points;
  double first_return = 0.0;
};
std::optional<EvaluationTrace> read_evaluation_trace(const std::filesystem::path& run_dir, const std::string& which);

}  // namespace codesign::run
