#pragma once
// How much the designs' different costs load the busiest rank (measured: docs/journal/cluster.md,
// "The split by cost, and why two ranks are slower").
//
// The scaling model (scaling_model.hpp) puts ⌈ψ/N⌉ environments of the same cost c on the busiest
// rank. The 110 designs do not cost the same: in `bench cluster` on the paper's config the mean
// collection of a design over an iteration ranged 0.12–0.48 s. With few environments per rank the
// rank that draws the expensive designs sets every decision's pace. busiest_load_factor estimates
// by simulation, from measured (design, cost) samples, the factor F by which this raises the
// collection term, for the contiguous slices (env_slice) and for the split by predicted cost
// (assign_by_cost, the split the MPI backend uses).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace codesign::cluster {

// One environment's settle and step CPU seconds over one iteration, with its design.
struct CostSample {
  int design = 0;
  double seconds = 0.0;
};

// Of a set of samples: the mean cost; over the designs with a sample, the least and the largest
// mean and the (population) standard deviation of their means; and the pooled standard deviation
// within a design (the root mean square of every sample's distance from its design's mean).
struct CostSummary {
  std::size_t designs = 0;
  double mean = 0.0, least_design = 0.0, largest_design = 0.0, across_designs = 0.0, within_design = 0.0;
};
// std::invalid_argument for no samples.
CostSummary summarize_costs(const std::vector<CostSample>& samples);

struct BusiestLoad {
  double contiguous = 1.0;  // F with the contiguous slices
  double by_cost = 1.0;     // F with assign_by_cost
};

// F = E[busiest rank's collection] / (collection_rounds(environments, ranks, threads) · mean cost),
// over `draws` iterations of `environments` samples drawn at random (with replacement) from
// `samples`. A rank's collection is the longest-first split of its environments over its threads
// (their makespan). assign_by_cost predicts an environment's cost by another sample of its design
// drawn at random (the design's cost in an earlier iteration, as the backend does), or by the mean
// of all samples when its design has only one. All costs equal gives F = 1 for either split.
// std::invalid_argument for no samples, a negative or non-finite cost, draws < 1, or what
// env_slice and collection_rounds refuse.
BusiestLoad busiest_load_factor(const std::vector<CostSample>& samples, std::size_t environments, int ranks,
                                int threads, int draws, std::uint64_t seed);

// One environment's settle and step CPU seconds at each meeting point of one iteration, with its
// design: seconds[0] its start (the settle), seconds[k] its k-th decision's step (a restart's
// restore of the settled state included).
struct DecisionCosts {
  int design = 0;
  std::vector<double> seconds;
};

// How much the meeting at every decision costs on top of the iteration totals. The ranks of the
// MPI backend meet at the start and at every decision (mpi_env_pool.hpp): a decision takes as long
// as its slowest rank, and a rank's share of a decision varies from one decision to the next
// (contact comes and goes, restarts) where its share of the iteration varies less. Over `draws`
// iterations of `environments` profiles drawn at random (with replacement) from `samples`, split
// over the ranks by assign_by_cost (each environment's iteration total predicted by another sample
// of its design, as busiest_load_factor does), a rank's time at meeting point k is the makespan of
// its environments' k-th costs over its threads, which take them in order of the environments'
// previous costs (the predicted totals at the start), each to the thread free soonest, as
// ThreadEnvPool does. Then
//   lockstep  = E[Σ_k max over ranks of the rank's time at k]    (the backend as built)
//   run_ahead = E[max over ranks of Σ_k the rank's time at k]    (ranks that met only at the
//                                                                  iteration's end)
// both over collection_rounds(environments, ranks, threads) · the mean iteration total, the
// normalisation of busiest_load_factor's F. All costs equal gives 1 for both; one rank gives
// lockstep == run_ahead. std::invalid_argument for no samples, profiles of different lengths or
// empty, a negative or non-finite cost, draws < 1, or what env_slice and collection_rounds refuse.
// start: E[the slowest rank's time at point 0] in the same normalisation, the share of lockstep
// spent at the start's meeting (the settles), which depends on the setups alone.
// floor: E[max over ranks of max(its costliest environment's iteration total, its environments'
// totals summed / threads)], the same normalisation: what no order of a rank's jobs on its threads
// can beat, since an environment's decisions follow one another (floor <= run_ahead for any costs).
// Ranks 1.. starting their environments (point 0) while rank 0 runs the update (MpiEnvPool::prestart),
// rank 0 starting its own after it: from the update's end, rank 0 takes its Σ_k and rank r ≥ 1
// takes max(0, its start − update) + Σ_{k≥1}. after_update: E[the largest of these], with `update`
// (in the samples' seconds) as given; update 0 gives run_ahead. prestarted: the same with the
// starts entirely hidden (update beyond every start): max(rank 0's Σ_k, max over r ≥ 1 of
// Σ_{k≥1}). prestart: E[max over r ≥ 1 of its start]. With P = prestart, prestarted +
// max(0, P − update) ≥ after_update: the bound scaling_model's prestart_s gives. One rank:
// prestarted == after_update == run_ahead, prestart == 0.
struct MeetingLoad {
  double lockstep = 1.0;
  double run_ahead = 1.0;
  double start = 0.0;
  double floor = 1.0;
  double prestarted = 1.0;
  double prestart = 0.0;
  double after_update = 1.0;
};
MeetingLoad meeting_load_factor(const std::vector<DecisionCosts>& samples, std::size_t environments, int ranks,
                                int threads, int draws, std::uint64_t seed, double update = 0.0);

}  // namespace codesign::cluster
