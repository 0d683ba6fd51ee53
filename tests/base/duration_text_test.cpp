#include "base/duration_text.hpp"

#include <limits>

#include <gtest/gtest.h>

namespace codesign {
namespace {

TEST(DurationText, MinutesAndSecondsBelowAnHour) {
  EXPECT_EQ(duration_text(0.0), "0m00s");
  EXPECT_EQ(duration_text(59.49), "0m59s");
  EXPECT_EQ(duration_text(59.5), "1m00s");  // rounds to the nearest second
  EXPECT_EQ(duration_text(187.0), "3m07s");
  EXPECT_EQ(duration_text(3599.4), "59m59s");
}

TEST(DurationText, HoursAndMinutesFromAnHourOn) {
  EXPECT_EQ(duration_text(3599.5), "1h00m");
  EXPECT_EQ(duration_text(3920.0), "1h05m");   // the paper run's wall time
  EXPECT_EQ(duration_text(3959.0), "1h05m");   // minutes are truncated, not rounded
  EXPECT_EQ(duration_text(26.0 * 3600 + 61), "26h01m");
}

TEST(DurationText, UnknownWhenNegativeOrNotFinite) {
  EXPECT_EQ(duration_text(-1.0), "?");
  EXPECT_EQ(duration_text(std::numeric_limits<double>::quiet_NaN()), "?");
  EXPECT_EQ(duration_text(std::numeric_limits<double>::infinity()), "?");
}

}  // namespace
}  // namespace codesign
