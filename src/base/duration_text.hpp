#pragma once
// A duration in seconds as a progress line shows it: "1h05m" from an hour on, "3m07s" below
// (rounded to the nearest second), "?" when it is not known (negative or not finite, as an ETA
// is before the first rate is measured). Used by the run's and the sweep's progress lines and
// final summaries.
#include <cmath>
#include <cstdio>
#include <string>

namespace codesign {

inline std::string duration_text(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const auto total = static_cast<long>(seconds + 0.5);
  char buf[32];
  if (total >= 3600)
    std::snprintf(buf, sizeof buf, "%ldh%02ldm", total / 3600, (total / 60) % 60);
  else
    std::snprintf(buf, sizeof buf, "%ldm%02lds", total / 60, total % 60);
  return buf;
}

}  // namespace codesign
