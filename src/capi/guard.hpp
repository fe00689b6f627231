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
#include "linalg/blas_threads.hpp"
#include "nitschedyn.h"
#include "problem/definition.hpp"

namespace nd {

// The thread's last error lives in a fixed buffer: the error path never
// allocates (a message that does not fit is truncated, ending in "..."), so a
// process out of memory still gets its code and a message.
void clear_last_error() noexcept;
void append_last_error(const char *text) noexcept;
// appends "(set with nd_problem_set_material, ...)" for the missing aspects
void append_calls_that_set(unsigned aspects) noexcept;

inline void set_last_error(const char *fn, const char *message) noexcept {
  clear_last_error();
  append_last_error(fn);
  append_last_error(": ");
  append_last_error(message);
}

// It also holds the BLAS to the library's thread limit for the call
// (linalg/blas_threads.hpp): every call may factorize or solve.
template <class Body>
int guarded(const char *fn, Body &&body) noexcept {
  clear_last_error();
  BlasThreadScope blas;
  try {
    return body();
  } catch (const Incomplete &e) {
    set_last_error(fn, e.what());
    append_last_error(" ");
    append_calls_that_set(e.missing());
    return e.code();
  } catch (const Error &e) {
    set_last_error(fn, e.what());
    return e.code();
  } catch (const std::bad_alloc &) {
    set_last_error(fn, "out of memory");
    return ND_ERR_NOMEM;
  } catch (const std::exception &e) {
    set_last_error(fn, "internal error: ");
    append_last_error(e.what());
    return ND_ERR_INTERNAL;
  } catch (...) {
    set_last_error(fn, "internal error");
    return ND_ERR_INTERNAL;
  }
}

// Argument checks shared by the API functions; each throws with the name.
// An enum argument is one of its X-macro list (nitschedyn.h).
#define ND_MEMBER_CASE_(name, value, text) case name:
#define ND_IS_MEMBER_(list, v) [](int x) { switch (x) { list(ND_MEMBER_CASE_) return true; default: return false; } }(v)
inline void need_member(bool member, int code, const char *arg, int value, const char *list) {
  if (!member) fail(code, std::string(arg) + " " + std::to_string(value) + " is not an " + list + " value");
}
inline void need(const void *ptr, const char *name) {
  if (!ptr) fail(ND_ERR_NULL, std::string(name) + " is NULL");
}
inline void need_finite(const double *x, int64_t n, const char *name) {
  for (int64_t i = 0; i < n; ++i)
    if (!std::isfinite(x[i]))
      fail(ND_ERR_NONFINITE, std::string(name) + "[" + std::to_string(i) + "] is not finite");
}

}  // namespace nd
