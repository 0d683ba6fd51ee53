// The sweep's points of the pressure grid and its controller names (the sweep's folder is
// tests/run/sweep_folder_test.cpp's).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/errors.hpp"
#include "core/design_sweep.hpp"
#include "test_files.hpp"

namespace codesign::core {
namespace {

namespace fs = std::filesystem;
using codesign::test_files::slurp;

TEST(DesignSweep, PointsCoverTheGridPerChamberCount) {
  SweepConfig c;
  c.pressures_kPa = {0.0, 10.0, 20.0};
  c.first_design = 54;  // the last one-chamber design
  c.last_design = 55;   // the first two-chamber design
  const std::vector<SweepPoint> p = sweep_points(c);
  ASSERT_EQ(p.size(), 3u + 9u);  // n = 1: the grid; n = 2: every pair
  EXPECT_EQ(p[0].design, 54);
  EXPECT_EQ(p[2].p1_kPa, 20.0);
  EXPECT_EQ(p[2].p2_kPa, 0.0);
  EXPECT_EQ(p[3].design, 55);
  EXPECT_EQ(p[4].p1_kPa, 0.0);
  EXPECT_EQ(p[4].p2_kPa, 10.0);
  c.pressures_kPa = {};
  EXPECT_THROW(c.validate(), std::invalid_argument);
}

TEST(DesignSweep, ControllerNamesRoundTrip) {
  for (SweepController c : {SweepController::FixedTheta, SweepController::PidForce, SweepController::PidStrain,
                            SweepController::PidEstimate})
    EXPECT_EQ(sweep_controller_from_name(to_string(c)), c);
  EXPECT_STREQ(to_string(SweepController::PidEstimate), "pid_estimate");
  try {
    sweep_controller_from_name("pid_oracle");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "unknown sweep controller 'pid_oracle'; allowed: fixed_theta, pid_force, pid_strain, pid_estimate");
  }
  for (PidSignal s : {PidSignal::Force, PidSignal::Strain, PidSignal::Estimate})
    EXPECT_EQ(pid_signal_from_name(to_string(s)), s);
  EXPECT_THROW(pid_signal_from_name("oracle"), std::invalid_argument);
}

}  // namespace
}  // namespace codesign::core
