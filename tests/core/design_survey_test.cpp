// The survey of designs (core/design_survey.hpp): one row per design in the order asked, the
// ranges it reports consistent with each other, the fixed-θ search only when asked, and rows that
// do not depend on how the designs are spread over threads.
#include <gtest/gtest.h>

#include <memory>

#include "core/design_survey.hpp"

namespace {

using namespace codesign;

std::shared_ptr<core::SimulatorPool> pool() {
  static auto p = std::make_shared<core::SimulatorPool>(fem::WhiskerModelSpec{}, fem::SceneConfig{}, fem::SolverConfig{});
  return p;
}

TEST(DesignSurvey, RowsAreConsistentAndIndependentOfThreads) {
  core::TaskConfig task;
  task.episode_steps = 50;  // 10 decisions: enough for the plate to reach the whisker
  core::SurveyOptions o;
  o.first_design = 20;
  o.last_design = 21;
  o.fixed_theta = false;
  rl::ThreadPool one(1), two(2);
  const std::vector<core::SurveyRow> a = core::survey_designs(pool(), task, o, one);
  const std::vector<core::SurveyRow> b = core::survey_designs(pool(), task, o, two);
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const core::SurveyRow& r = a[i];
    EXPECT_LE(r.strain_min, r.strain_max);
    EXPECT_LE(r.zeroed_min, r.zeroed_max);
    EXPECT_LE(r.force_min, r.force_mean);
    EXPECT_LE(r.force_mean, r.force_max);
    EXPECT_GE(r.force_min, 0.0);            // a contact force pushes, never pulls
    EXPECT_EQ(r.fixed.evaluations, 0);      // no fixed-θ search was asked for
    // Bit for bit the same rows whatever the thread count (each design runs on one thread).
    EXPECT_EQ(r.strain_min, b[i].strain_min);
    EXPECT_EQ(r.strain_max, b[i].strain_max);
    EXPECT_EQ(r.zeroed_min, b[i].zeroed_min);
    EXPECT_EQ(r.zeroed_max, b[i].zeroed_max);
    EXPECT_EQ(r.force_mean, b[i].force_mean);
  }
  // Designs 20 and 21 differ in wall thickness (2 mm, 2.5 mm), so must their strain ranges.
  EXPECT_NE(a[0].strain_max, a[1].strain_max);
}

}  // namespace
