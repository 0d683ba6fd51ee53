#include "run/verify_subjects.hpp"

#include <algorithm>
#include <cmath>

#include "fem/design.hpp"
#include "fem/design_space.hpp"

namespace codesign::run {

namespace {

bool contains(const std::vector<int>& v, int j) { return std::find(v.begin(), v.end(), j) != v.end(); }

// d* with one coordinate (`field`) set to the grid value farthest from d*'s that gives a design
// outside `group`; ties go to the larger value; -1 if none is left.
int farthest(int best, const std::vector<int>& group, const std::vector<double>& values, double fem::Design::*field) {
  const fem::Design b = fem::design_from_index(best);
  int pick = -1;
  double pick_distance = -1.0, pick_value = 0.0;
  for (const double value : values) {
    fem::Design d = b;
    d.*field = value;
    const int j = fem::index_of(d);
    if (j == best || contains(group, j)) continue;
    const double distance = std::abs(value - b.*field);
    if (distance > pick_distance || (distance == pick_distance && value > pick_value))
      pick = j, pick_distance = distance, pick_value = value;
  }
  return pick;
}

}  // namespace

std::pair<int, int> outside_designs(int best, const std::vector<int>& group) {
  const fem::DesignSpace paper = fem::DesignSpace::paper();
  const fem::DesignAxes& axes = paper.axes();
  const int wall = farthest(best, group, axes.walls_mm, &fem::Design::wall_mm);
  std::vector<int> taken = group;
  if (wall >= 0) taken.push_back(wall);
  return {wall, farthest(best, taken, axes.lengths_mm, &fem::Design::chamber_length_mm)};
}

std::vector<VerifySubject> verify_subjects(const SubjectSources& s) {
  std::vector<VerifySubject> out;
  std::vector<int> designs;
  const auto add = [&](std::string name, std::string controller, const DesignAtPressures& at, std::string why) {
    if (controller == kControllerPolicy) {
      if (contains(designs, at.design)) return;
      designs.push_back(at.design);
    }
    out.push_back({std::move(name), std::move(controller), at, std::move(why), {}});
  };
  add("d*", kControllerPolicy, s.best, "the run's answer, at p*");
  if (!s.single_design) {
    if (s.runner_up) add("runner_up", kControllerPolicy, *s.runner_up, "the run's runner-up, at its pressures");
    int taken = 0;
    for (const DesignAtPressures& d : s.ranked) {
      if (taken == s.next) break;
      if (contains(designs, d.design)) continue;
      ++taken;
      add("next_" + std::to_string(taken), kControllerPolicy, d, "next in the " + s.ranked_from + ", at its pressures");
    }
    const auto [wall, length] = outside_designs(s.best.design, designs);
    if (wall >= 0)
      add("outside_wall", kControllerPolicy, {wall, s.best.p1_kPa, s.best.p2_kPa},
          "d*'s length and chambers with the wall farthest from d*'s, at p*");
    if (length >= 0)
      add("outside_length", kControllerPolicy, {length, s.best.p1_kPa, s.best.p2_kPa},
          "d*'s wall and chambers with the chamber length farthest from d*'s, at p*");
  }
  for (const auto& [run, d] : s.others) add("d*_of_" + run, kControllerPolicy, d, "the d* of run " + run + ", at its p*");
  if (s.baselines) {
    add(kControllerPidForce, kControllerPidForce, s.best, "d* at p* under a PID on the true contact force (an oracle sensor)");
    add(kControllerPidEstimate, kControllerPidEstimate, s.best, "d* at p* under a PI(D) on the force estimated from ε and θ");
  }
  return out;
}

}  // namespace codesign::run
