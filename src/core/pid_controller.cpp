#include "core/pid_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace codesign::core {

void PidGains::validate() const {
  const char* names[] = {"kp", "ki", "kd"};
  const double values[] = {kp, ki, kd};
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(values[i]) || values[i] < 0.0)
      throw std::invalid_argument(std::string("PID gain ") + names[i] + " = " + std::to_string(values[i]) +
                                  " is invalid: gains must be finite and >= 0");
}

PidController::PidController(const PidGains& gains) : gains_(gains) { gains_.validate(); }

void PidController::reset() {
  integral_ = 0.0;
  last_error_ = 0.0;
  first_ = true;
}

double PidController::act(double e) {
  if (!std::isfinite(e)) return 0.0;
  const double de = first_ ? 0.0 : e - last_error_;
  first_ = false;
  last_error_ = e;
  // Conditional integration: the integral does not move while the output with the integral so
  // far is already saturated in the direction the error pushes.
  const double u_old = gains_.kp * e + gains_.ki * integral_ + gains_.kd * de;
  const bool saturated = std::abs(u_old) >= 1.0 && e != 0.0 && (e > 0.0) == (u_old > 0.0);
  if (!saturated) integral_ += e;
  const double u_out = gains_.kp * e + gains_.ki * integral_ + gains_.kd * de;
  return std::clamp(u_out, -1.0, 1.0);
}

PidSignal pid_signal_from_name(const std::string& name) {
  if (const std::optional<PidSignal> s = value_of(kPidSignalNames, name)) return *s;
  throw std::invalid_argument("unknown PID signal '" + name + "'; allowed: " + names_list(kPidSignalNames));
}

}  // namespace codesign::core
