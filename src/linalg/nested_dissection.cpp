// METIS's nested dissection (METIS_NodeND), called directly rather than
// through CHOLMOD's wrapper, which ignores METIS's return code: an
// out-of-memory inside METIS would leave CHOLMOD an undefined permutation.
//
// METIS orders the graph of the pattern's supervariables: consecutive rows
// with the same columns (a node's DOFs, which every element couples with
// the same neighbours) are one vertex, weighted by their count, and stay
// consecutive in the ordering. In 2D the graph then has half the vertices
// and a quarter of the edges, in 3D a third and a ninth.
#include <metis.h>

#include <algorithm>
#include <limits>

#include "common/error.hpp"
#include "linalg/ordering.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

// row i has the columns of row i - 1
bool same_columns(const Csr &A, int64_t i) {
  const int64_t m = A.ptr[i + 1] - A.ptr[i];
  return m == A.ptr[i] - A.ptr[i - 1] &&
         std::equal(A.col.begin() + A.ptr[i], A.col.begin() + A.ptr[i + 1], A.col.begin() + A.ptr[i - 1]);
}

}  // namespace

std::vector<int64_t> nested_dissection(const Csr &A) {
  const int64_t n = A.n;
  constexpr int64_t kMax = std::numeric_limits<idx_t>::max();
  if (n < 2 || static_cast<int64_t>(A.col.size()) > kMax) return {};
  // the supervariables: first[s] .. first[s + 1] - 1, and each row's
  std::vector<int64_t> first{0}, of(static_cast<size_t>(n));
  for (int64_t i = 1; i < n; ++i) {
    if (!same_columns(A, i)) first.push_back(i);
    of[i] = static_cast<int64_t>(first.size()) - 1;
  }
  const int64_t ns = static_cast<int64_t>(first.size());
  first.push_back(n);
  // their graph: a supervariable's first row's columns, by supervariable
  // (sorted columns: a supervariable's are consecutive), without itself
  std::vector<idx_t> xadj(static_cast<size_t>(ns) + 1), adjncy, weight(static_cast<size_t>(ns));
  adjncy.reserve(A.col.size() / static_cast<size_t>(std::max<int64_t>(1, (n / ns) * (n / ns))));
  for (int64_t s = 0; s < ns; ++s) {
    const int64_t i = first[s];
    int64_t last = -1;
    for (int64_t k = A.ptr[i]; k < A.ptr[i + 1]; ++k) {
      const int64_t t = of[A.col[k]];
      if (t != s && t != last) adjncy.push_back(static_cast<idx_t>(t));
      last = t;
    }
    xadj[s + 1] = static_cast<idx_t>(adjncy.size());
    weight[s] = static_cast<idx_t>(first[s + 1] - first[s]);
  }
  if (adjncy.empty()) return {};
  idx_t nv = static_cast<idx_t>(ns), options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);  // a fixed seed among them
  options[METIS_OPTION_NUMBERING] = 0;
  std::vector<idx_t> perm(static_cast<size_t>(ns)), iperm(perm.size());
  // (no weights when no row joined another: METIS's ordering of the whole graph, as before)
  const int status = METIS_NodeND(&nv, xadj.data(), adjncy.data(), ns < n ? weight.data() : nullptr, options,
                                  perm.data(), iperm.data());
  if (status == METIS_ERROR_MEMORY) fail(ND_ERR_NOMEM, "out of memory in METIS's nested dissection ordering");
  if (status != METIS_OK) return {};
  std::vector<int64_t> rows;
  rows.reserve(static_cast<size_t>(n));
  for (idx_t s : perm)
    for (int64_t i = first[s]; i < first[s + 1]; ++i) rows.push_back(i);
  return rows;
}

}  // namespace nd
