#pragma once
// `codesign survey`'s folder: DIR/survey.csv (one row per design, core::survey_designs) and the
// printed summary: the strain ranges over every design with the suggested [task] strain_min /
// strain_max and zeroed_strain_min / zeroed_strain_max (the measured range widened by 10 % on
// each side), and the best fixed-θ returns.
#include <string>

#include "core/design_survey.hpp"
#include "run/run_config.hpp"

namespace codesign::run {

struct SurveyRunOptions {
  core::SurveyOptions survey;
  std::string out;     // DIR
  int threads = 0;     // 0: one per core
  bool force = false;  // overwrite an earlier survey.csv
};

// Throws InputError, before any episode runs, if DIR holds survey.csv and `force` is off, or
// cannot be created.
void run_survey(const RunConfig& config, const SurveyRunOptions& options);

}  // namespace codesign::run
