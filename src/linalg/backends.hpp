// The backends behind make_factorization().
#pragma once
#include "linalg/factorization.hpp"

namespace nd {
std::unique_ptr<Factorization> make_dense_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_banded_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_cholmod_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_umfpack_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_klu_factorization(const Csr &pattern);
}  // namespace nd
