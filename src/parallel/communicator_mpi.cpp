// The communicator functions of builds with MPI (see communicator.hpp).
#include "parallel/communicator_mpi.hpp"

#include <chrono>
#include <climits>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "common/error.hpp"
#include "common/format.hpp"
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
  // an MPI error on it (a collective the ranks did not match) is a status, not the end of the job
  if (MPI_Comm_set_errhandler(own, MPI_ERRORS_RETURN) != MPI_SUCCESS) {
    MPI_Comm_free(&own);
    fail(ND_ERR_INTERNAL, "MPI_Comm_set_errhandler failed");
  }
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

void max_over_ranks(const Communicator *c, double *x, int n) {
  if (!c || n == 0) return;
  if (MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_MAX, c->comm) != MPI_SUCCESS)
    fail(ND_ERR_INTERNAL, "MPI_Allreduce of the ranks' maxima failed");
}

void exchange(const Communicator *c, const std::vector<int> &to, const std::vector<int64_t> &send_first,
              const double *send, const std::vector<int> &from, const std::vector<int64_t> &recv_first,
              double *recv) {
  if (to.empty() && from.empty()) return;
  if (!c) fail(ND_ERR_INTERNAL, "an exchange between ranks without a communicator");
  std::vector<MPI_Request> requests;
  requests.reserve(to.size() + from.size());
  int status = MPI_SUCCESS;
  auto count = [&](const std::vector<int64_t> &first, size_t k) {
    const int64_t m = first[k + 1] - first[k];
    if (m > INT_MAX) fail(ND_ERR_SIZE, "a message between ranks (" + std::to_string(m) + " values) exceeds MPI's int count");
    return static_cast<int>(m);
  };
  constexpr int kTag = 15;  // our duplicate communicator: no caller's message shares it
  for (size_t k = 0; k < from.size() && status == MPI_SUCCESS; ++k) {
    requests.push_back(MPI_REQUEST_NULL);
    status = MPI_Irecv(recv + recv_first[k], count(recv_first, k), MPI_DOUBLE, from[k], kTag, c->comm, &requests.back());
  }
  for (size_t k = 0; k < to.size() && status == MPI_SUCCESS; ++k) {
    requests.push_back(MPI_REQUEST_NULL);
    // (MPI 3's Isend takes a const buffer)
    status = MPI_Isend(send + send_first[k], count(send_first, k), MPI_DOUBLE, to[k], kTag, c->comm, &requests.back());
  }
  const int waited = MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  if (status != MPI_SUCCESS || waited != MPI_SUCCESS) fail(ND_ERR_INTERNAL, "an exchange of values between ranks failed");
}

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

namespace {
// The buffers of agree_on_call's two reductions: MPI holds them while a
// request is posted, so a timed-out exchange leaves them to MPI (leaked).
struct CallBuffers {
  uint64_t header[6], header_all[6];  // call, seq, digest and their complements (MPI_MIN: equal iff min == ~max)
  uint64_t rebuild = 0, rebuild_all = 0;  // MPI_BOR
  MPI_Request request = MPI_REQUEST_NULL;
};

// Waits for `r` until `deadline`: false when it passed first (r stays posted).
bool wait_until(MPI_Request &r, std::chrono::steady_clock::time_point deadline, bool &error) {
  for (int polls = 0;; ++polls) {
    int done = 0;
    if (MPI_Test(&r, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS) return error = true, false;
    if (done) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    // (the ranks usually meet within microseconds; a rank left waiting
    // should not take a core from the ranks it waits for)
    if (polls > 1000) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}
}  // namespace

CallAgreement agree_on_call(const Communicator *c, const CallHeader &mine, const char *call_name) {
  CallAgreement a;
  a.call_min = a.call_max = mine.call;
  a.rebuild = mine.rebuild;
  if (communicator_size(c) <= 1) return a;
  const int rank = communicator_rank(c);
  if (!c->lost_at.empty())
    fail(ND_ERR_STATE, "rank " + std::to_string(rank) + ": this problem's ranks lost step with each other earlier (" +
                           c->lost_at + "), so it makes no collective call any more: destroy it (nd_problem_destroy "
                           "on every rank) and restart from a checkpoint");
  a.sequence = ++c->calls;
  auto buffers = std::make_unique<CallBuffers>();
  CallBuffers &b = *buffers;
  const uint64_t sent[3] = {static_cast<uint64_t>(mine.call), a.sequence, mine.digest};
  for (int k = 0; k < 3; ++k) b.header[2 * k] = sent[k], b.header[2 * k + 1] = ~sent[k];
  b.rebuild = mine.rebuild;
  const double timeout = collective_timeout();
  using Clock = std::chrono::steady_clock;
  const auto wait = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout));
  bool error = false;
  auto phase = [&](const char *what) {
    if (wait_until(b.request, Clock::now() + wait, error)) return;
    c->lost_at = "rank " + std::to_string(rank) +
                 (error ? std::string(": MPI failed in the ") + what
                        : std::string(" waited ") + num(timeout) + " s for the other ranks' " + what) +
                 " in " + call_name + ", the problem's collective call #" + std::to_string(a.sequence);
    buffers.release();  // MPI may still write into them (a late rank): theirs now
    fail(ND_ERR_STATE, c->lost_at + ": a rank made another collective call, or one more or one fewer (see the "
                       "other ranks' errors; NITSCHEDYN_MPI_TIMEOUT sets the wait); the problem makes no collective "
                       "call any more: destroy it on every rank and restart from a checkpoint");
  };
  if (MPI_Iallreduce(b.header, b.header_all, 6, MPI_UINT64_T, MPI_MIN, c->comm, &b.request) != MPI_SUCCESS)
    fail(ND_ERR_INTERNAL, "MPI_Iallreduce of the collective call's header failed");
  phase("headers");
  // every rank got every header: then each knows what the others know
  if (MPI_Iallreduce(&b.rebuild, &b.rebuild_all, 1, MPI_UINT64_T, MPI_BOR, c->comm, &b.request) != MPI_SUCCESS)
    fail(ND_ERR_INTERNAL, "MPI_Iallreduce of the collective call's confirmation failed");
  phase("confirmation that every rank has the headers");
  auto same = [&b](int k) { return b.header_all[2 * k] == ~b.header_all[2 * k + 1]; };
  a.same_call = same(0) && same(1);
  a.same_digest = same(2);
  a.call_min = static_cast<int>(b.header_all[0]);
  a.call_max = static_cast<int>(~b.header_all[1]);
  a.rebuild = static_cast<unsigned>(b.rebuild_all);
  return a;
}

}  // namespace nd
