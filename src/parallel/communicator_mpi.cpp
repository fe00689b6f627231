// The communicator functions of builds with MPI (see communicator.hpp).
#include "parallel/communicator_mpi.hpp"

#include <cstdint>
#include <string>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {

Communicator::~Communicator() {
  int finalized = 1;
  if (MPI_Finalized(&finalized) == MPI_SUCCESS && !finalized) MPI_Comm_free(&comm);
}

CommunicatorPtr communicator_from_c(MPI_Comm comm) {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (!initialized || finalized)
    fail(ND_ERR_STATE, "MPI is not running (a communicator is given between MPI_Init and MPI_Finalize)");
  if (comm == MPI_COMM_NULL) fail(ND_ERR_VALUE, "the communicator is MPI_COMM_NULL");
  int inter = 0;
  if (MPI_Comm_test_inter(comm, &inter) != MPI_SUCCESS || inter)
    fail(ND_ERR_VALUE, "the communicator is an intercommunicator; an intracommunicator is needed");
  // our own duplicate: the library's collectives never meet the caller's messages
  MPI_Comm own = MPI_COMM_NULL;
  if (MPI_Comm_dup(comm, &own) != MPI_SUCCESS) fail(ND_ERR_INTERNAL, "MPI_Comm_dup failed");
  return std::make_shared<const Communicator>(own);
}

CommunicatorPtr communicator_from_fortran(int handle) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  // MPI_Comm_f2c needs MPI; communicator_from_c says what is wrong
  return communicator_from_c(initialized ? MPI_Comm_f2c(static_cast<MPI_Fint>(handle)) : MPI_COMM_NULL);
}

MPI_Comm mpi_comm(const Communicator *c) { return c ? c->comm : MPI_COMM_SELF; }

int communicator_size(const Communicator *c) {
  int size = 1;
  if (c) MPI_Comm_size(c->comm, &size);
  return size;
}

int communicator_rank(const Communicator *c) {
  int rank = 0;
  if (c) MPI_Comm_rank(c->comm, &rank);
  return rank;
}

namespace {
// op over the ranks' x, on every rank (x alone without a communicator)
template <class T>
T reduce(const Communicator *c, T x, MPI_Datatype type, MPI_Op op, const char *what) {
  if (!c) return x;
  T all = x;
  if (MPI_Allreduce(&x, &all, 1, type, op, c->comm) != MPI_SUCCESS)
    fail(ND_ERR_INTERNAL, std::string("MPI_Allreduce of ") + what + " failed");
  return all;
}
}  // namespace

int worst_status(const Communicator *c, int status) {
  return reduce(c, status, MPI_INT, MPI_MIN, "the step status");
}

double max_over_ranks(const Communicator *c, double x) { return reduce(c, x, MPI_DOUBLE, MPI_MAX, "a maximum"); }

bool same_on_all_ranks(const Communicator *c, uint64_t digest) {
  if (!c) return true;
  // min of d and of ~d (= ~max d) in one reduction: equal iff min == max
  uint64_t mine[2] = {digest, ~digest}, all[2] = {0, 0};
  if (MPI_Allreduce(mine, all, 2, MPI_UINT64_T, MPI_MIN, c->comm) != MPI_SUCCESS)
    fail(ND_ERR_INTERNAL, "MPI_Allreduce of the inputs' digest failed");
  return all[0] == ~all[1];
}

void gatherv(const Communicator *c, int root, const std::vector<double> &mine, std::vector<double> &all,
             const std::vector<int> &counts, const std::vector<int> &displs) {
  if (!c) {
    all = mine;
    return;
  }
  const int n = static_cast<int>(mine.size());
  const int status =
      root == kEveryRank
          ? MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, c->comm)
          : MPI_Gatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, root,
                        c->comm);
  if (status != MPI_SUCCESS) fail(ND_ERR_INTERNAL, "MPI_Gatherv of the ranks' values failed");
}

}  // namespace nd
