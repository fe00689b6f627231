// The backends behind make_factorization().
#pragma once
#include <vector>

#include "linalg/factorization.hpp"

namespace nd {
std::unique_ptr<Factorization> make_dense_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_banded_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_cholmod_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_umfpack_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_klu_factorization(const Csr &pattern);
// Reverse Cuthill-McKee: perm[new] = old.
std::vector<int64_t> reverse_cuthill_mckee(const Csr &pattern);
// half-bandwidth of the pattern in the ordering perm[new] = old
int64_t bandwidth(const Csr &pattern, const std::vector<int64_t> &perm);
}  // namespace nd
