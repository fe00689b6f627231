#include "parallel/agreement.hpp"

#include <cmath>
#include <cstdlib>
#include <new>
#include <string>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {

int status_of(const std::exception_ptr &e) {
  try {
    std::rethrow_exception(e);
  } catch (const Error &x) {
    return x.code();
  } catch (const std::bad_alloc &) {
    return ND_ERR_NOMEM;
  } catch (...) {
    return ND_ERR_INTERNAL;
  }
}

void agree_on_outcome(int worst, const std::exception_ptr &failure, const char *what, const char *consequence) {
  if (failure) std::rethrow_exception(failure);
  if (worst != ND_OK)
    fail(worst, std::string(what) + " failed on another rank (" + nd_strerror(worst) + "); " + consequence +
                    ": see that rank's error");
}

void on_every_rank(const std::function<int(int)> &worst_of, const std::function<void()> &local, const char *what,
                   const char *consequence) {
  std::exception_ptr failure;
  try {
    local();
  } catch (...) {
    failure = std::current_exception();
  }
  agree_on_outcome(worst_of(failure ? status_of(failure) : ND_OK), failure, what, consequence);
}

void on_every_rank(const Communicator *c, const std::function<void()> &local, const char *what,
                   const char *consequence) {
  on_every_rank([c](int mine) { return worst_status(c, mine); }, local, what, consequence);
}

double collective_timeout() {
  // far above the ranks' usual distance between two collective calls, and
  // still a bounded wait for a job that lost step
  constexpr double kDefault = 300;
  const char *text = std::getenv("NITSCHEDYN_MPI_TIMEOUT");
  if (!text) return kDefault;
  char *end = nullptr;
  const double t = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(t) && t > 0 ? t : kDefault;
}

}  // namespace nd
