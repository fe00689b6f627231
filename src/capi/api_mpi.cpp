// nd_problem_set_comm (include/nitschedyn_mpi.h): builds with PETSc only.
#include "capi/guard.hpp"
#include "capi/handles.hpp"
#include "nitschedyn_mpi.h"
#include "parallel/communicator_mpi.hpp"

extern "C" {

ND_EXPORT int nd_problem_set_comm(nd_problem p, MPI_Comm comm) {
  return nd::guarded("nd_problem_set_comm", [&] {
    nd::Problem &pr = nd::problem_of(p);
    pr.set_communicator(nd::communicator_from_c(comm));
    return ND_OK;
  });
}

}  // extern "C"
