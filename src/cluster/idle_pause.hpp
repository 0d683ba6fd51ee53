#pragma once

// How long a rank that waits for a message sleeps between two polls (docs/journal/cluster.md,
// "A waiting rank's polls"). Open MPI's shared-memory transport has no wait that sleeps in the
// kernel, so a waiting rank polls; each wake-up costs the ranks still working on the same cores
// some of their time (11-16 µs of theirs per wake, with a wide spread; measured with
// experiments/evaluation_pairs.sh and WAKER_US, same section), and a long pause makes the
// waiter notice its message late. A wait that has lasted w seconds is taken to last about as long
// again: then n = w / p wakes cost n · c and the answer comes p / 2 late on average, and
// c · w / p + p / 2 is least at p = √(2 c w). Hence the pause grows with the root of the time
// waited, from `min_s` to `max_s`.
namespace codesign::cluster {

struct IdlePause {
  double wake_cost_s = 16e-6;  // what a wake-up costs the working ranks (the upper measurement)
  double min_s = 20e-6;        // the first pauses
  double max_s = 20e-3;        // the longest: how late a rank may notice rank 0's last message
};

// The pause after `waited_s` seconds of waiting: √(2 c w) clamped to [min_s, max_s].
double idle_pause_seconds(double waited_s, const IdlePause& rule = {});

}  // namespace codesign::cluster
