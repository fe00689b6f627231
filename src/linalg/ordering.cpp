// Reverse Cuthill-McKee: a breadth-first numbering from a vertex of least
// degree, reversed, which keeps the band of a symmetric pattern narrow.
#include "linalg/ordering.hpp"

#include <algorithm>
#include <cstdlib>

namespace nd {

std::vector<int64_t> reverse_cuthill_mckee(const Csr &A) {
  const int64_t n = A.n;
  auto degree = [&](int64_t i) { return A.ptr[i + 1] - A.ptr[i]; };
  std::vector<int64_t> order;
  order.reserve(static_cast<size_t>(n));
  std::vector<char> seen(static_cast<size_t>(n), 0);
  std::vector<int64_t> by_degree(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) by_degree[i] = i;
  std::stable_sort(by_degree.begin(), by_degree.end(),
                   [&](int64_t a, int64_t b) { return degree(a) < degree(b); });
  std::vector<int64_t> nbrs;
  for (int64_t start : by_degree) {  // one breadth-first sweep per component
    if (seen[start]) continue;
    seen[start] = 1;
    size_t head = order.size();
    order.push_back(start);
    while (head < order.size()) {
      const int64_t i = order[head++];
      nbrs.clear();
      for (int64_t k = A.ptr[i]; k < A.ptr[i + 1]; ++k)
        if (!seen[A.col[k]]) {
          seen[A.col[k]] = 1;
          nbrs.push_back(A.col[k]);
        }
      std::stable_sort(nbrs.begin(), nbrs.end(), [&](int64_t a, int64_t b) { return degree(a) < degree(b); });
      order.insert(order.end(), nbrs.begin(), nbrs.end());
    }
  }
  std::reverse(order.begin(), order.end());
  return order;
}

int64_t bandwidth(const Csr &A, const std::vector<int64_t> &perm) {
  std::vector<int64_t> inv(perm.size());
  for (size_t i = 0; i < perm.size(); ++i) inv[perm[i]] = static_cast<int64_t>(i);
  int64_t kd = 0;
  for (int64_t i = 0; i < A.n; ++i)
    for (int64_t k = A.ptr[i]; k < A.ptr[i + 1]; ++k) kd = std::max<int64_t>(kd, std::llabs(inv[i] - inv[A.col[k]]));
  return kd;
}

}  // namespace nd
