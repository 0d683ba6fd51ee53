#include "run/progress_line.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <string>

#include <unistd.h>

#include "base/duration_text.hpp"
#include "fem/design.hpp"

namespace codesign::run {

ProgressLine::ProgressLine(bool enabled) : enabled_(enabled), tty_(enabled && ::isatty(::fileno(stdout))) {}

void ProgressLine::iteration(const core::IterationReport& rep, const core::DesignDistribution& dist,
                             const core::CodesignConfig& c, double elapsed_s, double steps_per_s,
                             std::int64_t numerical_failures, bool last) {
  if (!enabled_ || (elapsed_s - last_print_s_ < (tty_ ? 0.5 : 10.0) && !last)) return;
  last_print_s_ = elapsed_s;
  const std::int64_t total = c.total_timesteps;
  const int best = c.baseline == core::Baseline::SingleDesign ? c.single_design_index : dist.leading_design();
  const double mean_first = std::accumulate(rep.returns.begin(), rep.returns.end(), 0.0) /
                            static_cast<double>(std::max<std::size_t>(1, rep.returns.size()));
  const std::string failures =
      numerical_failures > 0 ? " | numerical failures " + std::to_string(numerical_failures) : "";
  std::printf("%st %lld/%lld (%.1f%%) | %.0f steps/s | ETA %s | %s | mean return %.2f | best %s R^ %.2f%s%s",
              tty_ ? "\r" : "", static_cast<long long>(rep.t), static_cast<long long>(total),
              100.0 * static_cast<double>(rep.t) / static_cast<double>(total), steps_per_s,
              duration_text(static_cast<double>(total - rep.t) / std::max(steps_per_s, 1e-9)).c_str(),
              core::to_string(dist.phase(rep.t)), mean_first, fem::design_label(best).c_str(),
              dist.state().score[best], failures.c_str(), tty_ ? "   " : "\n");
  std::fflush(stdout);
}

void ProgressLine::end_line() const {
  if (tty_) std::printf("\n");
}

}  // namespace codesign::run
