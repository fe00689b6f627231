/*
 * nitschedyn_mpi.h - the MPI part of the C interface of libnitschedyn, in
 * builds with PETSc (-DND_WITH_PETSC=ON) only. See nd_problem_set_comm(3).
 *
 * A problem steps on the ranks of a communicator when it is given one: every
 * rank holds the same mesh, problem and state (replicated), the linear solves
 * of the ND_SOLVER_PETSC_* solvers are distributed over the ranks (and with
 * them each rank holds its own rows of the operators only), and every
 * step either succeeds on every rank or fails on every rank with the same
 * status. Without a communicator a problem is this process's alone
 * (PETSC_COMM_SELF), as before. Each rank owns a part of the FE nodes (the
 * rows of the distributed matrix): nd_get_field_owned of nitschedyn.h reads
 * a field there (it takes no MPI type, so it is in every build).
 */
#ifndef NITSCHEDYN_MPI_H
#define NITSCHEDYN_MPI_H

#include <mpi.h>

#include "nitschedyn.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Collective over comm, before nd_problem_setup. The library keeps its own
   duplicate of comm (MPI_Comm_dup) and frees it in nd_problem_destroy, which
   is then collective too. */
ND_EXPORT int nd_problem_set_comm(nd_problem p, MPI_Comm comm);

#ifdef __cplusplus
}
#endif

#endif /* NITSCHEDYN_MPI_H */
