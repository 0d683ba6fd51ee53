#pragma once
// A discrete PID controller for the whisker's base, and its two sensor signals.
//
// One step per decision (sample time = one decision, so the gains are per decision):
//   e_k = error of decision k (in the units below), I_k = I_{k−1} + e_k, e_{−1} = e_0,
//   u_k = Kp·e_k + Ki·I_k + Kd·(e_k − e_{k−1}),  a_k = clip(u_k, −1, 1),  Δθ = a_k·θ_max
// — the same action channel, scaling and clipping as the policy's. Anti-windup by conditional
// integration: when the output with the old integral, Kp·e_k + Ki·I_{k−1} + Kd·(e_k − e_{k−1}),
// is already saturated (|·| ≥ 1) in the direction e_k pushes, the integrator keeps I_{k−1}. Since Δθ integrates the action, a P term already drives F
// towards its target without a steady offset for a constant disturbance; I and D help against
// the plate's moving disturbance.
//
// Signals (PidSignal), all scaled to "band units" so one gain range serves them all:
//   Force   e = (F_t − F)/(tol·F_t)        F measured directly: an oracle sensor the policy lacks;
//                                          e = ±1 at the band's edges.
//   Strain  e = −(ε_ref − ε)/strain_scale  ε is the policy's own signal. ε falls as F rises
//                                          (−4.7·10⁻⁶ per mN on j21, docs/codesign.md), hence the
//                                          minus; strain_scale is ε per band half-width.
//   Estimate e = (F_t − F̂)/(tol·F_t)       F̂(ε, θ) = (ε − c0 − c2·θ)/c1: the force estimated from
//                                          the strain gauge and the base-angle encoder, the robot's
//                                          own sensors (force_estimator.hpp, fitted by
//                                          estimator_calibration.hpp).
// Turning the base up (θ larger) presses the tip harder onto the plate (F rises; measured:
// tests/core/pid_tuning_test.cpp, ForceRisesWithTheBaseAngle), so a positive error (F below
// target) asks for a positive action, and the gains are non-negative.
#include <string>

#include "base/enum_names.hpp"

namespace codesign::core {

struct PidGains {
  bool operator==(const PidGains&) const = default;
  double kp = 0.0, ki = 0.0, kd = 0.0;  // action per band unit (Ki: per band unit·decision)
  // Throws std::invalid_argument naming the gain unless every gain is finite and >= 0.
  void validate() const;
};

class PidController {
 public:
  explicit PidController(const PidGains& gains);  // validates
  const PidGains& gains() const { return gains_; }
  // Forget the episode's history (integral, last error).
  void reset();
  // The action of the next decision for error e (clipped to [−1, 1]); a non-finite e gives 0
  // and leaves the state unchanged.
  double act(double error);
  double integral() const { return integral_; }

 private:
  PidGains gains_;
  double integral_ = 0.0;
  double last_error_ = 0.0;
  bool first_ = true;
};

enum class PidSignal { Force, Strain, Estimate };
inline constexpr EnumNames<PidSignal, 3> kPidSignalNames{
    {{PidSignal::Force, "force"}, {PidSignal::Strain, "strain"}, {PidSignal::Estimate, "estimate"}}};
inline const char* to_string(PidSignal s) { return name_of(kPidSignalNames, s).data(); }
PidSignal pid_signal_from_name(const std::string& name);  // one of to_string's names, else invalid_argument

}  // namespace codesign::core
