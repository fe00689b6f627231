// Size arithmetic for counts that come from a caller or a file: a product
// that overflows, or an array that could not be addressed, is ND_ERR_SIZE
// (with a message saying which count), never undefined behaviour or a
// std::length_error. A size that is representable but cannot be allocated
// stays std::bad_alloc (ND_ERR_NOMEM).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {

// a * b for non-negative a, b; `what` names the product in the message
inline int64_t checked_mul(int64_t a, int64_t b, const char *what) {
  int64_t r;
  if (a < 0 || b < 0 || __builtin_mul_overflow(a, b, &r))
    fail(ND_ERR_SIZE, std::string(what) + " overflows (" + std::to_string(a) + " * " + std::to_string(b) + ")");
  return r;
}

inline int64_t checked_add(int64_t a, int64_t b, const char *what) {
  int64_t r;
  if (__builtin_add_overflow(a, b, &r))
    fail(ND_ERR_SIZE, std::string(what) + " overflows (" + std::to_string(a) + " + " + std::to_string(b) + ")");
  return r;
}

// n elements of T: the count as size_t, or ND_ERR_SIZE when no array of that
// many elements can exist (n < 0, or n * sizeof(T) beyond PTRDIFF_MAX)
template <class T>
size_t checked_count(int64_t n, const char *what) {
  if (n < 0 || static_cast<uint64_t>(n) > static_cast<uint64_t>(PTRDIFF_MAX) / sizeof(T))
    fail(ND_ERR_SIZE, std::string(what) + " (" + std::to_string(n) + ") is too large for an array");
  return static_cast<size_t>(n);
}

}  // namespace nd
