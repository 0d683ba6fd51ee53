#include "cluster/mpi_wait.hpp"

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include "cluster/idle_pause.hpp"

namespace codesign::cluster {

void check(int rc, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, text, &len);
  throw std::runtime_error(std::string("MPI rollout backend: ") + what + ": " + std::string(text, static_cast<std::size_t>(len)));
}

void wait_without_spinning(MPI_Request& request, MPI_Status* status, const char* what) {
  int done = 0;
  const double start = MPI_Wtime();
  do {
    check(MPI_Test(&request, &done, status), what);
  } while (!done && MPI_Wtime() < start + 100e-6);
  while (!done) {
    std::this_thread::sleep_for(std::chrono::duration<double>(idle_pause_seconds(MPI_Wtime() - start)));
    check(MPI_Test(&request, &done, status), what);
  }
}

}  // namespace codesign::cluster
