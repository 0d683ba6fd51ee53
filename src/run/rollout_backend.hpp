#pragma once
// The rollout backend of a run (Algorithm 1's ψ environments): in this process on `threads`
// threads (core::ThreadEnvPool), or spread over the ranks of an MPI launch
// (cluster::MpiEnvPool, docs/cluster.md). Results are the same either way.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/env_pool.hpp"
#include "core/simulator_pool.hpp"
#include "run/run_settings.hpp"

namespace codesign::run {

// InputError unless every one of `ranks` gets at least one of the run's environments
// (designs_per_update): checked by every rank before any of them starts.
void check_rollout_ranks(const core::LoopConfig& lc, int ranks);

// Rank 0's pool: every environment here when ranks == 1, else its slice here and the others on
// ranks 1..ranks-1, which must be in serve_rollouts. InputError if ranks exceed the environments.
// `machine`: the world ranks on rank 0's machine (cluster::ranks_on_this_machine; empty: rank 0
// alone), whose threads rank 0 takes up when they are done with a whole rollout
// (cluster/lent_threads.hpp).
std::unique_ptr<core::EnvPool> make_rollout_pool(std::shared_ptr<core::SimulatorPool> sims, const core::LoopConfig& lc,
                                                 std::size_t threads, int ranks, const std::vector<int>& machine = {});

// One line on how the pool shared its environments out, for the run's summary: under MPI, at how
// many of its starts the environments went to the ranks by cost rather than in contiguous slices
// (cluster::assign_by_cost); empty for the threads of one process.
std::string rollout_sharing_note(core::EnvPool& pool);

// The start of every command that runs Algorithm 1 under an MPI launcher (docs/cluster.md): checks
// the launch's rank count against the run's environments (check_rollout_ranks: InputError, on
// every rank alike), then on ranks 1.. serves rank 0's rollouts until its pool is gone and returns
// true (the caller ends: such a rank touches no file); on rank 0, or without a launcher, returns
// false at once.
// `machine`: as make_rollout_pool's, for this rank's machine.
bool serve_unless_rank_zero(const RunSettings& settings, std::size_t threads, const std::vector<int>& machine = {});

// Ranks 1..ranks-1: this rank's slice of the run's environments (its own simulators, `threads`
// threads), stepped for rank 0 until its pool is gone. SIGINT and SIGTERM are ignored here: the
// launcher delivers them to every rank, and rank 0 answers them by finishing its iteration and
// checkpointing, which needs this rank until then.
void serve_rollouts(const RunSettings& settings, std::size_t threads, int rank, int ranks,
                    const std::vector<int>& machine = {});

}  // namespace codesign::run
