// The exception barrier of the C API: every nd_* function runs its body in
// guarded(), which clears the thread's last error on entry and turns any
// exception into a status code and a message. Nothing is printed.
// The core's messages say what is wrong and never name a C function;
// guarded() prefixes every one with "fn: ".
#pragma once
#include <cmath>
#include <new>
#include <string>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {

void set_last_error(const std::string &message);
void clear_last_error();

template <class Body>
int guarded(const char *fn, Body &&body) noexcept {
  clear_last_error();
  try {
    return body();
  } catch (const Error &e) {
    set_last_error(std::string(fn) + ": " + e.what());
    return e.code();
  } catch (const std::bad_alloc &) {
    set_last_error(std::string(fn) + ": out of memory");
    return ND_ERR_NOMEM;
  } catch (const std::exception &e) {
    set_last_error(std::string(fn) + ": internal error: " + e.what());
    return ND_ERR_INTERNAL;
  } catch (...) {
    set_last_error(std::string(fn) + ": internal error");
    return ND_ERR_INTERNAL;
  }
}

// Argument checks shared by the API functions; each throws with the name.
inline void need(const void *ptr, const char *name) {
  if (!ptr) fail(ND_ERR_NULL, std::string(name) + " is NULL");
}
inline void need_finite(const double *x, int64_t n, const char *name) {
  for (int64_t i = 0; i < n; ++i)
    if (!std::isfinite(x[i]))
      fail(ND_ERR_NONFINITE, std::string(name) + "[" + std::to_string(i) + "] is not finite");
}

}  // namespace nd
