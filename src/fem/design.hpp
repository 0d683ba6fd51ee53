#pragma once
// The 110 discrete whisker designs j = (n, l, w) of the co-design space.
//
//   n ∈ {1, 2}                 number of chambers
//   l ∈ {20, 22, ..., 40} mm   chamber length (11 values)
//   w ∈ {2.0, 2.5, ..., 4.0} mm wall thickness (5 values)
//
// Index (0-based, n outermost, then l, then w):  j = (n-1)*55 + (l-20)/2*5 + (w-2)/0.5.
// The paper's two best designs: j21 = {1, 28, 2.5}, j63 = {2, 22, 3.5}.
#include <array>
#include <string>

namespace codesign::fem {

struct Design {
  int n = 1;                         // chambers, 1 or 2
  double chamber_length_mm = 28.0;   // l
  double wall_mm = 2.5;              // w
};

inline constexpr int kDesignCount = 110;
inline constexpr int kChamberLengthCount = 11;
inline constexpr int kWallCount = 5;

// j must lie in 0..109, otherwise std::out_of_range.
Design design_from_index(int j);
// Inverse of design_from_index. A design that is not on the grid (n not 1/2, l or w off the grid
// by more than 1e-9 mm, or out of range) throws std::invalid_argument.
int index_of(const Design& d);
// "j35 {1, 34 mm, 2 mm}": the index and {n, l, w} as run output and figures name a design.
// j outside 0..109: std::out_of_range.
std::string design_label(int j);
// (n, l, w) each mapped linearly from its range onto [-1, 1] (n: 1 → -1, 2 → +1).
std::array<double, 3> normalised(const Design& d);

}  // namespace codesign::fem
