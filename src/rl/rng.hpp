#pragma once
// The learner's seeded random number generator: std::mt19937_64 plus portable uniform and
// normal draws. The standard library's distributions are not specified bit-for-bit (libstdc++ and
// libc++ differ), so both are written out here: a run is reproducible from its seed on any
// platform with IEEE doubles and the same libm.
//
//   Rng rng(42);
//   double u = rng.uniform();        // [0, 1)
//   double z = rng.normal();         // N(0, 1), Box-Muller, both values of a pair are used
//   Rng child = rng.split();         // an independent stream (e.g. one per environment)
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

namespace codesign::rl {

// splitmix64's output function: one well-mixed 64-bit value from another (seeds of child streams).
inline std::uint64_t splitmix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed = 0) : engine_(seed) {}

  std::uint64_t next_u64() { return engine_(); }

  // Uniform in [0, 1) from the top 53 bits of one draw.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

  // Uniform integer in [0, n), n > 0 (Lemire's multiply-shift with rejection: unbiased).
  std::uint64_t uniform_index(std::uint64_t n) {
    for (;;) {
      const unsigned __int128 m = static_cast<unsigned __int128>(engine_()) * n;
      const auto low = static_cast<std::uint64_t>(m);
      if (low >= n || low >= (-n) % n) return static_cast<std::uint64_t>(m >> 64);
    }
  }

  // Standard normal by the Box-Muller transform; the second value of each pair is cached.
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]: log is finite
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double t = 2.0 * std::numbers::pi * u2;
    spare_ = r * std::sin(t);
    has_spare_ = true;
    return r * std::cos(t);
  }

  // A new generator seeded from this one (splitmix64 of a draw, so child streams differ).
  Rng split() { return Rng(splitmix64(engine_())); }

  std::mt19937_64& engine() { return engine_; }

  // The whole state (engine and the cached Box-Muller value) as text, for checkpoints;
  // restore() gives a generator whose future draws are identical. restore() returns false (and
  // leaves the generator unchanged) for text that is not such a state.
  std::string save() const {
    std::ostringstream out;
    out << engine_ << ' ' << (has_spare_ ? 1 : 0) << ' ' << std::hexfloat << spare_;
    return out.str();
  }
  bool restore(const std::string& text) {
    std::istringstream in(text);
    std::mt19937_64 e;
    int has = 0;
    std::string spare;
    if (!(in >> e >> has >> spare) || (has != 0 && has != 1)) return false;
    char* end = nullptr;
    const double v = std::strtod(spare.c_str(), &end);
    if (end == spare.c_str() || *end != '\0') return false;
    std::string rest;
    if (in >> rest) return false;
    engine_ = e;
    has_spare_ = has == 1;
    spare_ = v;
    return true;
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace codesign::rl
