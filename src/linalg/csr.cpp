#include "linalg/csr.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {

// Two sums per row: the latency of the dependent adds, not memory, bounded
// the single sum on these patterns (10-40 entries a row).
void Csr::multiply(const double *x, double *y, RowSet rows) const {
  for_rows(rows, [&](int64_t, int64_t i, int64_t k, int64_t e) __attribute__((always_inline)) {
    double s = 0, s1 = 0;
    for (; k + 1 < e; k += 2) {
      s += val[k] * x[col[k]];
      s1 += val[k + 1] * x[col[k + 1]];
    }
    if (k < e) s += val[k] * x[col[k]];
    y[i] = s + s1;
  });
}

void require_same_pattern(const Csr &A, const Csr &B) {
  if (B.n != A.n || B.val.size() != A.val.size() || B.part != A.part || B.held.size() != A.held.size())
    fail(ND_ERR_INTERNAL, "two operators that should share a pattern do not");
}

int64_t Csr::slot(int64_t i) const {
  if (!part) return i;
  auto it = std::lower_bound(held.begin(), held.end(), i);
  return it != held.end() && *it == i ? it - held.begin() : -1;
}

void Csr::require_places(RowSet rows) const {
  const int64_t m = rows.size(n);
  if (m != stored() || (m > 0 && (rows[0] != held.front() || rows[m - 1] != held.back())))
    fail(ND_ERR_INTERNAL, "a pass over other rows than the " + std::to_string(stored()) + " an operator's part holds");
}

int64_t Csr::find(int64_t i, int64_t j) const {
  const int64_t at = slot(i);
  if (at < 0) return -1;
  auto b = col.begin() + ptr[at], e = col.begin() + ptr[at + 1];
  auto it = std::lower_bound(b, e, j);
  return it != e && *it == j ? it - col.begin() : -1;
}

namespace {
// (cold, out of add_outer's loop)
[[noreturn]] __attribute__((noinline, cold)) void outside_pattern(int64_t i, int64_t j) {
  fail(ND_ERR_INTERNAL, "a coupling outside the operator pattern: entry (" + std::to_string(i) + ", " +
                            std::to_string(j) + ") is not stored (Csr::add_outer)");
}
}  // namespace

void Csr::add_outer(const std::vector<int64_t> &idx, const double *u, const double *v, double f) {
  for (size_t i = 0; i < idx.size(); ++i) {
    const int64_t at = slot(idx[i]);  // (once per row: a part searches its rows)
    if (at < 0 || ptr[at] == ptr[at + 1]) continue;  // a row this part does not hold
    const auto b = col.begin() + ptr[at], e = col.begin() + ptr[at + 1];
    for (size_t j = 0; j < idx.size(); ++j) {
      const auto at_j = std::lower_bound(b, e, idx[j]);
      // (a pair outside the pattern would land in a neighbour's entry)
      if (at_j == e || *at_j != idx[j]) outside_pattern(idx[i], idx[j]);
      val[at_j - col.begin()] += f * u[i] * v[j];
    }
  }
}

Csr csr_from_rows(std::vector<std::vector<int64_t>> rows) {
  Csr A;
  A.n = static_cast<int64_t>(rows.size());
  std::vector<int64_t> &ptr = A.ptr.mut(), &col = A.col.mut();
  ptr.assign(rows.size() + 1, 0);
  for (size_t i = 0; i < rows.size(); ++i) {
    auto &r = rows[i];
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    ptr[i + 1] = ptr[i] + static_cast<int64_t>(r.size());
  }
  col.reserve(static_cast<size_t>(ptr.back()));
  for (auto &r : rows) col.insert(col.end(), r.begin(), r.end());
  A.val.assign(A.col.size(), 0.0);
  return A;
}

void csr_combine(double a, const Csr &A, double b, const Csr &B, Csr &C) {
  C.n = A.n;
  C.part = A.part;
  C.held = A.held;
  C.ptr = A.ptr;  // shared, not copied
  C.col = A.col;
  C.val.resize(A.val.size());
  for (size_t k = 0; k < A.val.size(); ++k) C.val[k] = a * A.val[k] + b * B.val[k];
}

double dot(int64_t n, const double *x, const double *y) {
  // in four sums (i mod 4), not one chain of dependent adds, each waiting on
  // the one before: that latency, not memory, bounds a long dot product
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  int64_t i = 0;
  for (; i + 3 < n; i += 4) {
    s0 += x[i] * y[i];
    s1 += x[i + 1] * y[i + 1];
    s2 += x[i + 2] * y[i + 2];
    s3 += x[i + 3] * y[i + 3];
  }
  if (i < n) s0 += x[i] * y[i];
  if (i + 1 < n) s1 += x[i + 1] * y[i + 1];
  if (i + 2 < n) s2 += x[i + 2] * y[i + 2];
  return (s0 + s1) + (s2 + s3);
}

double norm2(int64_t n, const double *x) { return std::sqrt(dot(n, x, x)); }

}  // namespace nd
