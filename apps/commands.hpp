#pragma once
// Sub-commands of the `codesign` binary. Each apps/cmd_*.cpp (or apps/bench/bench_*.cpp) adds its own
// sub-command to the parent it is given and, when the user selects it, stores in `run` the
// work to do. main.cpp parses the command line, then calls `run` and returns its exit code.
// Errors in user input are thrown as codesign::InputError (base/errors.hpp); main prints them
// and exits with 2.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace codesign::app {

using Runner = std::function<int()>;

void add_run_command(CLI::App& root, Runner& run);        // cmd_run.cpp (the main job)
void add_survey_command(CLI::App& root, Runner& run);     // cmd_survey.cpp
void add_mesh_command(CLI::App& root, Runner& run);       // cmd_mesh.cpp
void add_sim_command(CLI::App& root, Runner& run);        // cmd_sim.cpp
void add_train_gym_command(CLI::App& root, Runner& run);  // cmd_train_gym.cpp
void add_figures_command(CLI::App& root, Runner& run);    // cmd_figures.cpp
void add_render_command(CLI::App& root, Runner& run);     // cmd_render.cpp
void add_check_command(CLI::App& root, Runner& run);      // cmd_check.cpp
void add_config_keys_command(CLI::App& root, Runner& run);  // cmd_config_keys.cpp
void add_baseline_command(CLI::App& root, Runner& run);   // cmd_baseline.cpp (`baseline pid`)
void add_sweep_command(CLI::App& root, Runner& run);      // cmd_sweep.cpp
void add_refine_command(CLI::App& root, Runner& run);     // cmd_refine.cpp
void add_evaluate_command(CLI::App& root, Runner& run);   // cmd_evaluate.cpp
void add_verify_command(CLI::App& root, Runner& run);     // cmd_verify.cpp
// `codesign bench <what>`: main.cpp creates the `bench` parent.
void add_bench_fem_command(CLI::App& bench, Runner& run);  // bench/bench_fem.cpp
void add_bench_ppo_command(CLI::App& bench, Runner& run);  // bench/bench_ppo.cpp
void add_bench_codesign_command(CLI::App& bench, Runner& run);  // bench/bench_codesign.cpp
void add_bench_cluster_command(CLI::App& bench, Runner& run);   // bench/bench_cluster.cpp
void add_bench_telemetry_command(CLI::App& bench, Runner& run);  // bench/bench_telemetry.cpp
void add_bench_render_command(CLI::App& bench, Runner& run);  // bench/bench_render.cpp

}  // namespace codesign::app
