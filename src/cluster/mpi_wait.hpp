#pragma once
// MPI calls shared by this folder's sources. It includes mpi.h, so only sources of src/cluster
// (which link Open MPI privately) include it; the folder's other headers stay free of MPI.
#include <mpi.h>

namespace codesign::cluster {

// std::runtime_error naming `what` and MPI's text unless rc is MPI_SUCCESS.
void check(int rc, const char* what);

// Waits for a posted request without holding a core. Open MPI's blocking calls poll the shared
// memory transport in a loop, so a rank waiting through rank 0's PPO update or final evaluation
// would take a core from it when the ranks share a machine. This polls for up to 100 µs (an answer
// to a step usually comes within that: docs/journal/cluster.md, "Measured: one and two ranks on
// one machine"), then sleeps between polls for a pause that grows with the root of the time
// waited (idle_pause.hpp).
void wait_without_spinning(MPI_Request& request, MPI_Status* status, const char* what);

}  // namespace codesign::cluster
