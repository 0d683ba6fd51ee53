#pragma once
// `codesign verify`: the specialists first, when asked for (a fresh policy trained on each of the
// run's policy subjects' designs alone, at its pressures, per seed: what the dedicated configs
// did by hand), then the verify of the run with them as subjects (run/verify_run.hpp).
//
// A specialist is an ordinary single-design run folder, RUN/verify/specialists/j<J>_s<SEED>/,
// made from RUN/verify/specialists/j<J>_s<SEED>.toml: the run's config.toml extended with
// codesign.baseline = "single_design", the design, its pressures, the budget and the seed. One that
// finished is reused; one stopped by a signal resumes from its checkpoint at the next call.
#include <cstdint>
#include <vector>

#include "run/verify_run.hpp"

namespace codesign::run {

struct VerifyJobOptions {
  VerifyOptions verify;
  bool specialists = false;
  std::int64_t specialist_timesteps = 100000;  // decisions of each specialist's training
  std::vector<int> specialist_seeds{1};
};

// Returns the exit status: 0, or 128 + signal when SIGTERM/SIGINT stopped a specialist's training
// (checkpointed; the next call resumes it). InputError as verify_run.
int run_verify_job(const VerifyJobOptions& options);

}  // namespace codesign::run
