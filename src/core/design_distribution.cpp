#include "core/design_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace codesign::core {
namespace {

// Below this population std of a design's reward buffer the advantage is taken as 0 (no
// continuous update): a single entry or identical returns carry no scale to normalise by.
constexpr double kMinRewardStd = 1e-12;

double sigmoid(double z) {
  if (z >= 0.0) return 1.0 / (1.0 + std::exp(-z));
  const double e = std::exp(z);
  return e / (1.0 + e);
}

template <class T>
std::string str(const T& value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

[[noreturn]] void bad_field(const std::string& field, const std::string& value,
                            const std::string& allowed) {
  throw std::invalid_argument("DistributionConfig." + field + ": value " + value +
                              " is out of range; allowed " + allowed);
}

[[noreturn]] void bad_state(const std::string& what) {
  throw std::invalid_argument("DistributionState: " + what);
}

bool finite(const Eigen::Ref<const Eigen::MatrixXd>& m) { return m.allFinite(); }

}  // namespace

void DistributionConfig::validate() const {
  if (exploration_end < 0) bad_field("exploration_end", str(exploration_end), "[0, inf)");
  if (exploitation_start <= exploration_end)
    bad_field("exploitation_start", str(exploitation_start),
              "(exploration_end = " + str(exploration_end) + ", inf)");
  if (!(std::isfinite(alpha) && alpha > 0.0)) bad_field("alpha", str(alpha), "(0, inf)");
  if (!(phi >= 0.0 && phi <= 1.0)) bad_field("phi", str(phi), "[0, 1]");
  if (!(std::isfinite(beta_start) && beta_start >= 0.0))
    bad_field("beta_start", str(beta_start), "[0, inf)");
  if (!(std::isfinite(beta_end) && beta_end >= 0.0))
    bad_field("beta_end", str(beta_end), "[0, inf)");
  if (beta_schedule != BetaSchedule::Ramp && beta_schedule != BetaSchedule::Entropy)
    bad_field("beta_schedule", str(static_cast<int>(beta_schedule)), "ramp or entropy");
  if (!(std::isfinite(entropy_end) && entropy_end >= 0.0))
    bad_field("entropy_end", str(entropy_end), "[0, ln(number of designs)]");
  if (reward_buffer < 2) bad_field("reward_buffer", str(reward_buffer), "[2, inf)");
  if (!(std::isfinite(pressure_max_kPa) && pressure_max_kPa > 0.0))
    bad_field("pressure_max_kPa", str(pressure_max_kPa), "(0, inf)");
  if (!std::isfinite(latent_mu0)) bad_field("latent_mu0", str(latent_mu0), "finite");
  if (!(std::isfinite(latent_sigma0) && latent_sigma0 > 0.0))
    bad_field("latent_sigma0", str(latent_sigma0), "(0, inf)");
  if (!(latent_sigma_min > 0.0 && latent_sigma_min <= latent_sigma0))
    bad_field("latent_sigma_min", str(latent_sigma_min),
              "(0, latent_sigma0 = " + str(latent_sigma0) + "]");
}

DesignDistribution::DesignDistribution(const DistributionConfig& config, std::vector<int> chambers)
    : config_(config), chambers_(std::move(chambers)) {
  config_.validate();
  if (chambers_.empty()) throw std::invalid_argument("DesignDistribution: no designs");
  for (std::size_t j = 0; j < chambers_.size(); ++j) {
    if (chambers_[j] != 1 && chambers_[j] != 2)
      throw std::invalid_argument("DesignDistribution: chambers[" + std::to_string(j) +
                                  "] = " + std::to_string(chambers_[j]) + "; allowed 1 or 2");
  }
  const auto n = chambers_.size();
  const double max_entropy = std::log(static_cast<double>(n));
  if (config_.beta_schedule == BetaSchedule::Entropy && config_.entropy_end > max_entropy)
    bad_field("entropy_end", str(config_.entropy_end),
              "[0, ln " + std::to_string(n) + " = " + str(max_entropy) + "]");
  const double s0 = config_.latent_sigma0 * config_.latent_sigma0;
  state_.score = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  state_.baseline = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  state_.mu.assign(n, Eigen::Vector2d::Constant(config_.latent_mu0));
  state_.sigma.assign(n, s0 * Eigen::Matrix2d::Identity());
  state_.buffer.assign(n, {});
  state_.samples.assign(n, 0);
}

DesignDistribution::DesignDistribution(const DistributionConfig& config, std::vector<int> chambers,
                                       DistributionState state)
    : DesignDistribution(config, std::move(chambers)) {
  const auto n = chambers_.size();
  const auto ni = static_cast<Eigen::Index>(n);
  if (state.score.size() != ni || state.baseline.size() != ni || state.mu.size() != n ||
      state.sigma.size() != n || state.buffer.size() != n || state.samples.size() != n)
    bad_state("sizes do not match the " + std::to_string(n) + " designs");
  if (!finite(state.score) || !finite(state.baseline)) bad_state("non-finite score or baseline");
  for (std::size_t j = 0; j < n; ++j) {
    const std::string at = " of design " + std::to_string(j);
    if (!finite(state.mu[j])) bad_state("non-finite mu" + at);
    const Eigen::Matrix2d& s = state.sigma[j];
    if (!finite(s) || s(0, 1) != s(1, 0)) bad_state("sigma" + at + " is not finite and symmetric");
    if (chambers_[j] == 1 && s(0, 1) != 0.0) bad_state("sigma" + at + " (1 chamber) has Σ12 ≠ 0");
    if (Eigen::LLT<Eigen::Matrix2d>(s).info() != Eigen::Success)
      bad_state("sigma" + at + " is not positive definite");
    if (state.buffer[j].size() > static_cast<std::size_t>(config_.reward_buffer))
      bad_state("buffer" + at + " is longer than reward_buffer");
    for (double r : state.buffer[j])
      if (!std::isfinite(r)) bad_state("non-finite return in buffer" + at);
    if (state.samples[j] < static_cast<std::int64_t>(state.buffer[j].size()))
      bad_state("samples" + at + " is smaller than its buffer");
  }
  if (state.collapsed) {
    if (state.best_design < 0 || state.best_design >= static_cast<int>(n))
      bad_state("best_design " + std::to_string(state.best_design) + " out of range");
    if (!finite(state.best_latent)) bad_state("non-finite best_latent");
  } else if (state.best_design != -1) {
    bad_state("best_design must be -1 when not collapsed");
  }
  state_ = std::move(state);
}

Phase DesignDistribution::phase(std::int64_t t) const {
  if (t < config_.exploration_end) return Phase::Exploration;
  if (t < config_.exploitation_start) return Phase::Transition;
  return Phase::Exploitation;
}

double DesignDistribution::beta(std::int64_t t) const {
  if (config_.beta_schedule == BetaSchedule::Entropy)
    return phase(t) == Phase::Exploration ? 0.0 : entropy_matching_beta(state_.score, *target_entropy(t));
  switch (phase(t)) {
    case Phase::Exploration: return 0.0;
    case Phase::Transition: {
      const double f = static_cast<double>(t - config_.exploration_end) /
                       static_cast<double>(config_.exploitation_start - config_.exploration_end);
      return config_.beta_start + (config_.beta_end - config_.beta_start) * f;
    }
    case Phase::Exploitation: return config_.beta_end;
  }
  return 0.0;
}

std::optional<double> DesignDistribution::target_entropy(std::int64_t t) const {
  if (config_.beta_schedule != BetaSchedule::Entropy) return std::nullopt;
  const double start = std::log(static_cast<double>(design_count()));
  switch (phase(t)) {
    case Phase::Exploration: return start;
    case Phase::Transition: {
      const double f = static_cast<double>(t - config_.exploration_end) /
                       static_cast<double>(config_.exploitation_start - config_.exploration_end);
      return start + f * (config_.entropy_end - start);
    }
    case Phase::Exploitation: return config_.entropy_end;
  }
  return start;
}

// exp by std::exp, element by element: Eigen's vectorised exp clamps its argument (e^-5000
// gives 5.6e-309, not 0) and is not bit-identical between packet and scalar paths, so a run's
// design draws would depend on the build's SIMD width.
Eigen::VectorXd DesignDistribution::probabilities(std::int64_t t) const {
  const double b = beta(t);
  const double top = (b * state_.score).maxCoeff();
  Eigen::VectorXd e(state_.score.size());
  for (Eigen::Index j = 0; j < e.size(); ++j) e(j) = std::exp(b * state_.score(j) - top);
  return e / e.sum();
}

double DesignDistribution::entropy(std::int64_t t) const { return softmax_entropy(state_.score, beta(t)); }

double softmax_entropy(const Eigen::VectorXd& score, double b) {
  const double top = (b * score).maxCoeff();
  double z = 0.0;
  for (Eigen::Index j = 0; j < score.size(); ++j) z += std::exp(b * score(j) - top);
  const double log_z = std::log(z);
  double h = 0.0;
  for (Eigen::Index j = 0; j < score.size(); ++j) {
    const double log_q = b * score(j) - top - log_z;
    const double q = std::exp(log_q);
    if (q > 0.0) h -= q * log_q;
  }
  return h;
}

double entropy_matching_beta(const Eigen::VectorXd& score, double target) {
  const Eigen::Index n = score.size();
  if (n <= 1 || !(target < std::log(static_cast<double>(n)))) return 0.0;
  const double top = score.maxCoeff();
  double next = -std::numeric_limits<double>::infinity();  // the largest score below the top
  for (Eigen::Index j = 0; j < n; ++j)
    if (score(j) < top) next = std::max(next, score(j));
  if (next == -std::numeric_limits<double>::infinity()) return 0.0;  // all equal: q uniform for any β
  const double cap = std::min(kBetaCapLogit / (top - next), kBetaMax);
  if (softmax_entropy(score, cap) > target) return cap;  // floor ln(#tied maxima) above the target
  // Invariant: H(lo) > target ≥ H(hi). Each halving keeps it; the loop ends on the relative
  // width, or when no double lies strictly between the ends (a bound of 4096 is a safety net only).
  double lo = 0.0, hi = cap;
  for (int i = 0; i < 4096 && hi - lo > kBetaRelTolerance * hi; ++i) {
    const double mid = lo + 0.5 * (hi - lo);
    if (mid <= lo || mid >= hi) break;
    if (softmax_entropy(score, mid) <= target) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  return hi;
}

DesignSample DesignDistribution::sample(std::int64_t t, rl::Rng& rng) const {
  // Always the same three draws, in this order, whatever the phase.
  const double u = rng.uniform();
  const double xi0 = rng.normal();
  const double xi1 = rng.normal();

  DesignSample out;
  if (state_.collapsed || phase(t) == Phase::Exploitation) {
    out.design = state_.collapsed ? state_.best_design : argmax_score();
    out.latent = state_.collapsed ? state_.best_latent : state_.mu[out.design];
    out.pressures_kPa = pressures_kPa(out.latent, out.design);
    return out;
  }

  const Eigen::VectorXd q = probabilities(t);
  int j = -1;
  double cumulative = 0.0;
  for (Eigen::Index k = 0; k < q.size(); ++k) {
    cumulative += q(k);
    if (u < cumulative) {
      j = static_cast<int>(k);
      break;
    }
  }
  if (j < 0) {  // u ≥ the rounded total: the last bin with non-zero probability
    for (Eigen::Index k = q.size() - 1; k >= 0; --k) {
      if (q(k) > 0.0) {
        j = static_cast<int>(k);
        break;
      }
    }
  }

  const Eigen::LLT<Eigen::Matrix2d> llt(state_.sigma[j]);
  if (llt.info() != Eigen::Success)
    throw std::logic_error("DesignDistribution: sigma of design " + std::to_string(j) +
                           " is not positive definite");
  out.design = j;
  out.latent = state_.mu[j] + llt.matrixL() * Eigen::Vector2d(xi0, xi1);
  out.pressures_kPa = pressures_kPa(out.latent, j);
  return out;
}

void DesignDistribution::update(const std::vector<DesignSample>& samples,
                                const std::vector<double>& returns, std::int64_t t) {
  if (samples.size() != returns.size())
    throw std::invalid_argument("DesignDistribution::update: " + std::to_string(samples.size()) +
                                " samples but " + std::to_string(returns.size()) + " returns");
  for (std::size_t i = 0; i < samples.size(); ++i) {
    check_design(samples[i].design);
    if (!std::isfinite(returns[i]) || !samples[i].latent.allFinite())
      throw std::invalid_argument("DesignDistribution::update: sample " + std::to_string(i) +
                                  " has a non-finite return or latent");
  }

  const Phase ph = phase(t);
  // Strong guarantee: if the arithmetic overflows (a latent astronomically far from μ), the
  // state is left as it was.
  DistributionState before = state_;
  if (ph == Phase::Exploitation && !state_.collapsed) collapse();

  for (std::size_t i = 0; i < samples.size(); ++i) {
    const int j = samples[i].design;
    const double r = returns[i];

    // Line 3: running stats over the reward buffer.
    auto& buf = state_.buffer[j];
    buf.push_back(r);
    if (buf.size() > static_cast<std::size_t>(config_.reward_buffer)) buf.erase(buf.begin());
    ++state_.samples[j];

    if (ph == Phase::Exploration) {  // lines 4–8
      if (r > state_.score(j)) {
        state_.score(j) = r;
        state_.mu[j] = Eigen::Vector2d::Constant(config_.latent_mu0);
        state_.sigma[j] =
            config_.latent_sigma0 * config_.latent_sigma0 * Eigen::Matrix2d::Identity();
      }
    } else if (ph == Phase::Transition) {  // lines 9–14
      const double count = static_cast<double>(buf.size());
      const double mean = std::accumulate(buf.begin(), buf.end(), 0.0) / count;
      double var = 0.0;
      for (double x : buf) var += (x - mean) * (x - mean);
      const double std_dev = std::sqrt(var / count);  // population std
      state_.score(j) = mean;
      const double advantage = std_dev > kMinRewardStd ? (r - state_.baseline(j)) / std_dev : 0.0;
      if (advantage != 0.0) {
        const Eigen::Vector2d d = samples[i].latent - state_.mu[j];  // old μ
        const double step = config_.alpha * advantage;
        const Eigen::Matrix2d old_sigma = state_.sigma[j];
        state_.mu[j] += step * d;                                     // Eq. 7
        state_.sigma[j] = old_sigma + step * (d * d.transpose() - old_sigma);  // Eq. 8
        condition_sigma(j);                                           // line 14 + PD floor
        if (!state_.mu[j].allFinite() || !state_.sigma[j].allFinite()) {
          state_ = std::move(before);
          throw std::invalid_argument("DesignDistribution::update: sample " + std::to_string(i) +
                                      " makes mu or sigma of design " + std::to_string(j) +
                                      " non-finite");
        }
      }
    }
    // Exploitation: R̂, μ, Σ fixed.

    // Line 17, every phase (Eq. 9).
    state_.baseline(j) = (1.0 - config_.phi) * state_.baseline(j) + config_.phi * r;
  }
}

void DesignDistribution::collapse() {
  if (state_.collapsed) return;
  state_.best_design = argmax_score();
  state_.best_latent = state_.mu[state_.best_design];
  state_.collapsed = true;
}

Eigen::Vector2d DesignDistribution::pressures_kPa(const Eigen::Vector2d& latent,
                                                  int design) const {
  check_design(design);
  const double p1 = config_.pressure_max_kPa * sigmoid(latent(0));
  const double p2 = chambers_[design] == 1 ? 0.0 : config_.pressure_max_kPa * sigmoid(latent(1));
  return {p1, p2};
}

Eigen::Vector2d DesignDistribution::mean_pressures_kPa(int design) const {
  check_design(design);
  return pressures_kPa(state_.mu[design], design);
}

Eigen::Vector2d DesignDistribution::sigma_pressures_kPa(int design) const {
  check_design(design);
  Eigen::Vector2d out;
  for (int i = 0; i < 2; ++i) {
    const double s = sigmoid(state_.mu[design](i));
    out(i) = config_.pressure_max_kPa * s * (1.0 - s) * std::sqrt(state_.sigma[design](i, i));
  }
  if (chambers_[design] == 1) out(1) = 0.0;
  return out;
}

std::vector<int> DesignDistribution::ranking() const {
  std::vector<int> order(chambers_.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return state_.score(a) > state_.score(b); });
  return order;
}

int DesignDistribution::chambers(int design) const {
  check_design(design);
  return chambers_[design];
}

int DesignDistribution::argmax_score() const {
  int best = 0;
  for (int j = 1; j < design_count(); ++j)
    if (state_.score(j) > state_.score(best)) best = j;  // strict: ties keep the lower index
  return best;
}

void DesignDistribution::check_design(int design) const {
  if (design < 0 || design >= design_count())
    throw std::invalid_argument("DesignDistribution: design index " + std::to_string(design) +
                                " out of range [0, " + std::to_string(design_count()) + ")");
}

void DesignDistribution::condition_sigma(int design) {
  const double floor = config_.latent_sigma_min * config_.latent_sigma_min;
  Eigen::Matrix2d& s = state_.sigma[design];
  if (chambers_[design] == 1) {  // Algorithm 2 line 14; Σ diagonal: its eigenvalues are Σ11, Σ22
    s(0, 1) = 0.0;
    s(1, 0) = 0.0;
    s(0, 0) = std::max(s(0, 0), floor);
    s(1, 1) = std::max(s(1, 1), floor);
    return;
  }
  s = 0.5 * (s + s.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(s);
  if (eig.eigenvalues().minCoeff() >= floor) return;  // already PD above the floor: untouched
  const Eigen::Vector2d lambda = eig.eigenvalues().cwiseMax(floor);
  const Eigen::Matrix2d v = eig.eigenvectors();
  s = v * lambda.asDiagonal() * v.transpose();
  s = 0.5 * (s + s.transpose()).eval();
}

}  // namespace codesign::core
