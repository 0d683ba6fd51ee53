#pragma once
// The run's progress line on stdout: timestep, rate, time left, phase, mean first-episode return,
// leading design with its score, numerical failures. On a terminal it is rewritten in place at
// most every 0.5 s; to a file or pipe it is a new line at most every 10 s; the last iteration
// always prints.
#include <cstdint>

#include "core/codesign_config.hpp"
#include "core/design_distribution.hpp"
#include "core/outer_loop.hpp"

namespace codesign::run {

class ProgressLine {
 public:
  explicit ProgressLine(bool enabled);  // false: prints nothing

  // After an iteration, elapsed_s into this session; `last`: the run's final iteration.
  void iteration(const core::IterationReport& rep, const core::DesignDistribution& dist,
                 const core::CodesignConfig& c, double elapsed_s, double steps_per_s, std::int64_t numerical_failures,
                 bool last);
  // Ends a line that a terminal would leave open (before other output follows it).
  void end_line() const;

 private:
  bool enabled_;
  bool tty_;
  double last_print_s_ = -1e9;
};

}  // namespace codesign::run
