/* Helpers of the tests that run under mpiexec (C and C++). Each is
 * collective over MPI_COMM_WORLD: every rank calls it at the same point. */
#ifndef ND_TESTUTIL_MPI_H
#define ND_TESTUTIL_MPI_H
#include <mpi.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

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
