// Version and error reporting.

#include "capi/guard.hpp"

namespace nd {
namespace {
// One message per thread (distinct handles may be used from distinct
// threads), in static thread-local storage: setting it never allocates.
constexpr size_t kMessageCapacity = 1024;
thread_local char last_error[kMessageCapacity];
thread_local size_t last_error_length;
constexpr char kEllipsis[] = "...";
}  // namespace

void clear_last_error() noexcept {
  last_error[0] = '\0';
  last_error_length = 0;
}

void append_last_error(const char *text) noexcept {
  if (!text) return;
  constexpr size_t limit = kMessageCapacity - 1;  // room for the terminating NUL
  size_t n = last_error_length;
  if (n >= limit) return;                         // already full (and truncated)
  while (*text && n < limit) last_error[n++] = *text++;
  if (*text) {  // truncated: end with "..."
    n = limit;
    for (size_t k = 0; k < sizeof kEllipsis - 1; ++k) last_error[limit - (sizeof kEllipsis - 1) + k] = kEllipsis[k];
  }
  last_error[n] = '\0';
  last_error_length = n;
}

void append_calls_that_set(unsigned aspects) noexcept {
  static const AspectName kCalls[] = {{kMaterial, "nd_problem_set_material"},
                                      {kNitsche, "nd_problem_set_nitsche"},
                                      {kScheme, "nd_problem_set_scheme"},
                                      {kTimestep, "nd_problem_set_timestep"}};
  append_last_error("(set with ");
  bool first = true;
  for (const AspectName &c : kCalls)
    if (aspects & c.aspect) {
      if (!first) append_last_error(", ");
      append_last_error(c.name);
      first = false;
    }
  append_last_error(")");
}
}  // namespace nd

extern "C" {

ND_EXPORT int nd_version(int *major, int *minor, int *patch) {
  return nd::guarded("nd_version", [&] {
    nd::need(major, "major");
    nd::need(minor, "minor");
    nd::need(patch, "patch");
    *major = ND_VERSION_MAJOR;
    *minor = ND_VERSION_MINOR;
    *patch = ND_VERSION_PATCH;
    return ND_OK;
  });
}

ND_EXPORT const char *nd_last_error(void) { return nd::last_error; }

ND_EXPORT const char *nd_strerror(int code) {
#define ND_STRERROR_CASE_(name, value, text) \
  case name:                                 \
    return text;
  switch (code) { ND_STATUS_LIST(ND_STRERROR_CASE_) }
#undef ND_STRERROR_CASE_
  return "unknown status code";
}

ND_EXPORT int nd_set_blas_threads(int threads) {
  return nd::guarded("nd_set_blas_threads", [&] {
    if (threads < 0)
      nd::fail(ND_ERR_VALUE, "threads = " + std::to_string(threads) + " is negative (0: leave the BLAS alone)");
    nd::set_blas_thread_limit(threads);
    return ND_OK;
  });
}

ND_EXPORT int nd_get_blas_threads(int *threads) {
  return nd::guarded("nd_get_blas_threads", [&] {
    nd::need(threads, "threads");
    *threads = nd::blas_thread_limit();
    return ND_OK;
  });
}

}  // extern "C"
