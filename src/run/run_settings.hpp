#pragma once
// What a co-design run runs: its simulator tables and its loop ([task], [codesign], [ppo]), as
// read from a run config. Shared by the run (run.hpp), its rollout backends and its evaluation.
#include <string>

#include "core/outer_loop.hpp"
#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"
#include "run/run_config.hpp"

namespace codesign::run {

struct RunSettings {
  fem::WhiskerModelSpec spec;
  fem::SceneConfig scene;
  fem::SolverConfig solver;
  core::LoopConfig loop;
  std::string config_text;   // the config file's text (copied to config.input.toml)
};
// The settings of a run of `config` (its simulator tables and its [task], [codesign], [ppo]).
RunSettings run_settings(const RunConfig& config, std::string config_text = {});

}  // namespace codesign::run
