// Rows of a matrix to compute: `count` of them listed in `list`, or all of
// them (list null): a rank's own rows (parallel/share.hpp), or a process's.
// Here, below both linalg and parallel, so neither includes the other.
#pragma once
#include <cstdint>

namespace nd {

struct RowSet {
  const int64_t *list = nullptr;
  int64_t count = -1;  // with list
  int64_t size(int64_t n) const { return list ? count : n; }
  int64_t operator[](int64_t r) const { return list ? list[r] : r; }
};

}  // namespace nd
