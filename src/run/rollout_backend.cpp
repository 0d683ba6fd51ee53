#include "run/rollout_backend.hpp"

#include <csignal>
#include <stdexcept>

#include "base/errors.hpp"
#include "cluster/mpi_env_pool.hpp"
#include "cluster/mpi_world.hpp"
#include "codesign/outer_loop.hpp"

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

}  // namespace

void check_rollout_ranks(const core::LoopConfig& lc, int ranks) {
  if (ranks > 1) slice_of(lc, 0, ranks);
}

std::unique_ptr<core::EnvPool> make_rollout_pool(std::shared_ptr<core::SimulatorPool> sims, const core::LoopConfig& lc,
                                                 std::size_t threads, int ranks) {
  const auto n = static_cast<std::size_t>(lc.codesign.designs_per_update);
  if (ranks <= 1) return std::make_unique<core::ThreadEnvPool>(sims, lc.task, n, threads, lc.ppo.privileged_critic);
  const cluster::EnvSlice mine = slice_of(lc, 0, ranks);
  auto local = std::make_unique<core::ThreadEnvPool>(sims, lc.task, mine.count, threads, lc.ppo.privileged_critic);
  return std::make_unique<cluster::MpiEnvPool>(std::move(local), n, ranks);
}

std::string rollout_sharing_note(core::EnvPool& pool) {
  const auto* mpi = dynamic_cast<const cluster::MpiEnvPool*>(&pool);
  if (!mpi) return {};
  return "rollouts on " + std::to_string(mpi->ranks()) + " MPI ranks: environments shared out by cost at " +
         std::to_string(mpi->reassigned_starts()) + " of " + std::to_string(mpi->starts()) +
         " iterations' starts (contiguous slices at the others: the first, and any where the costs gave that split); "
         "each rank ran its environments' whole rollout, meeting the others once, in " +
         std::to_string(mpi->rollouts()) + " of them (the others step by step, meeting at every decision: "
         "recurrent policies and observation statistics need that); designs' meshes: " +
         std::to_string(mpi->meshes_received()) + " made on the other ranks and sent to rank 0, " +
         std::to_string(mpi->meshes_sent()) + " sent to a rank that had not built the design (built there from "
         "the mesh instead of meshing)";
}

void serve_rollouts(const RunSettings& s, std::size_t threads, int rank, int ranks) {
  std::signal(SIGINT, SIG_IGN);
  std::signal(SIGTERM, SIG_IGN);
  const core::LoopConfig& lc = s.loop;
  const cluster::EnvSlice mine = slice_of(lc, rank, ranks);
  auto sims = std::make_shared<core::SimulatorPool>(s.spec, s.scene, s.solver);
  core::ThreadEnvPool local(sims, lc.task, mine.count, threads, lc.ppo.privileged_critic);
  rl::ActorCritic model = core::feed_forward_model(lc, local);  // rollout() sends its parameters
  cluster::serve_env_pool(local, lc.ppo.policy == rl::PolicyKind::Mlp ? &model : nullptr);
}

bool serve_unless_rank_zero(const RunSettings& s, std::size_t threads) {
  const int rank = cluster::world_rank(), ranks = cluster::world_size();
  check_rollout_ranks(s.loop, ranks);
  if (rank == 0) return false;
  serve_rollouts(s, threads, rank, ranks);
  return true;
}

}  // namespace codesign::run
