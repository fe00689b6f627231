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

// The header of a problem's collective call (Problem::collective): which
// call, this rank's how-many-th on the communicator, the digest of what the
// ranks must agree on, and the derived objects this rank has to build
// (`rebuild`, a bit set the ranks OR together).
struct CallHeader {
  int call = 0;
  uint64_t digest = 0;
  unsigned rebuild = 0;
};
// What the ranks sent: whether every rank made the same call (and the
// lowest and highest call numbers), with the same digest, and the OR of
// their `rebuild`s; `sequence` is the call's number on the communicator.
struct CallAgreement {
  bool same_call = true, same_digest = true;
  int call_min = 0, call_max = 0;
  unsigned rebuild = 0;
  uint64_t sequence = 0;
};
// Exchanges the header over c's ranks without waiting for ever: two
// nonblocking reductions (the header, then that every rank got it), each
// waited for at most collective_timeout() seconds. A rank that waits longer
// fails with ND_ERR_STATE and the communicator is lost: its reduction stays
// posted (a late rank's header meets it, and the late rank then times out
// in the second one), so every later exchange fails at once. Without a
// communicator (or on one rank) returns `mine`'s agreement, no message.
CallAgreement agree_on_call(const Communicator *c, const CallHeader &mine, const char *call_name);
// The seconds a rank waits for the others' headers: NITSCHEDYN_MPI_TIMEOUT from the
// environment when it is a positive number, else 300.
double collective_timeout();

}  // namespace nd
