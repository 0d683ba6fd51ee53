/* Helper of experiments/evaluation_pairs.sh: a process that does what a waiting MPI rank does between
 * its polls, and nothing else: sleeps US microseconds, wakes, sleeps again, for SECONDS seconds
 * (or until killed), then prints how many times it woke. Beside a run of codesign on the same
 * cores it shows what the wake-ups alone cost the run. Not part of codesign.
 *   idle_waker US SECONDS */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: idle_waker US SECONDS\n");
    return 2;
  }
  const long us = atol(argv[1]);
  const double seconds = atof(argv[2]);
  struct timespec t0, t, pause = {us / 1000000, (us % 1000000) * 1000};
  clock_gettime(CLOCK_MONOTONIC, &t0);
  long wakes = 0;
  do {
    nanosleep(&pause, NULL);
    ++wakes;
    clock_gettime(CLOCK_MONOTONIC, &t);
  } while ((double)(t.tv_sec - t0.tv_sec) + 1e-9 * (double)(t.tv_nsec - t0.tv_nsec) < seconds);
  printf("%ld wakes in %.3f s\n", wakes, seconds);
  return 0;
}
