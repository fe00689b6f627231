// Orderings of a symmetric pattern: for the banded backend and AUTO's
// choice, and the fill-reducing one of the CHOLMOD backend.
#pragma once
#include <vector>

#include "linalg/csr.hpp"

namespace nd {

// Reverse Cuthill-McKee: perm[new] = old.
std::vector<int64_t> reverse_cuthill_mckee(const Csr &pattern);
// half-bandwidth of the pattern in the ordering perm[new] = old
int64_t bandwidth(const Csr &pattern, const std::vector<int64_t> &perm);
// METIS's nested dissection of the pattern's graph, perm[new] = old; empty
// when METIS cannot take it (more than 2^31 - 1 entries, for its 32-bit
// indices; no off-diagonal entry) or refuses it, for the caller to use AMD.
// Throws ND_ERR_NOMEM when METIS runs out of memory. METIS's seed is fixed:
// the ordering depends on the pattern alone.
std::vector<int64_t> nested_dissection(const Csr &pattern);

}  // namespace nd
