// Version and error reporting.
#include <string>

#include "capi/guard.hpp"

namespace nd {
namespace {
// One message per thread: distinct handles may be used from distinct threads.
thread_local std::string last_error;
}  // namespace
void set_last_error(const std::string &message) { last_error = message; }
void clear_last_error() { last_error.clear(); }

std::string calls_that_set(unsigned aspects) {
  static const AspectName kCalls[] = {{kMaterial, "nd_problem_set_material"},
                                      {kNitsche, "nd_problem_set_nitsche"},
                                      {kScheme, "nd_problem_set_scheme"},
                                      {kTimestep, "nd_problem_set_timestep"}};
  return "(set with " + aspect_names(aspects, kCalls) + ")";
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

ND_EXPORT const char *nd_last_error(void) { return nd::last_error.c_str(); }

ND_EXPORT const char *nd_strerror(int code) {
#define ND_STRERROR_CASE_(name, value, text) \
  case name:                                 \
    return text;
  switch (code) { ND_STATUS_LIST(ND_STRERROR_CASE_) }
#undef ND_STRERROR_CASE_
  return "unknown status code";
}

}  // extern "C"
