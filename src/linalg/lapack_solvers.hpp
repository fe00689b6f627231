#pragma once
#include <vector>

#include "linalg/factorization.hpp"

namespace nd {
std::unique_ptr<Factorization> make_dense_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_banded_factorization(const Csr &pattern);
// Reverse Cuthill-McKee: perm[new] = old.
std::vector<int64_t> reverse_cuthill_mckee(const Csr &pattern);
}  // namespace nd
