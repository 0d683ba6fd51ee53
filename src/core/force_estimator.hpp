#pragma once
// An estimate of the contact force from the robot's own sensors: the strain gauge ε and the
// base-angle encoder θ.
//
// Model: ε = c0 + c1·F + c2·θ (ε falls as F rises, so c1 < 0 on every design we have seen; ε
// also moves with θ at a fixed F, the base turning the body), inverted as
// F̂(ε, θ) = (ε − c0 − c2·θ)/c1.
// fit_force_estimator() finds (c0, c1, c2) by least squares of ε over samples (ε, F, θ) and
// reports how good the fit is: R² of ε, and the rms of F̂ − F over the samples in mN
// (= rms of the ε residual / |c1|). Where the samples come from: estimator_calibration.hpp.
#include <vector>

namespace codesign::core {

struct ForceSample {
  double strain = 0.0;    // ε
  double force_mN = 0.0;  // F
  double theta_rad = 0.0; // θ
};

struct ForceEstimator {
  bool operator==(const ForceEstimator&) const = default;
  double c0 = 0.0;  // ε at F = 0, θ = 0
  double c1 = 0.0;  // ε per mN
  double c2 = 0.0;  // ε per rad
  // F̂ in mN (not clamped: a negative estimate means "out of contact by that much").
  double force_mN(double strain, double theta_rad) const { return (strain - c0 - c2 * theta_rad) / c1; }
};

struct ForceFit {
  ForceEstimator estimator;
  double r2 = 0.0;       // 1 − Σ residual² / Σ (ε − mean ε)²
  double rms_mN = 0.0;   // rms of F̂ − F over the samples
  int samples = 0;
};

// Least squares of ε against (1, F, θ). Throws std::invalid_argument, saying why, for fewer than
// 3 samples, a non-finite sample, F or θ without spread (e.g. θ constant), F and θ collinear
// (F an affine function of θ: the model cannot tell their effects apart), or a fit whose c1 is
// zero (ε does not see F, so F̂ would be undefined).
ForceFit fit_force_estimator(const std::vector<ForceSample>& samples);

}  // namespace codesign::core
