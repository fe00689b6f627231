// The CSR getters' two calls (nd_problem_get_matrix, nd_problem_contact_tangent).
#pragma once
#include <algorithm>
#include <string>

#include "capi/guard.hpp"
#include "linalg/csr.hpp"

namespace nd {

// The two-call pattern of the CSR getters: sizes when every array is NULL,
// else all three, with *n and *nnz (the caller's capacities) the sizes.
// Returns whether the arrays are to be filled.
inline bool csr_request(const Csr &A, int64_t *n, int64_t *nnz, const int64_t *row_ptr, const int64_t *col_idx,
                 const double *values) {
  need(nnz, "nnz");
  const int64_t rows = A.n, entries = static_cast<int64_t>(A.val.size());
  if (!row_ptr && !col_idx && !values) {
    if (n) *n = rows;
    *nnz = entries;
    return false;
  }
  need(row_ptr, "row_ptr"), need(col_idx, "col_idx"), need(values, "values");
  if (n && *n != rows)
    fail(ND_ERR_SIZE, "*n is " + std::to_string(*n) + ", the matrix has " + std::to_string(rows) +
                          " rows (a first call with NULL arrays gives the sizes)");
  if (*nnz != entries)
    fail(ND_ERR_SIZE, "*nnz is " + std::to_string(*nnz) + ", the matrix has " + std::to_string(entries) +
                          " entries (a first call with NULL arrays gives the sizes)");
  return true;
}

inline void csr_copy(const Csr &A, int64_t *row_ptr, int64_t *col_idx, double *values) {
  std::copy(A.ptr.begin(), A.ptr.end(), row_ptr);
  std::copy(A.col.begin(), A.col.end(), col_idx);
  std::copy(A.val.begin(), A.val.end(), values);
}

}  // namespace nd
