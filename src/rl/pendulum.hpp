#pragma once
// Gymnasium's Pendulum-v1, re-implemented with the same dynamics, reward, reset distribution and
// order of operations (gymnasium/envs/classic_control/pendulum.py), in float64 throughout
// (Gymnasium returns float32 observations; the dynamics there are float64 too).
//
//   step(u): u      = clip(u, -max_torque, max_torque)
//            cost   = angle_normalize(th)^2 + 0.1 thdot^2 + 0.001 u^2   (state BEFORE the update)
//            thdot' = clip(thdot + (3 g / (2 l) sin(th) + 3 / (m l^2) u) dt, -max_speed, max_speed)
//            th'    = th + thdot' dt                       (th is not wrapped; only the cost wraps)
//            reward = -cost, obs = [cos th', sin th', thdot'], never terminated.
//   reset:   th ~ U(-pi, pi), thdot ~ U(-1, 1) (Gymnasium draws both with one uniform call,
//            th first). The episode is truncated after 200 steps by make_pendulum's TimeLimit.
#include <cstdint>
#include <memory>
#include <optional>

#include "rl/env.hpp"
#include "rl/rng.hpp"

namespace codesign::rl {

struct PendulumConfig {
  double g = 10.0;
  double m = 1.0;
  double l = 1.0;
  double dt = 0.05;
  double max_speed = 8.0;
  double max_torque = 2.0;
  int max_episode_steps = 200;
};

// Python's ((x + pi) % (2 pi)) - pi: floor modulo, result in [-pi, pi).
double angle_normalize(double x);

class Pendulum final : public Env {
 public:
  explicit Pendulum(const PendulumConfig& config = {});

  const EnvSpec& spec() const override { return spec_; }
  // Before the first seeded reset the RNG is seeded with 0 (deterministic, unlike Gymnasium's
  // OS-entropy default).
  Eigen::VectorXd reset(std::optional<std::uint64_t> seed) override;
  StepResult step(const Eigen::VectorXd& action) override;

  double theta() const { return th_; }
  double theta_dot() const { return thdot_; }
  // For tests and demos: put the pendulum in a given state.
  void set_state(double theta, double theta_dot) {
    th_ = theta;
    thdot_ = theta_dot;
  }
  Eigen::VectorXd observation() const;
  const PendulumConfig& config() const { return config_; }

 private:
  PendulumConfig config_;
  EnvSpec spec_;
  Rng rng_{0};
  double th_ = 0.0;
  double thdot_ = 0.0;
};

// Pendulum wrapped in TimeLimit(config.max_episode_steps): the Pendulum-v1 of gym.make.
std::unique_ptr<Env> make_pendulum(const PendulumConfig& config = {});
EnvFactory pendulum_factory(const PendulumConfig& config = {});

}  // namespace codesign::rl
