#include "cluster/mpi_world.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "cluster/mpi_wait.hpp"

namespace codesign::cluster {

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
    if (std::getenv(v) != nullptr) return true;
  return false;
}

MpiSession::MpiSession(int* argc, char*** argv) {
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    throw std::runtime_error("MPI_Init_thread failed");
  // Errors come back as return codes (checked where each call is made), not as an abort inside MPI.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
}

MpiSession::~MpiSession() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  // The ranks meet before MPI_Finalize, waiting as the rollouts wait (mpi_wait.hpp). Open MPI 4.1's
  // MPI_Finalize waits for the job's other ranks by sleeping 100 µs between polls (about 6 500
  // wakes a second: experiments/finalize_wakes.sh), and the other ranks get there while rank 0
  // still renders the frames and figures; each wake takes a moment of the cores rank 0 works on
  // (idle_pause.hpp). A failed barrier only means MPI_Finalize does the waiting.
  MPI_Request request;
  if (MPI_Ibarrier(MPI_COMM_WORLD, &request) == MPI_SUCCESS) {
    try {
      wait_without_spinning(request, MPI_STATUS_IGNORE, "the ranks' last meeting");
    } catch (const std::exception&) {
    }
  }
  MPI_Finalize();
}

namespace {
bool mpi_active() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  return initialized && !finalized;
}
}  // namespace

int world_rank() {
  if (!mpi_active()) return 0;
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int world_size() {
  if (!mpi_active()) return 1;
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

std::vector<int> ranks_on_this_machine() {
  if (!mpi_active()) return {0};
  MPI_Comm here;
  if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &here) != MPI_SUCCESS)
    throw std::runtime_error("MPI_Comm_split_type failed");
  int n = 1;
  MPI_Comm_size(here, &n);
  const int me = world_rank();
  std::vector<int> ranks(static_cast<std::size_t>(n), 0);
  const int rc = MPI_Allgather(&me, 1, MPI_INT, ranks.data(), 1, MPI_INT, here);
  MPI_Comm_free(&here);
  if (rc != MPI_SUCCESS) throw std::runtime_error("MPI_Allgather of the machine's ranks failed");
  std::sort(ranks.begin(), ranks.end());
  return ranks;
}

void abort_world(int status) {
  if (mpi_active()) MPI_Abort(MPI_COMM_WORLD, status);
}

}  // namespace codesign::cluster
