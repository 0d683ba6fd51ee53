/* Helper of experiments/finalize_wakes.sh: how a rank waits in MPI_Finalize for a rank still at work.
 * Rank 0 sleeps SECONDS (default 5) before MPI_Finalize; every other rank calls it at once. With
 * BARRIER=1 in the environment the ranks first meet in an MPI_Ibarrier waited as codesign's ranks
 * wait (cluster/mpi_wait.cpp: polls for 100 us, then sleeps √(2 · 16 µs · waited), 20 µs to 20 ms),
 * so MPI_Finalize itself has no one to wait for. Each rank prints the wall time, CPU time and
 * context switches of its ending. Not part of codesign. */
#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const double seconds = argc > 1 ? atof(argv[1]) : 5.0;
  const int barrier = getenv("BARRIER") != NULL && atoi(getenv("BARRIER")) != 0;
  if (rank == 0) usleep((useconds_t)(seconds * 1e6));
  struct rusage u0, u1;
  getrusage(RUSAGE_SELF, &u0);
  const double t0 = now();
  if (barrier) {
    MPI_Request request;
    MPI_Ibarrier(MPI_COMM_WORLD, &request);
    int done = 0;
    while (!done && now() < t0 + 100e-6) MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    while (!done) {
      double p = sqrt(2.0 * 16e-6 * (now() - t0));
      p = p < 20e-6 ? 20e-6 : (p > 20e-3 ? 20e-3 : p);
      usleep((useconds_t)(p * 1e6));
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    }
  }
  MPI_Finalize();
  const double t1 = now();
  getrusage(RUSAGE_SELF, &u1);
  const double cpu = (double)(u1.ru_utime.tv_sec - u0.ru_utime.tv_sec + u1.ru_stime.tv_sec - u0.ru_stime.tv_sec) +
                     1e-6 * (double)(u1.ru_utime.tv_usec - u0.ru_utime.tv_usec + u1.ru_stime.tv_usec - u0.ru_stime.tv_usec);
  printf("rank %d, %s: ending %.2f s wall, %.3f s CPU, %ld voluntary context switches (%.0f a second)\n", rank,
         barrier ? "barrier first" : "MPI_Finalize alone", t1 - t0, cpu, u1.ru_nvcsw - u0.ru_nvcsw,
         (double)(u1.ru_nvcsw - u0.ru_nvcsw) / (t1 - t0));
  return 0;
}
