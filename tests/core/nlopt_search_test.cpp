// core::maximise (the NLopt wrapper) on functions with known optima: interior and boundary
// maxima for every method, bounds respected at every call, the evaluation budget, several starts,
// fixed coordinates, and clear errors for bad boxes and options.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "core/nlopt_search.hpp"

namespace codesign::core {
namespace {

// Negative squared distance to c: the maximum is c, with value 0.
Objective bowl(std::vector<double> c, int* calls = nullptr) {
  return [c, calls](const std::vector<double>& x) {
    if (calls) ++*calls;
    double s = 0;
    for (std::size_t i = 0; i < x.size(); ++i) s += (x[i] - c[i]) * (x[i] - c[i]);
    return -s;
  };
}

TEST(NloptSearch, HaltonPointsAreTheRadicalInverses) {
  // Bases 2 and 3: index 1 -> (1/2, 1/3), 2 -> (1/4, 2/3), 3 -> (3/4, 1/9), exact in binary
  // for base 2 and to one rounding for base 3.
  const std::vector<double> p1 = halton_point(1, 2), p2 = halton_point(2, 2), p3 = halton_point(3, 2);
  EXPECT_EQ(p1[0], 0.5);
  EXPECT_NEAR(p1[1], 1.0 / 3.0, 1e-15);
  EXPECT_EQ(p2[0], 0.25);
  EXPECT_NEAR(p2[1], 2.0 / 3.0, 1e-15);
  EXPECT_EQ(p3[0], 0.75);
  EXPECT_NEAR(p3[1], 1.0 / 9.0, 1e-15);
}

TEST(NloptSearch, EveryMethodFindsAnInteriorMaximum) {
  // Box [-1, 2]^3 (width 3), maximum at c. The run stops when a step is below
  // xtol_rel * width = 3e-8 or f changes by < 1e-14; for a smooth bowl the point is then within
  // a few steps of c. We allow 1e-4 (>3000 such steps): a method that stalls elsewhere fails.
  const std::vector<double> c{0.3, -0.5, 1.2};
  for (LocalMethod m : {LocalMethod::Bobyqa, LocalMethod::Cobyla, LocalMethod::NelderMead, LocalMethod::Sbplx}) {
    SearchOptions o;
    o.method = m;
    o.starts = 1;
    o.max_evals = 2000;
    o.xtol_rel = 1e-8;
    o.ftol_abs = 1e-14;
    const SearchResult r = maximise(bowl(c), {{-1, -1, -1}, {2, 2, 2}}, o);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.x[static_cast<std::size_t>(i)], c[static_cast<std::size_t>(i)], 1e-4)
        << to_string(m) << " coordinate " << i;
    EXPECT_GE(r.value, -3e-8) << to_string(m);  // = -|x - c|^2 with |x_i - c_i| <= 1e-4
    EXPECT_LE(r.evaluations, 2000);
  }
}

TEST(NloptSearch, BoundaryMaximumAndNoCallOutsideTheBox) {
  // The unconstrained maximum (3, -2) lies outside [0, 1]^2; the constrained one is the corner
  // (1, 0). Every call must lie in the box.
  for (LocalMethod m : {LocalMethod::Bobyqa, LocalMethod::Cobyla, LocalMethod::NelderMead, LocalMethod::Sbplx}) {
    bool outside = false;
    const Objective f = [&](const std::vector<double>& x) {
      for (double v : x) outside = outside || v < 0.0 || v > 1.0;
      return -(x[0] - 3) * (x[0] - 3) - (x[1] + 2) * (x[1] + 2);
    };
    SearchOptions o;
    o.method = m;
    o.starts = 2;
    o.max_evals = 400;
    o.xtol_rel = 1e-9;
    o.ftol_abs = 1e-14;
    const SearchResult r = maximise(f, {{0, 0}, {1, 1}}, o);
    EXPECT_FALSE(outside) << to_string(m);
    EXPECT_NEAR(r.x[0], 1.0, 1e-6) << to_string(m);
    EXPECT_NEAR(r.x[1], 0.0, 1e-6) << to_string(m);
  }
}

TEST(NloptSearch, StopsOnTheBudget) {
  // 3 starts sharing 13 evaluations in 2-D: BOBYQA needs 2n + 1 = 5 points for its first model,
  // so no start can converge before its share (5, 4, 4) runs out: exactly 13 calls.
  int calls = 0;
  SearchOptions o;
  o.starts = 3;
  o.max_evals = 13;
  o.xtol_rel = 0.0;
  o.ftol_abs = 0.0;
  const SearchResult r = maximise(bowl({0.2, 0.7}, &calls), {{0, 0}, {1, 1}}, o);
  EXPECT_EQ(calls, 13);
  EXPECT_EQ(r.evaluations, 13);
  EXPECT_EQ(r.start_values.size(), 3u);
  // Never more than the budget, whatever the method.
  for (LocalMethod m : {LocalMethod::Cobyla, LocalMethod::NelderMead, LocalMethod::Sbplx}) {
    calls = 0;
    o.method = m;
    o.max_evals = 7;
    maximise(bowl({0.2, 0.7}, &calls), {{0, 0}, {1, 1}}, o);
    EXPECT_LE(calls, 7) << to_string(m);
    EXPECT_GE(calls, 3) << to_string(m);  // every start evaluates at least its start point
  }
}

TEST(NloptSearch, SeveralStartsReachTheHigherPeak) {
  // Two Gaussian peaks of width 0.1: height 1 at the box centre (start 0), height 2 at
  // (0.3, 0.7), next to start 2 (Halton point 2 = (0.25, 0.667)). One start finds the lower peak;
  // three find the higher one.
  const Objective f = [](const std::vector<double>& x) {
    auto g = [&](double a, double b) { return std::exp(-((x[0] - a) * (x[0] - a) + (x[1] - b) * (x[1] - b)) / 0.01); };
    return g(0.5, 0.5) + 2.0 * g(0.3, 0.7);
  };
  SearchOptions o;
  o.starts = 1;
  o.max_evals = 100;
  o.xtol_rel = 1e-6;
  const SearchResult one = maximise(f, {{0, 0}, {1, 1}}, o);
  EXPECT_NEAR(one.value, 1.0, 1e-3);
  o.starts = 3;
  o.max_evals = 300;
  const SearchResult three = maximise(f, {{0, 0}, {1, 1}}, o);
  EXPECT_NEAR(three.value, 2.0, 1e-3);
  EXPECT_NEAR(three.x[0], 0.3, 1e-2);
  EXPECT_NEAR(three.x[1], 0.7, 1e-2);
  EXPECT_EQ(three.best_start, 2);
}

TEST(NloptSearch, FixedCoordinatesStayFixedAndOneVariableWorks) {
  bool moved = false;
  const Objective f = [&](const std::vector<double>& x) {
    moved = moved || x[1] != 0.25;
    return -(x[0] - 0.6) * (x[0] - 0.6) - x[1];
  };
  SearchOptions o;  // BOBYQA: with one free variable it runs as COBYLA
  o.max_evals = 200;
  o.xtol_rel = 1e-9;
  o.ftol_abs = 1e-14;
  const SearchResult r = maximise(f, {{0, 0.25}, {1, 0.25}}, o);
  EXPECT_FALSE(moved);
  EXPECT_NEAR(r.x[0], 0.6, 1e-5);
  EXPECT_EQ(r.x[1], 0.25);
  // Every coordinate fixed: one evaluation.
  int calls = 0;
  const SearchResult p = maximise(bowl({0, 0}, &calls), {{0.5, 0.5}, {0.5, 0.5}}, o);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(p.x, (std::vector<double>{0.5, 0.5}));
}

TEST(NloptSearch, BadBoxesAndOptionsAreClearErrors) {
  SearchOptions o;
  auto message = [&](const SearchBox& b, const SearchOptions& opt) {
    try {
      maximise(bowl({0, 0}), b, opt);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message({{0, 1}, {1, 0.5}}, o),
            "search box: coordinate 1 has lower bound 1.000000 above its upper bound 0.500000");
  EXPECT_EQ(message({{0, NAN}, {1, 1}}, o), "search box: bound of coordinate 1 is not finite");
  EXPECT_EQ(message({{0}, {1, 1}}, o), "search box: lower and upper bounds need the same, non-zero length (got 1 and 2)");
  SearchOptions bad = o;
  bad.starts = 0;
  EXPECT_EQ(message({{0, 0}, {1, 1}}, bad), "search: starts must be >= 1 (got 0)");
  bad = o;
  bad.starts = 4;
  bad.max_evals = 3;
  EXPECT_EQ(message({{0, 0}, {1, 1}}, bad), "search: max_evals must be >= starts (4), got 3");
  EXPECT_THROW(local_method_from_name("newton"), std::invalid_argument);
}

TEST(NloptSearch, AnExceptionOfTheObjectivePropagates) {
  int calls = 0;
  const Objective f = [&](const std::vector<double>&) -> double {
    if (++calls == 3) throw std::runtime_error("simulator exploded");
    return 0.0;
  };
  SearchOptions o;
  o.max_evals = 50;
  try {
    maximise(f, {{0, 0}, {1, 1}}, o);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "simulator exploded");
  }
  EXPECT_EQ(calls, 3);
}

}  // namespace
}  // namespace codesign::core
