/* The harness of the MPI tests (testutil_mpi.h): a check that fails on one
 * rank alone, before a collective call the other ranks are already in, ends
 * the job with its message instead of leaving them waiting. Run by
 * mpi_failed_check.sh, which expects a non-zero exit, this message, and no
 * timeout. */
#include "testutil_mpi.h"

static int g_rank, g_size;

START_TEST(a_check_failed_on_one_rank_ends_the_job) {
  ck_assert_msg(g_rank != g_size - 1, "a check failed on rank %d alone", g_rank);
  MPI_Barrier(MPI_COMM_WORLD); /* the other ranks wait here for the last one */
}
END_TEST

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  Suite *s = suite_create("mpi_failed_check");
  TCase *tc = tcase_create("harness");
  tcase_add_test(tc, a_check_failed_on_one_rank_ends_the_job);
  suite_add_tcase(s, tc);
  return nd_test_run_on_ranks(s);
}
