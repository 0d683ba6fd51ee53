// The design space from its axes (fem/design_space.hpp): the paper's space gives what design.hpp's
// functions give for all 110 designs, to the bit; another space indexes n outermost, then l, then
// w, round-trips, and maps its own axes onto [−1, 1]; bad axes are refused naming the axis.
#include <gtest/gtest.h>

#include <stdexcept>

#include "base/grid_values.hpp"
#include "fem/design_space.hpp"

namespace codesign::fem {
namespace {

TEST(DesignSpace, ThePapersSpaceIsDesignHppToTheBit) {
  const DesignSpace s = DesignSpace::paper();
  EXPECT_TRUE(s.is_paper());
  ASSERT_EQ(s.size(), kDesignCount);
  for (int j = 0; j < kDesignCount; ++j) {
    const Design a = s.design(j), b = design_from_index(j);
    EXPECT_EQ(a.n, b.n);
    EXPECT_EQ(a.chamber_length_mm, b.chamber_length_mm);
    EXPECT_EQ(a.wall_mm, b.wall_mm);
    EXPECT_EQ(s.index_of(b), j);
    EXPECT_EQ(s.normalised(j), normalised(b)) << j;  // the policy's features, exactly
    EXPECT_EQ(s.label(j), design_label(j));
  }
}

TEST(DesignSpace, AnOffGridSpaceIndexesAndScalesItsOwnAxes) {
  // Walls 1.5–3 mm, chambers up to 50 mm, one chamber: 1 × 16 × 4 designs.
  const DesignSpace s(DesignAxes{{1}, grid_values(20.0, 50.0, 2.0), grid_values(1.5, 3.0, 0.5)});
  EXPECT_FALSE(s.is_paper());
  ASSERT_EQ(s.size(), 64);
  const Design last = s.design(63);
  EXPECT_EQ(last.chamber_length_mm, 50.0);
  EXPECT_EQ(last.wall_mm, 3.0);
  const Design d = s.design(4 * 3 + 2);  // l index 3 (26 mm), w index 2 (2.5 mm)
  EXPECT_EQ(d.chamber_length_mm, 26.0);
  EXPECT_EQ(d.wall_mm, 2.5);
  for (int j = 0; j < s.size(); ++j) EXPECT_EQ(s.index_of(s.design(j)), j);
  // A one-value axis maps to 0; l = 26 on [20, 50] is 2·6/30 − 1 = −0.6; w = 2.5 on [1.5, 3] is 1/3.
  const std::array<double, 3> f = s.normalised(4 * 3 + 2);
  EXPECT_EQ(f[0], 0.0);
  EXPECT_NEAR(f[1], -0.6, 1e-15);
  EXPECT_NEAR(f[2], 1.0 / 3.0, 1e-15);
  EXPECT_THROW(s.index_of({2, 26.0, 2.5}), std::invalid_argument);
  EXPECT_THROW(s.design(64), std::out_of_range);
}

TEST(DesignSpace, RangesIncludeTheirEndAndBadAxesAreRefused) {
  EXPECT_EQ(grid_values(2.0, 4.0, 0.5), (std::vector<double>{2.0, 2.5, 3.0, 3.5, 4.0}));
  EXPECT_EQ(grid_values(0.1, 0.3, 0.1).size(), 3u);  // 0.3 reached despite 0.1's rounding
  EXPECT_EQ(grid_values(20.0, 25.0, 2.0), (std::vector<double>{20.0, 22.0, 24.0}));
  EXPECT_THROW(grid_values(1.0, 2.0, 0.0), std::invalid_argument);
  EXPECT_THROW(grid_values(3.0, 2.0, 0.5), std::invalid_argument);
  const auto refused = [](DesignAxes a, const std::string& axis) {
    try {
      DesignSpace s(std::move(a));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what()).find(axis) != std::string::npos;
    }
    return false;
  };
  EXPECT_TRUE(refused({{}, {20.0}, {2.0}}, "chambers: no values"));
  EXPECT_TRUE(refused({{1, 3}, {20.0}, {2.0}}, "chambers: 3 is not 1 or 2"));
  EXPECT_TRUE(refused({{1}, {22.0, 20.0}, {2.0}}, "chamber_length_mm: values must be strictly increasing"));
  EXPECT_TRUE(refused({{1}, {20.0}, {2.0, 2.0}}, "wall_mm: values must be strictly increasing"));
  EXPECT_TRUE(refused({{1}, {20.0}, {-1.0}}, "wall_mm: values must be finite and > 0"));
}

}  // namespace
}  // namespace codesign::fem
