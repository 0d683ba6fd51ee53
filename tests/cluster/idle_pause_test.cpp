#include "cluster/idle_pause.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace codesign::cluster {
namespace {

// What a wait of W seconds costs with pause p, by the header's model: W / p wakes at c each, and
// the message noticed p / 2 late on average.
double wait_cost(double W, double p, double c) { return c * W / p + 0.5 * p; }

TEST(IdlePause, MinimisesWakesPlusLatenessBetweenItsBounds) {
  const IdlePause rule;
  // Waits whose optimum √(2 c W) lies inside [min_s, max_s]: 20 µs ↔ W = 12.5 µs, 20 ms ↔ W = 12.5 s.
  for (const double W : {1e-4, 1e-3, 0.01, 0.1, 1.0, 10.0}) {
    const double p = idle_pause_seconds(W, rule);
    EXPECT_NEAR(p, std::sqrt(2.0 * rule.wake_cost_s * W), 1e-12 + 1e-12 * p) << "W " << W;
    // A least cost: 1 % either way costs more, by about f''(p) (0.01 p)² / 2 = c W (0.01)² / p.
    const double f = wait_cost(W, p, rule.wake_cost_s);
    for (const double k : {0.99, 1.01}) EXPECT_GT(wait_cost(W, k * p, rule.wake_cost_s), f) << "W " << W << " k " << k;
  }
}

TEST(IdlePause, ClampedToItsBounds) {
  const IdlePause rule;
  EXPECT_EQ(idle_pause_seconds(0.0, rule), rule.min_s);
  EXPECT_EQ(idle_pause_seconds(-1.0, rule), rule.min_s);
  EXPECT_EQ(idle_pause_seconds(1e-6, rule), rule.min_s);  // √(2 · 16e-6 · 1e-6) = 5.7 µs < 20 µs
  EXPECT_EQ(idle_pause_seconds(13.0, rule), rule.max_s);  // √(2 · 16e-6 · 13) = 20.4 ms > 20 ms
  EXPECT_EQ(idle_pause_seconds(3600.0, rule), rule.max_s);
}

// Waking every p(w) for a wait of W seconds takes ∫ dw / √(2 c w) = √(2 W / c) wakes where p is
// not clamped: for c = 16 µs a 1 s wait (a PPO update) about 354 of them, where 500 µs pauses took
// about 1 770 (500 µs asked, about 560 µs slept, measured). Counted step by step from w0 (where p
// reaches its lower bound): each step [w, w + p(w)] adds 1 to the count and ∫ dw / p ∈
// [p(w) / p(w + p(w)), 1] to the integral, since p grows; so the count is at least the integral,
// and above it by at most Σ (1 − p_k / p_{k+1}) ≤ ln(p(W) / p(w0)) plus the last step, which may
// overrun W.
TEST(IdlePause, WakesOfAWaitGrowWithItsRoot) {
  const IdlePause rule;
  const double c = rule.wake_cost_s;
  const double w0 = 0.5 * rule.min_s * rule.min_s / c;  // p(w0) = min_s
  for (const double W : {0.01, 0.1, 1.0, 10.0}) {
    int wakes = 0;
    for (double w = w0; w < W; w += idle_pause_seconds(w, rule)) ++wakes;
    const double integral = std::sqrt(2.0 * W / c) - std::sqrt(2.0 * w0 / c);
    EXPECT_GE(wakes, integral) << "W " << W;
    EXPECT_LE(wakes, integral + std::log(idle_pause_seconds(W, rule) / rule.min_s) + 1.0) << "W " << W;
  }
}

}  // namespace
}  // namespace codesign::cluster
