// The communicator functions of a build without MPI (see communicator.hpp).
#include "common/error.hpp"
#include "nitschedyn.h"
#include "parallel/communicator.hpp"

namespace nd {

CommunicatorPtr communicator_from_fortran(int) {
  fail(ND_ERR_KEY, "an MPI communicator needs MPI, and this build of libnitschedyn has none "
                   "(configure with -DND_WITH_PETSC=ON)");
}
int communicator_size(const Communicator *) { return 1; }
int communicator_rank(const Communicator *) { return 0; }
int worst_status(const Communicator *, int status) { return status; }
bool same_on_all_ranks(const Communicator *, uint64_t) { return true; }
double max_over_ranks(const Communicator *, double x) { return x; }
void max_over_ranks(const Communicator *, double *, int) {}
void exchange(const Communicator *, const std::vector<int> &to, const std::vector<int64_t> &, const double *,
              const std::vector<int> &from, const std::vector<int64_t> &, double *) {
  if (!to.empty() || !from.empty()) fail(ND_ERR_INTERNAL, "an exchange between ranks in a build without MPI");
}
void gatherv(const Communicator *, int, const std::vector<double> &mine, std::vector<double> &all,
             const std::vector<int> &, const std::vector<int> &) {
  all = mine;
}

CallAgreement agree_on_call(const Communicator *, const CallHeader &mine, const char *) {
  CallAgreement a;
  a.call_min = a.call_max = mine.call;
  a.rebuild = mine.rebuild;
  return a;
}

}  // namespace nd
