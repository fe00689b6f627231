/* The number of steps of a run to time T with the step tau, round(T / tau),
 * checked: the conversion of a double an int64_t does not hold is undefined
 * behaviour (T / tau of 2^63 or more, NaN, infinite). Shared by the example
 * drivers, the stability suite and nitschedyn(1) (tools/cli/scene.cpp). */
#ifndef ND_STEP_COUNT_H
#define ND_STEP_COUNT_H
#include <stdint.h>

/* round(T / tau), or -1 when it is not a number of steps in [0, 2^63 - 1] */
static inline int64_t nd_step_count(double T, double tau) {
  const double steps = T / tau + 0.5; /* rounded below */
  /* 2^63: an int64_t holds every double below it (NaN fails the test too) */
  if (!(steps >= 0 && steps < 9223372036854775808.0)) return -1;
  return (int64_t)steps;
}

#endif
