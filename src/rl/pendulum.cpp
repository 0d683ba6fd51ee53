#include "rl/pendulum.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace codesign::rl {

double angle_normalize(double x) {
  constexpr double pi = std::numbers::pi;
  constexpr double two_pi = 2.0 * std::numbers::pi;
  // Python float modulo: fmod, then shift into the divisor's sign.
  double r = std::fmod(x + pi, two_pi);
  if (r < 0.0) r += two_pi;
  return r - pi;
}

Pendulum::Pendulum(const PendulumConfig& config) : config_(config) {
  spec_.observation.low = Eigen::Vector3d(-1.0, -1.0, -config_.max_speed);
  spec_.observation.high = Eigen::Vector3d(1.0, 1.0, config_.max_speed);
  spec_.action.low = Eigen::VectorXd::Constant(1, -config_.max_torque);
  spec_.action.high = Eigen::VectorXd::Constant(1, config_.max_torque);
}

Eigen::VectorXd Pendulum::observation() const {
  return Eigen::Vector3d(std::cos(th_), std::sin(th_), thdot_);
}

Eigen::VectorXd Pendulum::reset(std::optional<std::uint64_t> seed) {
  if (seed) rng_ = Rng(*seed);
  constexpr double pi = std::numbers::pi;
  th_ = -pi + 2.0 * pi * rng_.uniform();
  thdot_ = -1.0 + 2.0 * rng_.uniform();
  return observation();
}

StepResult Pendulum::step(const Eigen::VectorXd& action) {
  const PendulumConfig& c = config_;
  const double u = std::clamp(action(0), -c.max_torque, c.max_torque);
  const double an = angle_normalize(th_);
  const double cost = an * an + 0.1 * thdot_ * thdot_ + 0.001 * u * u;

  double newthdot =
      thdot_ + (3.0 * c.g / (2.0 * c.l) * std::sin(th_) + 3.0 / (c.m * c.l * c.l) * u) * c.dt;
  newthdot = std::clamp(newthdot, -c.max_speed, c.max_speed);
  th_ = th_ + newthdot * c.dt;
  thdot_ = newthdot;

  StepResult r;
  r.obs = observation();
  r.reward = -cost;
  return r;
}

std::unique_ptr<Env> make_pendulum(const PendulumConfig& config) {
  return std::make_unique<TimeLimit>(std::make_unique<Pendulum>(config), config.max_episode_steps);
}

EnvFactory pendulum_factory(const PendulumConfig& config) {
  return [config](std::size_t) { return make_pendulum(config); };
}

}  // namespace codesign::rl
