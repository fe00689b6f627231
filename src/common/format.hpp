// Numbers in messages: %g style (6 significant digits, exponent when needed),
// so that a tolerance of 1e-12 or a time of 8e-06 reads as such in unit-scaled
// and SI runs alike, and independent of the caller's locale.
#pragma once
#include <charconv>
#include <string>

namespace nd {

inline std::string num(double x, int digits = 6) {
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, digits);
  return std::string(buf, r.ptr);
}

}  // namespace nd
