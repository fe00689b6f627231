// FNV-1a, 64 bits: the checkpoint's checksum and the ranks' agreement digest.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace nd {

struct Hash {
  uint64_t h = 1469598103934665603ull;
  void bytes(const void *p, size_t n) {
    const unsigned char *c = static_cast<const unsigned char *>(p);
    for (size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 1099511628211ull;
  }
  template <class T>
  void value(const T &x) { bytes(&x, sizeof x); }
  template <class T>
  void vec(const std::vector<T> &v) {
    value(static_cast<uint64_t>(v.size()));
    bytes(v.data(), v.size() * sizeof(T));
  }
};

}  // namespace nd
