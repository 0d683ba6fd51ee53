#pragma once
// `codesign refine` (docs/baselines.md, "`codesign refine`"): polishes p* of a finished co-design run
// (core::refine_pressures). Reads DIR/config.toml (the resolved config), DIR/policy.bin and
// DIR/result.toml's [best]; keeps the policy and j* fixed; NLopt searches p in [0, p_max] (p2 = 0
// for one chamber) on tuning phases; tests p* before and after on the run's evaluation phases;
// appends a [refined] table to DIR/result.toml, leaving the rest of the file byte for byte as it
// was. Holds the run folder's lock meanwhile.
#include <string>

#include "core/nlopt_search.hpp"

namespace codesign::run {

struct RefineRunOptions {
  std::string run;                 // DIR
  int phases = 4;                  // tuning plate phases per evaluation
  int starts = 2;                  // NLopt starts
  int max_evals = 20;              // evaluations over all starts, ≥ starts
  std::string method = core::to_string(core::LocalMethod::Bobyqa);  // a name of core::kLocalMethodNames
  int threads = 0;                 // 0: one per core
};

// Bad input (a folder that is not a finished run, a live run's folder, max_evals < starts, a
// policy that does not fit the run's task) is an InputError before any episode.
void refine_run(const RefineRunOptions& options);

}  // namespace codesign::run
