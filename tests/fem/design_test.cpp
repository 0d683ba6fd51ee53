#include <gtest/gtest.h>

#include <stdexcept>

#include "fem/design.hpp"

using namespace codesign::fem;

TEST(Design, PaperTopDesigns) {
  const Design j21 = design_from_index(21);
  EXPECT_EQ(j21.n, 1);
  EXPECT_DOUBLE_EQ(j21.chamber_length_mm, 28.0);
  EXPECT_DOUBLE_EQ(j21.wall_mm, 2.5);
  const Design j63 = design_from_index(63);
  EXPECT_EQ(j63.n, 2);
  EXPECT_DOUBLE_EQ(j63.chamber_length_mm, 22.0);
  EXPECT_DOUBLE_EQ(j63.wall_mm, 3.5);
}

TEST(Design, FormulaAndRoundTripForAll110) {
  int seen = 0;
  for (int j = 0; j < kDesignCount; ++j) {
    const Design d = design_from_index(j);
    // The spec's formula, evaluated independently of the implementation.
    const double formula = (d.n - 1) * 55 + (d.chamber_length_mm - 20) / 2 * 5 + (d.wall_mm - 2) / 0.5;
    EXPECT_DOUBLE_EQ(formula, j);
    EXPECT_EQ(index_of(d), j);
    EXPECT_TRUE(d.n == 1 || d.n == 2);
    EXPECT_GE(d.chamber_length_mm, 20.0);
    EXPECT_LE(d.chamber_length_mm, 40.0);
    EXPECT_GE(d.wall_mm, 2.0);
    EXPECT_LE(d.wall_mm, 4.0);
    ++seen;
  }
  EXPECT_EQ(seen, 110);
  EXPECT_THROW(design_from_index(-1), std::out_of_range);
  EXPECT_THROW(design_from_index(110), std::out_of_range);
}

TEST(Design, IndexOfRejectsOffGridDesigns) {
  EXPECT_THROW(index_of({3, 28, 2.5}), std::invalid_argument);
  EXPECT_THROW(index_of({1, 29, 2.5}), std::invalid_argument);
  EXPECT_THROW(index_of({1, 42, 2.5}), std::invalid_argument);
  EXPECT_THROW(index_of({1, 28, 2.25}), std::invalid_argument);
  EXPECT_THROW(index_of({1, 28, 4.5}), std::invalid_argument);
}

TEST(Design, NormalisedSpansMinusOneToOne) {
  const auto lo = normalised(design_from_index(0));
  const auto hi = normalised(design_from_index(109));
  for (int k = 0; k < 3; ++k) {
    EXPECT_DOUBLE_EQ(lo[k], -1.0);
    EXPECT_DOUBLE_EQ(hi[k], 1.0);
  }
  const auto j21 = normalised(design_from_index(21));  // {1, 28, 2.5}
  EXPECT_DOUBLE_EQ(j21[0], -1.0);
  EXPECT_DOUBLE_EQ(j21[1], 2.0 * 8 / 20 - 1);
  EXPECT_DOUBLE_EQ(j21[2], 2.0 * 0.5 / 2 - 1);
}

// The labels the run's output and figures print: the paper's two designs (Table III), and the
// ends of the grid.
TEST(Design, LabelNamesIndexAndGeometry) {
  EXPECT_EQ(design_label(21), "j21 {1, 28 mm, 2.5 mm}");
  EXPECT_EQ(design_label(63), "j63 {2, 22 mm, 3.5 mm}");
  EXPECT_EQ(design_label(0), "j0 {1, 20 mm, 2 mm}");
  EXPECT_EQ(design_label(109), "j109 {2, 40 mm, 4 mm}");
  EXPECT_THROW(design_label(110), std::out_of_range);
}
