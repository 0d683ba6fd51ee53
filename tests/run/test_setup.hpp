#pragma once
// A co-design run small enough for unit tests: the loop of tiny_loop.hpp (4 environments, 5
// decisions per episode, small networks, all three phases within 6 iterations) as run settings.
#include "run/run.hpp"
#include "tiny_loop.hpp"

namespace codesign::run::test {

inline RunSettings tiny_run(std::uint64_t seed = 7) {
  const test_loops::TinyLoop t = test_loops::tiny_loop(seed);
  RunSettings s;
  s.spec = t.spec;
  s.scene = t.scene;
  s.solver = t.solver;
  s.loop = t.loop;
  s.config_text = "# tiny test run, seed " + std::to_string(seed) + "\n";
  return s;
}

}  // namespace codesign::run::test
