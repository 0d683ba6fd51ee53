#pragma once
// The MPI world of a process started by an MPI launcher (`mpirun -np N codesign run ...`), or
// none. Without a launcher the binary never calls MPI and runs as a single process.
//
// MPI's own state is process-wide; this file keeps none of its own: world_rank()/world_size()
// ask the library (0 and 1 when MPI was not initialised).
#include <string>
#include <vector>

namespace codesign::cluster {

// True when a launcher started this process: Open MPI's mpirun sets OMPI_COMM_WORLD_SIZE, Slurm's
// srun with PMIx sets PMIX_RANK, MPICH-style launchers set PMI_SIZE.
bool launched_by_mpi();

// MPI_Init_thread (MPI_THREAD_FUNNELED: only the main thread calls MPI; the rollout threads do
// not) in the constructor, MPI_Finalize in the destructor. One per process, in main().
class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

int world_rank();   // 0 without MPI
int world_size();   // 1 without MPI

// The world ranks of the job's ranks on this process's machine (they share its memory and cores),
// this one included, in increasing order; {0} without MPI. Collective: every rank of the job must
// call it.
std::vector<int> ranks_on_this_machine();

// Ends every rank of the job at once (MPI_Abort) with `status`; without MPI, returns.
void abort_world(int status);

}  // namespace codesign::cluster
