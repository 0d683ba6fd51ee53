#pragma once
// `codesign verify`'s rows and its report.md (docs/verify.md): a verdict per condition — is d*
// within the best group, i.e. does its 95 % interval reach the best design's — and one plain
// sentence at the top. Pure text from the rows.
#include <string>
#include <vector>

#include "run/verify_subjects.hpp"

namespace codesign::run {

// One held-out condition's test of one subject.
struct VerifyRow {
  std::string subject, controller;
  DesignAtPressures at;
  std::string condition;
  double mean_return = 0.0, std_return = 0.0, ci95 = 0.0, band_fraction = 0.0;
  int episodes = 0;
};

// One line per condition: d*'s interval against the best policy subject's (among the designs),
// and the baselines beside it. "within" when d*'s upper end reaches the best's lower end.
struct Verdict {
  std::string condition;
  bool within = true;        // d* within the best group (true when d* is the only design)
  std::string best_subject;  // the policy subject with the highest mean
  std::string line;
};
std::vector<Verdict> verdicts(const std::vector<VerifyRow>& rows, const std::vector<std::string>& conditions);

struct VerifyReportInput {
  std::string run;                                 // the run folder as given
  std::string phase_set;                           // "test" or "validation"
  int phases = 0;
  std::vector<VerifySubject> subjects;
  std::vector<std::pair<std::string, std::string>> conditions;  // (name, what it is), suite order
  std::vector<VerifyRow> rows;
  std::string notes;                               // extra lines (how the subjects were chosen)
};
std::string verify_report(const VerifyReportInput& in);

}  // namespace codesign::run
