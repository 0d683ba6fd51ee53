#pragma once
// A discrete design space j = (n, l, w) given by its three axes, so that a space can come from
// the config rather than from the code. The paper's space is DesignSpace::paper(): n ∈ {1, 2},
// l ∈ {20, 22, …, 40} mm, w ∈ {2.0, 2.5, …, 4.0} mm, 110 designs, and for it every function here
// gives what design.hpp's free functions give, to the bit (tests/fem/design_space_test.cpp).
//
// Index: n outermost, then l, then w, as in design.hpp. The features a policy sees of a design
// (normalised) map each axis from its smallest to its largest value onto [−1, 1]; an axis of one
// value maps to 0.
#include <array>
#include <string>
#include <vector>

#include "fem/design.hpp"

namespace codesign::fem {

struct DesignAxes {
  bool operator==(const DesignAxes&) const = default;
  std::vector<int> chambers;
  std::vector<double> lengths_mm;
  std::vector<double> walls_mm;
};

class DesignSpace {
 public:
  // The paper's 110 designs.
  static DesignSpace paper();
  // std::invalid_argument naming the axis: an empty axis; chambers outside {1, 2} (the
  // observation holds two pressures); a length or wall not finite and > 0; values not strictly
  // increasing.
  explicit DesignSpace(DesignAxes axes);

  const DesignAxes& axes() const { return axes_; }
  int size() const;
  bool is_paper() const;
  // std::out_of_range naming the index and the size for j outside [0, size()).
  Design design(int j) const;
  // The index of a design of the space (lengths and walls matched to within 1e-9 mm);
  // std::invalid_argument otherwise.
  int index_of(const Design& d) const;
  std::array<double, 3> normalised(int j) const;
  // "j35 {1, 34 mm, 2 mm}", as design_label.
  std::string label(int j) const;

 private:
  DesignAxes axes_;
};

}  // namespace codesign::fem
