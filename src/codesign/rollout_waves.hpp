#pragma once
// Which of a share's environments take their next job together when a rank runs its share's whole
// rollout (run_ahead.hpp): the schedule of run_share (issue 20 §3).
//
// Stepping every environment at every decision, with one forward pass of the policy per decision,
// leaves threads idle when the environments do not divide evenly over them: 3 environments on 2
// threads take two step times per decision, one thread idle for half of it (the busiest rank of 40
// environments on 16 ranks × 2 threads holds 3). Nothing an environment computes depends on when
// it steps or beside which others (its column of the policy's batch depends on no other column, and
// its draws are fixed per decision), so a share can advance in waves instead: each wave one forward
// pass for the environments in it that step, then each of them takes one job on the threads,
// longest first: its episode's start (the first job) or its next decision. Three environments of
// equal cost on 2 threads then go two at a time, one step time per wave: 1.5 step times per
// decision and 1.5 forward passes instead of one.
//
// next_wave picks the wave: the environments with jobs left, those with the most predicted work
// left first (jobs left × predicted cost of a job, the start's cost added while it is to come), as
// many as the candidate size that gives the most predicted work per second of wave:
//   Σ costs / (makespan of those costs over the threads taken longest first + pass_s if one steps)
// over the sizes threads, 2·threads, ... below the count of environments with jobs left, and that
// count; a smaller size must beat every larger one by more than 1 % (the predictions are the last
// jobs' costs, which vary). With every cost equal and the threads dividing the environments, the
// wave is all of them: one wave per decision, the schedule of stepping all at every decision.
#include <cstddef>
#include <vector>

namespace codesign::core {

struct WaveEnv {
  int jobs_left = 0;          // 0: done
  bool started = true;        // false: the next job is the episode's start (no forward pass)
  double start_cost = 0.0;    // predicted seconds of the start (while not started)
  double step_cost = 0.0;     // predicted seconds of one decision's step
};

// The makespan of `costs` over `threads` threads, each taken in falling order by the thread with
// the least load so far (the longest-processing-time rule; ThreadPool::parallel_for_ordered runs
// them so). 0 for no costs; threads >= 1.
double longest_first_makespan(std::vector<double> costs, std::size_t threads);

// The indices of the environments in the next wave, most predicted work left first (ties: lower
// index); empty when none has jobs left. threads >= 1 (std::invalid_argument otherwise, or for a
// negative or non-finite cost or pass_s).
std::vector<std::size_t> next_wave(const std::vector<WaveEnv>& envs, std::size_t threads, double pass_s);

}  // namespace codesign::core
