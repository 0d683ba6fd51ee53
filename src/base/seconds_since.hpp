#pragma once
// Wall seconds elapsed since a steady-clock time point: the timing of the rollout loop, the
// trainer and the co-design's outer loop.
#include <chrono>

namespace codesign {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace codesign
