#pragma once
// The run config: every table a config file may hold, read once by one reader and shared by
// every sub-command (the run, sim, baselines, sweep, render, check, evaluate, refine, the
// benchmarks). Each table has one reader (io/config/fem_config.hpp, io/config/mesh_config.hpp,
// run/codesign_tables_reader.hpp, io/config/gym_config.hpp for [ppo], io/config/render_config.hpp) and one writer
// (io/config/config_writer.hpp and run/codesign_tables_writer.hpp); this file only puts them together.
#include <memory>
#include <string>

#include "core/codesign_config.hpp"
#include "core/design_sweep.hpp"
#include "core/pid_tuning.hpp"
#include "core/task_config.hpp"
#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"
#include "io/config/fem_config.hpp"
#include "io/config/render_config.hpp"
#include "io/config/toml_reader.hpp"
#include "rl/ppo.hpp"

namespace codesign::run {

struct RunConfig {
  fem::WhiskerModelSpec spec;
  fem::SceneConfig scene;
  fem::SolverConfig solver;
  fem::SimScenario scenario;
  core::TaskConfig task;          // [task]
  core::CodesignConfig codesign;  // [codesign]
  rl::PpoConfig ppo;               // [ppo] over the paper's settings (rl::paper_ppo_config)
  core::PidTuningConfig pid;      // [pid]: PID baseline tuning
  core::SweepConfig sweep;        // [sweep]: the design landscape
  std::string telemetry_url;       // [telemetry] url: LCM URL, "" = off
  int telemetry_train_every = 2;   // [telemetry] train_decision_every: every N-th decision of training env 0 (0 = none)
  io::RenderConfig render;         // [render]: PNG frames (docs/rendering.md)
};

template <class V>
void describe_telemetry_table(V& v, std::string& url, int& train_decision_every) {
  v.text({"url", "", "LCM URL the run publishes to (docs/telemetry.md; \"\": none)"}, url);
  v.integer({"train_decision_every", "", "every N-th decision of training environment 0 is published (0: none)"},
            train_decision_every, {0, 1000000});
}

// Reads [geometry], [mesh], [fibres] (layout + stiffness), [material], [scene], [solver], [sim]
// from the file, and validates
// the other known tables of a run config ([task], [codesign], [ppo]) so one file serves all
// commands; then root.finish() (unknown tables/keys are errors). An empty path gives defaults.
RunConfig read_run_config(const std::string& config_path);
// The same from a parsed config (tests/fuzz/fuzz_config.cpp feeds it TOML text).
RunConfig read_run_config(io::TableReader& root);

}  // namespace codesign::run
