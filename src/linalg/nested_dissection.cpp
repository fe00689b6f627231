// METIS's nested dissection (METIS_NodeND), called directly rather than
// through CHOLMOD's wrapper, which ignores METIS's return code: an
// out-of-memory inside METIS would leave CHOLMOD an undefined permutation.
//
// METIS orders the graph of the pattern's supervariables: consecutive rows
// with the same columns (a node's DOFs, which every element couples with
// the same neighbours) are one vertex, weighted by their count, and stay
// consecutive in the ordering. In 2D the graph then has half the vertices
// and a quarter of the edges, in 3D a third and a ninth.
//
// METIS prints to standard error when one of its allocations fails (GKlib's
// gk_malloc: the memory in use and "***Memory allocation failed for ...")
// before it returns METIS_ERROR_MEMORY, and a library prints nothing. So
// the memory METIS will need is taken once, and given back, just before it
// runs: where that fails (an address-space limit, ulimit -v) the ordering
// fails with ND_ERR_NOMEM before METIS starts.
#include <metis.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <string>

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

// Takes `bytes` and frees them: ND_ERR_NOMEM when they are not there.
void require_room(int64_t bytes, const char *what) {
  // (through a volatile pointer: a malloc freed unused may be left out by the compiler)
  static void *(*volatile take)(size_t) = std::malloc;
  void *block = take(static_cast<size_t>(bytes));
  if (!block)
    fail(ND_ERR_NOMEM, "out of memory: the " + std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB of " + what +
                           " are not available");
  std::free(block);
}

}  // namespace

int64_t metis_memory_bound(int64_t vertices, int64_t entries) {
  // measured (tests/unit_metis_memory.cpp): about 100 KiB, then 3.7 to 4.6
  // index values per vertex and adjacency entry on grids of 10^2 to 2 10^5
  // vertices; twice that, for the graphs of other meshes
  return (int64_t{256} << 10) + 8 * (vertices + entries) * static_cast<int64_t>(sizeof(idx_t));
}

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
  require_room(metis_memory_bound(ns, static_cast<int64_t>(adjncy.size())), "METIS's nested dissection ordering");
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
