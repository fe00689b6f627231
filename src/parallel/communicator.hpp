// The ranks of an MPI job that step one problem together (replicated mesh
// and state, distributed linear solves). Only builds with
// PETSc know MPI (parallel/communicator_mpi.cpp); the others have the same
// functions with this process alone (parallel/communicator_serial.cpp), so
// that the rest of the library never tests for MPI.
//
// A problem without a communicator (null) is this process alone, as it
// always was. Every function taking one is collective over its ranks: every
// rank must call it, in the same order.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

namespace nd {

struct Communicator;  // the library's own duplicate of the caller's MPI_Comm
using CommunicatorPtr = std::shared_ptr<const Communicator>;

// From Fortran's integer handle (MPI_Comm_f2c), duplicated (MPI_Comm_dup:
// collective). Throws ND_ERR_KEY in a build without MPI, ND_ERR_VALUE for
// MPI_COMM_NULL or a handle MPI does not accept.
CommunicatorPtr communicator_from_fortran(int handle);
int communicator_size(const Communicator *c);  // 1 when null
int communicator_rank(const Communicator *c);  // 0 when null
// The worst (lowest) status over the ranks: every rank gets the same.
int worst_status(const Communicator *c, int status);
// Whether every rank passed the same digest.
bool same_on_all_ranks(const Communicator *c, uint64_t digest);
double max_over_ranks(const Communicator *c, double x);  // the largest of the ranks' x, on every rank
// x[k] <- the largest of the ranks' x[k], k < n, in one reduction
void max_over_ranks(const Communicator *c, double *x, int n);
constexpr int kEveryRank = -1;
// Point to point: to rank to[k] the values send[send_first[k] .. send_first[k+1]),
// from rank from[k] recv[recv_first[k] .. recv_first[k+1]). Every rank calls
// it with lists that match (what r sends to s, s receives from r); only the
// ranks named exchange messages, so it costs what the lists hold, not P.
void exchange(const Communicator *c, const std::vector<int> &to, const std::vector<int64_t> &send_first,
              const double *send, const std::vector<int> &from, const std::vector<int64_t> &recv_first,
              double *recv);
// MPI_Gatherv (MPI_Allgatherv for kEveryRank): rank r's `mine` (counts[r]
// values) lands at all[displs[r]] on `root`, or on every rank; `all` is not
// read elsewhere.
void gatherv(const Communicator *c, int root, const std::vector<double> &mine, std::vector<double> &all,
             const std::vector<int> &counts, const std::vector<int> &displs);

}  // namespace nd
