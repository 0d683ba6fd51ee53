#include "run/rollout_backend.hpp"

#include <csignal>
#include <cstdio>
#include <stdexcept>

#include "base/errors.hpp"
#include "cluster/mpi_env_pool.hpp"
#include "cluster/mpi_world.hpp"
#include "core/outer_loop.hpp"

namespace codesign::run {

namespace {

cluster::EnvSlice slice_of(const core::LoopConfig& lc, int rank, int ranks) {
  try {
    return cluster::env_slice(static_cast<std::size_t>(lc.codesign.designs_per_update), rank, ranks);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::to_string(ranks) + " MPI ranks (mpirun -np / srun -n): codesign.designs_per_update = " +
                     std::to_string(lc.codesign.designs_per_update) +
                     " environments cannot give every rank one; allowed: 1 to " +
                     std::to_string(lc.codesign.designs_per_update) + " ranks");
  }
}

// A rank's own threads and the other ranks on its machine (lent_threads.hpp), and the threads its
// pool holds for them.
struct RankThreads {
  cluster::Lending lending;
  std::size_t pool = 0;
};

RankThreads rank_threads(std::size_t threads, int rank, const std::vector<int>& machine, std::size_t envs) {
  RankThreads t;
  t.lending.own_threads = threads;
  for (int r : machine)
    if (r != rank) t.lending.peers.push_back(r);
  t.pool = cluster::pool_threads(threads, t.lending.peers.size() + 1, envs, cluster::cpus_of_this_process());
  return t;
}

std::string seconds_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", s);
  return buf;
}

}  // namespace

void check_rollout_ranks(const core::LoopConfig& lc, int ranks) {
  if (ranks > 1) slice_of(lc, 0, ranks);
}

std::unique_ptr<core::EnvPool> make_rollout_pool(std::shared_ptr<core::SimulatorPool> sims, const core::LoopConfig& lc,
                                                 std::size_t threads, int ranks, const std::vector<int>& machine) {
  const auto n = static_cast<std::size_t>(lc.codesign.designs_per_update);
  if (ranks <= 1) return std::make_unique<core::ThreadEnvPool>(sims, lc.task, n, threads, lc.ppo.privileged_critic);
  const cluster::EnvSlice mine = slice_of(lc, 0, ranks);
  RankThreads t = rank_threads(threads, 0, machine, mine.count);
  auto local = std::make_unique<core::ThreadEnvPool>(sims, lc.task, mine.count, t.pool, lc.ppo.privileged_critic);
  return std::make_unique<cluster::MpiEnvPool>(std::move(local), n, ranks, std::move(t.lending));
}

std::string rollout_sharing_note(core::EnvPool& pool) {
  const auto* mpi = dynamic_cast<const cluster::MpiEnvPool*>(&pool);
  if (!mpi) return {};
  return "rollouts on " + std::to_string(mpi->ranks()) + " MPI ranks: environments shared out by cost at " +
         std::to_string(mpi->reassigned_starts()) + " of " + std::to_string(mpi->starts()) +
         " iterations' starts (contiguous slices at the others: the first, and any where the costs gave that split); "
         "each rank ran its environments' whole rollout, meeting the others once, in " +
         std::to_string(mpi->rollouts()) + " of them (the others step by step, meeting at every decision: "
         "recurrent policies and observation statistics need that), the ranks with cores of their own during rank "
         "0's PPO update starting their environments during it in " + std::to_string(mpi->prestarted_rollouts()) +
         "; designs' meshes: " +
         std::to_string(mpi->meshes_received()) + " made on the other ranks and sent to rank 0, " +
         std::to_string(mpi->meshes_sent()) + " sent to a rank that had not built the design (built there from "
         "the mesh instead of meshing); the ranks stepped whole rollouts on threads lent by ranks of their machine "
         "that were done for " + seconds_text(mpi->lent_seconds_of_all_ranks()) + " s in all";
}

void serve_rollouts(const RunSettings& s, std::size_t threads, int rank, int ranks, const std::vector<int>& machine) {
  std::signal(SIGINT, SIG_IGN);
  std::signal(SIGTERM, SIG_IGN);
  const core::LoopConfig& lc = s.loop;
  const cluster::EnvSlice mine = slice_of(lc, rank, ranks);
  auto sims = std::make_shared<core::SimulatorPool>(s.spec, s.scene, s.solver);
  const RankThreads t = rank_threads(threads, rank, machine, mine.count);
  core::ThreadEnvPool local(sims, lc.task, mine.count, t.pool, lc.ppo.privileged_critic);
  rl::ActorCritic model = core::feed_forward_model(lc, local);  // rollout() sends its parameters
  cluster::serve_env_pool(local, lc.ppo.policy == rl::PolicyKind::Mlp ? &model : nullptr, t.lending);
}

bool serve_unless_rank_zero(const RunSettings& s, std::size_t threads, const std::vector<int>& machine) {
  const int rank = cluster::world_rank(), ranks = cluster::world_size();
  check_rollout_ranks(s.loop, ranks);
  if (rank == 0) return false;
  serve_rollouts(s, threads, rank, ranks, machine);
  return true;
}

}  // namespace codesign::run
