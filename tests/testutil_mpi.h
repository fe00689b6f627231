/* Helpers of the tests that run under mpiexec (C and C++). Each is
 * collective over MPI_COMM_WORLD: every rank calls it at the same point. */
#ifndef ND_TESTUTIL_MPI_H
#define ND_TESTUTIL_MPI_H
#include <mpi.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

/* A failed check ends the job. Under mpiexec Check runs without fork: a
 * failed check leaves its test on that rank alone, and the other ranks
 * would wait for it in their next collective call, a hang until ctest's
 * timeout with no message. So every Check assertion of these tests (they
 * all end in _ck_assert_failed) prints its message with the rank and calls
 * MPI_Abort, and mpiexec exits non-zero on every rank. */
static inline void nd_test_abort_job(const char *file, int line, const char *expr, const char *msg, ...)
    __attribute__((noreturn, format(printf, 4, 5)));
static inline void nd_test_abort_job(const char *file, int line, const char *expr, const char *msg, ...) {
  int rank = -1, up = 0;
  MPI_Initialized(&up);
  if (up) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  /* one line, one write: the ranks' output is interleaved by lines */
  char text[1024];
  int used = snprintf(text, sizeof text, "%s:%d: rank %d: ", file, line, rank);
  if (used < 0 || used >= (int)sizeof text) used = 0;
  if (msg) {
    va_list ap;
    va_start(ap, msg);
    vsnprintf(text + used, sizeof text - (size_t)used, msg, ap);
    va_end(ap);
  } else {
    snprintf(text + used, sizeof text - (size_t)used, "%s", expr);
  }
  fprintf(stderr, "%s\n", text);
  fflush(stderr);
  if (up) MPI_Abort(MPI_COMM_WORLD, 1);
  abort();
}
#define _ck_assert_failed nd_test_abort_job

/* a verdict of every rank (a check that fails on some ranks only would
 * leave the others waiting in the next collective call) */
static inline int nd_test_on_all_ranks(int ok) {
  int all = 0;
  MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
  return all;
}

/* every rank holds the same bytes as rank 0 */
static inline int nd_test_same_on_all_ranks(const void *data, int nbytes) {
  unsigned char *root = (unsigned char *)malloc((size_t)nbytes);
  memcpy(root, data, (size_t)nbytes);
  MPI_Bcast(root, nbytes, MPI_BYTE, 0, MPI_COMM_WORLD);
  int same = memcmp(root, data, (size_t)nbytes) == 0, all = 0;
  MPI_Allreduce(&same, &all, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
  free(root);
  return all;
}

/* Runs the suite on every rank, then finalizes MPI; a failure on any rank
 * fails the run on every rank. */
static inline int nd_test_run_on_ranks(Suite *s) {
  int status = nd_test_run(s), worst = 0;
  MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return worst;
}

#endif
