// Orderings of a symmetric pattern: for the banded backend and AUTO's choice.
#pragma once
#include <vector>

#include "linalg/csr.hpp"

namespace nd {

// Reverse Cuthill-McKee: perm[new] = old.
std::vector<int64_t> reverse_cuthill_mckee(const Csr &pattern);
// half-bandwidth of the pattern in the ordering perm[new] = old
int64_t bandwidth(const Csr &pattern, const std::vector<int64_t> &perm);

}  // namespace nd
