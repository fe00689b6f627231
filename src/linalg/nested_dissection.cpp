// METIS's nested dissection (METIS_NodeND), called directly rather than
// through CHOLMOD's wrapper, which ignores METIS's return code: an
// out-of-memory inside METIS would leave CHOLMOD an undefined permutation.
#include <metis.h>

#include <limits>

#include "common/error.hpp"
#include "linalg/ordering.hpp"
#include "nitschedyn.h"

namespace nd {

std::vector<int64_t> nested_dissection(const Csr &A) {
  const int64_t n = A.n;
  constexpr int64_t kMax = std::numeric_limits<idx_t>::max();
  if (n < 2 || static_cast<int64_t>(A.col.size()) > kMax) return {};
  // the graph: A's pattern without its diagonal (both halves, as METIS wants)
  std::vector<idx_t> xadj(static_cast<size_t>(n) + 1), adjncy;
  adjncy.reserve(A.col.size());
  for (int64_t i = 0; i < n; ++i) {
    for (int64_t k = A.ptr[i]; k < A.ptr[i + 1]; ++k)
      if (A.col[k] != i) adjncy.push_back(static_cast<idx_t>(A.col[k]));
    xadj[i + 1] = static_cast<idx_t>(adjncy.size());
  }
  if (adjncy.empty()) return {};
  idx_t nv = static_cast<idx_t>(n), options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);  // a fixed seed among them
  options[METIS_OPTION_NUMBERING] = 0;
  std::vector<idx_t> perm(static_cast<size_t>(n)), iperm(perm.size());
  const int status = METIS_NodeND(&nv, xadj.data(), adjncy.data(), nullptr, options, perm.data(), iperm.data());
  if (status == METIS_ERROR_MEMORY) fail(ND_ERR_NOMEM, "out of memory in METIS's nested dissection ordering");
  if (status != METIS_OK) return {};
  return std::vector<int64_t>(perm.begin(), perm.end());
}

}  // namespace nd
