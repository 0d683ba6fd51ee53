#pragma once
// What a completed run reports: the contents of result.toml (run_folder.hpp writes it) and the
// run's closing lines on stdout.
#include <cstdint>
#include <filesystem>

#include "core/outer_loop.hpp"
#include "run/final_evaluation.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

// result.toml of a run that trained `timesteps` decisions in `iterations` iterations, with
// `numerical_failures` training episodes ended by a numerical failure, in wall_s seconds over all
// its sessions.
ResultFile final_result(const FinalEvaluation& evaluation, const core::LoopConfig& lc, std::int64_t timesteps,
                        std::int64_t iterations, std::int64_t numerical_failures, double wall_s);

// The closing lines: d* and its test, the fixed-angle reference, the runner-up, numerical
// failures, where result.toml is.
void print_result(const std::filesystem::path& run_dir, const ResultFile& result, const FinalEvaluation& evaluation);

}  // namespace codesign::run
