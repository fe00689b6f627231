/* The helpers of the C benchmarks that time steps through the public API
 * (bench/obstacle_step.c, bench/friction_step.c): a monotonic clock, a
 * scalar read, and a call that ends the program with the library's message. */
#ifndef ND_BENCH_STEP_TIMING_H
#define ND_BENCH_STEP_TIMING_H
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "nitschedyn.h"

static inline double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline double scalar(nd_problem p, int key) {
  double x = 0;
  nd_get_scalar(p, key, &x);
  return x;
}

/* (BENCH_NAME: the program's name, defined before this header) */
#define CHECK(call)                                                          \
  do {                                                                       \
    if ((call) != ND_OK) {                                                   \
      fprintf(stderr, "%s: %s: %s\n", BENCH_NAME, #call, nd_last_error()); \
      exit(1);                                                               \
    }                                                                        \
  } while (0)

#endif
