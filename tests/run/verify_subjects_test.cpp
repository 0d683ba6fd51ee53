// What `codesign verify` tests, from the run's answers (run/verify_subjects.hpp), and the verdict
// per condition (run/verify_report.hpp), on hand-made inputs whose answers follow from the rules.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "fem/design.hpp"
#include "run/verify_report.hpp"
#include "run/verify_subjects.hpp"

namespace codesign::run {
namespace {

int j(int n, double l, double w) { return fem::index_of({n, l, w}); }

TEST(VerifySubjects, OutsideBodiesAreTheFarthestWallAndLengthAtDstarsOtherCoordinates) {
  const int best = j(1, 28, 2.5);
  // Walls 2.0..4.0: 4.0 is 1.5 from 2.5; lengths 20..40: 40 is 12 from 28.
  EXPECT_EQ(outside_designs(best, {}), std::make_pair(j(1, 28, 4.0), j(1, 40, 2.5)));
  // Taken ones give way to the next farthest: wall 3.5 (1.0 from 2.5, beyond 2.0's 0.5); length 38
  // (10 from 28, beyond 20's 8).
  EXPECT_EQ(outside_designs(best, {j(1, 28, 4.0), j(1, 40, 2.5)}), std::make_pair(j(1, 28, 3.5), j(1, 38, 2.5)));
  // A tie (walls 2.0 and 4.0 both 1.0 from 3.0) goes to the thicker; two chambers stay two.
  EXPECT_EQ(outside_designs(j(2, 30, 3.0), {}).first, j(2, 30, 4.0));
}

TEST(VerifySubjects, OrderDeduplicationAndSingleDesignRuns) {
  SubjectSources s;
  s.best = {21, 5.0, 0.0};
  s.runner_up = DesignAtPressures{63, 4.0, 6.0};
  s.ranked = {{21, 5.0, 0.0}, {63, 4.0, 6.0}, {22, 7.0, 0.0}, {40, 9.0, 0.0}, {41, 9.5, 0.0}};
  s.ranked_from = "order";
  s.others = {{"seed2", {22, 7.5, 0.0}}, {"seed3", {47, 3.0, 0.0}}};
  const std::vector<VerifySubject> v = verify_subjects(s);
  std::vector<std::string> names;
  for (const VerifySubject& x : v) names.push_back(x.name);
  // seed2's d* is next_1's design: named once, as next_1.
  const std::vector<std::string> want{"d*",           "runner_up",     "next_1",    "next_2",      "outside_wall",
                                      "outside_length", "d*_of_seed3", "pid_force", "pid_estimate"};
  EXPECT_EQ(names, want);
  EXPECT_EQ(v[2].at, (DesignAtPressures{22, 7.0, 0.0}));
  EXPECT_EQ(v[4].at, (DesignAtPressures{j(1, 28, 4.0), 5.0, 0.0}));  // outside bodies at d*'s pressures
  EXPECT_EQ(v[7].at, s.best);

  s.single_design = true;
  s.baselines = false;
  s.others.clear();
  const std::vector<VerifySubject> alone = verify_subjects(s);
  ASSERT_EQ(alone.size(), 1u);
  EXPECT_EQ(alone[0].name, "d*");
}

VerifyRow row(std::string subject, std::string controller, int design, double mean, double ci) {
  VerifyRow r;
  r.subject = std::move(subject);
  r.controller = std::move(controller);
  r.at.design = design;
  r.condition = "nominal";
  r.mean_return = mean;
  r.ci95 = ci;
  return r;
}

TEST(VerifyReport, DstarIsWithinTheBestGroupWhenItsIntervalReachesTheBests) {
  // Best 40 ± 1 reaches down to 39; d* 37.5 ± 1.5 reaches up to 39.0: within (the ends touch).
  std::vector<VerifyRow> rows{row("d*", kControllerPolicy, 21, 37.5, 1.5), row("next_1", kControllerPolicy, 22, 40.0, 1.0),
                              row(kControllerPidForce, kControllerPidForce, 21, 48.0, 0.5)};
  std::vector<Verdict> v = verdicts(rows, {"nominal"});
  ASSERT_EQ(v.size(), 1u);
  EXPECT_TRUE(v[0].within);
  EXPECT_EQ(v[0].best_subject, "next_1");  // the PID is no design of the group
  EXPECT_NE(v[0].line.find("is within the best group (best: next_1, j22"), std::string::npos) << v[0].line;
  EXPECT_NE(v[0].line.find("pid_force 48.0 [47.5, 48.5]"), std::string::npos) << v[0].line;
  rows[0].ci95 = 1.4;  // reaches 38.9 < 39
  v = verdicts(rows, {"nominal"});
  EXPECT_FALSE(v[0].within);
  EXPECT_NE(v[0].line.find("is below the best group"), std::string::npos) << v[0].line;
  // A single-design run: d* is the only design, beside its PID.
  rows.erase(rows.begin() + 1);
  v = verdicts(rows, {"nominal"});
  EXPECT_TRUE(v[0].within);
  EXPECT_NE(v[0].line.find("37.5 [36.1, 38.9], the only design tested; pid_force"), std::string::npos) << v[0].line;
}

}  // namespace
}  // namespace codesign::run
