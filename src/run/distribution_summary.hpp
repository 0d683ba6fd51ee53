#pragma once
// What the CSV logs and the telemetry both say of the design distribution after an iteration,
// computed once per iteration for both.
#include <array>
#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "core/design_distribution.hpp"

namespace codesign::run {

struct DistributionSummary {
  core::Phase phase = core::Phase::Exploration;
  double entropy = 0.0;
  std::optional<double> target_entropy;  // the entropy schedule's H*(t); none under the ramp
  Eigen::VectorXd q;          // q_disc over the designs
  std::array<int, 3> top{};   // the three most probable designs, most probable first
  int best = 0;               // leading design and its score, mean and sigma of p in kPa
  double best_score = 0.0;
  Eigen::Vector2d mu = Eigen::Vector2d::Zero(), sigma = Eigen::Vector2d::Zero();
};

DistributionSummary summarize(const core::DesignDistribution& dist, std::int64_t t);

}  // namespace codesign::run
