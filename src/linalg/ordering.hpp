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
// It first takes the memory METIS will need (metis_memory_bound) and gives
// it back: ND_ERR_NOMEM then, rather than METIS's message on standard error
// when an allocation of its own fails.
std::vector<int64_t> nested_dissection(const Csr &pattern);
// The bytes METIS_NodeND may allocate at most for a graph of `vertices`
// vertices and `entries` adjacency entries (both directions of each edge).
int64_t metis_memory_bound(int64_t vertices, int64_t entries);

}  // namespace nd
