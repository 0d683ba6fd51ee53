#pragma once
// How the ψ environments of an iteration are shared out over MPI ranks (mpi_env_pool.hpp).
//
// How many: env_slice, fixed for a run (each rank's ThreadEnvPool holds that many environments).
// Which: assign_by_cost, chosen anew at every start(), when every environment begins a new episode
// with a new design and so can move to any rank without changing a result (env_pool.hpp: an
// environment owns its state, draws no random numbers, and a simulator's reset() leaves no trace
// of earlier episodes). The ranks meet at every decision (step by step) or once per rollout (whole
// rollouts), so a rank whose environments are slower holds the others up; giving each rank a
// similar predicted cost is what --threads does within one process by handing out environments
// one at a time. A rank also builds what it has not yet built for the designs it is given
// (BuildCosts), which one process does once for all its threads.
#include <cstddef>
#include <vector>

namespace codesign::cluster {

// The environments [first, first + count) of `rank` among `ranks`: contiguous, sizes differing by
// at most one, the larger slices first. Throws std::invalid_argument if ranks < 1, rank outside
// [0, ranks), or n_envs < ranks (every rank steps at least one environment).
struct EnvSlice {
  std::size_t first = 0, count = 0;
};
EnvSlice env_slice(std::size_t n_envs, int rank, int ranks);
// env_slice of every rank, rank 0 first (the same errors).
std::vector<EnvSlice> env_slices(std::size_t n_envs, int ranks);

// Each environment's predicted cost for assign_by_cost, from `design_cost` (per design index
// 0..109, the CPU seconds of its settles and steps in the last iteration that stepped it; NaN where
// not yet stepped): a known design's own cost; a design not yet stepped, the mean of the known
// designs of its wall thickness, which sets most of a design's cost (traced two-rank runs of
// paper.toml: about 0.8 s per iteration at 2.0 mm, 0.3 s at 4.0 mm; docs/journal/cluster.md,
// "Builds and wall thickness in the split"), or of all known designs if none of that thickness
// is known; an environment without a valid design, the mean of all. Empty if no design is known.
std::vector<double> predict_costs(const std::vector<double>& design_cost, const std::vector<int>& env_design);

// A permutation `order` of the environments 0 .. cost.size()-1: place j of the slices (rank r has
// places [slices[r].first, + count)) steps environment order[j]. Pinned environments (each below
// slices[0].count) stay on rank 0 at their own place (order[i] == i): live telemetry follows them
// there. The others go, costliest first (ties: lower index first), to the rank with the least
// predicted cost so far among those with a free place (ties: lower rank) — the greedy
// longest-processing-time rule with the slices' sizes as capacities; so no rank's total exceeds
// another's by more than the largest single cost, unless pins force it; then swaps between two
// ranks that lower the larger of their totals (the overload below, without builds). Within a rank the
// environments keep ascending order around the pins. Throws std::invalid_argument if the slices
// do not cover cost.size() places contiguously from 0, a cost is negative or not finite, or a pin
// is out of range or repeated.
std::vector<std::size_t> assign_by_cost(const std::vector<double>& cost, const std::vector<EnvSlice>& slices,
                                        const std::vector<std::size_t>& pinned);

// What a rank must build before it can step an environment, on top of the environment's cost: the
// design's model the first time the rank gets that design — meshing it, or, where the design's
// mesh is known (rank 0 holds it and sends it), only building the model from the mesh — and one
// more simulator whenever the rank steps more environments of a design at once than it ever has
// (each rank's SimulatorPool keeps its simulators for reuse). Seconds of one rank's CPU, like the
// costs.
struct BuildCosts {
  double model = 0.0;      // one design's model, on a rank that has none of it, meshing it
  double simulator = 0.0;  // one simulator, its model built
  std::vector<int> design;              // per environment, its design (negative: builds nothing)
  std::vector<std::vector<int>> held;   // per rank, per design index: simulators the rank holds
  double model_from_mesh = 0.0;         // one design's model from its known mesh (instead of `model`)
  std::vector<char> meshed{};           // per design index: its mesh is known (missing: not)
};

// assign_by_cost with each rank's builds counted: an environment (costliest first, as above) goes
// to the rank with a free place whose total, the environment's cost plus what that rank must build
// for it, would be least after it (ties: lower rank); an environment taken by a rank uses one of
// its held simulators of the design, or builds one. Then, since that greedy places one environment
// at a time, two environments on two ranks swap places while that lowers the larger of the two
// ranks' totals, or keeps it and lowers their sum (fewer builds), until no swap does (pins stay).
// The plain assign_by_cost above is this with both build costs zero; the swaps only narrow its
// bound. With builds the bound does not carry over (once a rank's slice is full the others may
// have to take environments they must build for). Throws std::invalid_argument as above, and if
// `build` has not one design per environment and one row of held counts per rank, or a build cost
// or held count is negative or not finite.
std::vector<std::size_t> assign_by_cost(const std::vector<double>& cost, const std::vector<EnvSlice>& slices,
                                        const std::vector<std::size_t>& pinned, const BuildCosts& build);

// After an assignment (`order`, as assign_by_cost returns it): each rank holds at least as many
// simulators of each design as it steps environments of it now. The designs' indices beyond a
// rank's row of held counts grow it. Throws std::invalid_argument if `build` has not one row per
// slice or `order` does not fill the slices.
void record_held(const std::vector<std::size_t>& order, const std::vector<EnvSlice>& slices, BuildCosts& build);

}  // namespace codesign::cluster
