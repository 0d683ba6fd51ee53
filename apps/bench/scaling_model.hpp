#pragma once
// How an iteration of Algorithm 1 scales with MPI ranks: a model fed with costs
// measured on one machine (`codesign bench cluster`, docs/cluster.md).
//
// One iteration on N ranks of t threads each:
//   collection  F · ⌈⌈ψ/N⌉ / t⌉ · c  +  (N − 1) · s · x
//   serial      u + p + d
// with ψ environments split as cluster::env_slice does (the busiest rank holds ⌈ψ/N⌉, stepped on
// its t threads in rounds of t environments of equal cost), c the collection wall of one
// environment per round over an iteration (its settles and FEM steps, and what a round costs
// besides: resets, observations, thread hand-offs; `bench cluster` measures it), s the
// exchanges per iteration (one per decision and one start when the rollouts go step by step; one
// when each rank runs its environments' whole rollout, core/run_ahead.hpp), x the cost of one
// exchange between rank 0 and one other rank (rank 0 talks to the ranks one after the other), and the parts that
// run on rank 0 alone: u the PPO update, p the policy inference, d the distribution update.
// F (collect_factor, 1 by default) is how much more the busiest rank carries because the designs
// differ in cost (cost_spread.hpp estimates it from measured costs for a given N).
// Amdahl's law with a message term: the serial part bounds the speed-up at (⌈ψ/t⌉·c + u + p + d) /
// (c + u + p + d) however many ranks there are.
// With update_spread the update's u becomes e · u / N + g · 2 (N − 1)/N · y: a data-parallel update
// (each rank computes the gradient of its share of each minibatch; not built), g the minibatches
// whose gradient an iteration's update computes, y the time to move one gradient (the parameters'
// size) from one rank to another. 2 (N − 1)/N gradients is the least any rank must send and receive
// to combine N ranks' gradients and share the sum (a reduce-scatter, then an all-gather; the sum's
// order can stay fixed, as one process's, by summing each segment on its owner in a fixed order).
// With y = 0 the messages are free: a bound. u / N alone would be optimistic: a rank's share of a
// 256-sample minibatch on 16 ranks is 16 samples, too narrow for the products' full speed; e
// (update_share_cost, 1 by default) is the measured time of the busiest rank's share of a
// minibatch's gradient times N over the whole minibatch's, set for the N at hand.
#include <cstddef>
#include <vector>

namespace codesign::cluster {

struct ScalingCosts {
  std::size_t environments = 40;     // ψ
  int threads_per_rank = 1;          // t
  double env_collect_s = 0.0;        // c
  int exchanges = 51;                // s: decisions per episode + 1
  double exchange_s = 0.0;           // x
  double update_s = 0.0;             // u
  double policy_s = 0.0;             // p
  double distribution_s = 0.0;       // d
  bool update_spread = false;        // u / N + messages instead of u (see above)
  double update_minibatches = 0.0;   // g: minibatches with a gradient per iteration (update_spread)
  double gradient_transfer_s = 0.0;  // y: one gradient from one rank to another (update_spread)
  double update_share_cost = 1.0;    // e: a share's compute, N shares over the whole (update_spread)
  double collect_factor = 1.0;       // F (see above)
  // Wall seconds the ranks other than rank 0 spend starting their next environments (the settles)
  // while rank 0 runs the update (MpiEnvPool::prestart); the update's term becomes max(it, this).
  // collect_factor then holds F without those starts. 0: no starts before the update.
  double prestart_s = 0.0;
};

// ⌈⌈environments/ranks⌉ / threads⌉: the rounds of one environment each that the busiest rank's
// threads step per decision (env_slice's split; std::invalid_argument as env_slice, or threads < 1).
std::size_t collection_rounds(std::size_t environments, int ranks, int threads);

// Seconds per iteration on `ranks` ranks (1 ≤ ranks ≤ environments; std::invalid_argument
// otherwise, or for threads_per_rank < 1 or a negative cost).
double iteration_seconds(const ScalingCosts& c, int ranks);

// One iteration of a finished one-process run (its ppo.csv row): wall seconds of the collection
// (policy inference included), of the policy inference, and of the PPO update.
struct RunIteration {
  double collect_s = 0.0, policy_s = 0.0, update_s = 0.0;
};

// A whole run of `run_threads` threads, projected iteration by iteration to `ranks` ranks of
// `threads` threads (experiments/cluster_projection.sh's arithmetic): with
// s = rounds(ranks, threads) / rounds(1, run_threads) · (collect − policy), each iteration takes
// F · s + policy + update, the update's term max(update, P · s) on more than one rank (P: the
// slowest rank's starts during the update, 0: none; F then the collection without them). Messages
// are left out. Seconds of the run; std::invalid_argument for no iterations, a negative or
// non-finite figure, or what collection_rounds refuses.
double projected_run_seconds(const std::vector<RunIteration>& run, std::size_t environments, int run_threads,
                             int ranks, int threads, double F, double P);

}  // namespace codesign::cluster
