// The backends behind make_factorization().
#pragma once
#include <string>

#include "linalg/factorization.hpp"

namespace nd {

std::unique_ptr<Factorization> make_dense_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_banded_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_cholmod_factorization(const Csr &pattern);
// the same with the ordering of ordered_like where that is a CHOLMOD factor
// of as many unknowns (its METIS run not made again), else its own
std::unique_ptr<Factorization> make_cholmod_factorization_like(const Csr &pattern, const Factorization *ordered_like);
// nnz(L) of the CHOLMOD backend's analysis of the pattern (its ordering), for reports
double cholmod_factor_nonzeros(const Csr &pattern);
// does that analysis choose a supernodal factor? (for tests of its paths)
bool cholmod_is_supernodal(const Csr &pattern);
// the most columns of one of its supernodes (0: a simplicial factor)
int64_t cholmod_widest_supernode(const Csr &pattern);
// Diagonal blocks of a supernodal factor up to this many columns are solved
// by the library's own loops, wider ones by the BLAS (linalg/cholmod.cpp)
constexpr int kCholmodOwnTriangle = 32;
std::unique_ptr<Factorization> make_umfpack_factorization(const Csr &pattern);
std::unique_ptr<Factorization> make_klu_factorization(const Csr &pattern);
#ifdef ND_HAVE_PETSC
// linalg/petsc.cpp (ND_WITH_PETSC)
std::unique_ptr<Factorization> make_petsc_mumps_factorization(const Csr &pattern, const DofGeometry *geometry);
std::unique_ptr<Factorization> make_petsc_gamg_factorization(const Csr &pattern, const DofGeometry *geometry);
#endif

// Shared by the backends that factor with SPD requested; each sets the
// backend's verdict `def` (NotPositiveDefinite before it throws).
[[noreturn]] void fail_not_positive_definite(Definiteness &def, const std::string &why);
// Sylvester's law of inertia: the pivots d[0..n) of a symmetric elimination
// (D of LDL^T; U's diagonal of an LU with symmetric pivoting and a positive
// row scaling) have the signs of the eigenvalues. Throws unless all are > 0.
void require_positive_pivots(int64_t n, const double *d, Definiteness &def);
// LU backends: pivots p[k] (row) and q[k] (column); only symmetric pivoting
// (p == q) reveals the inertia, else def is Unknown.
void lu_definiteness(int64_t n, const int64_t *p, const int64_t *q, const double *udiag, Definiteness &def);

// Every backend refuses a matrix with a NaN or infinite entry before it
// factors (ND_ERR_NONFINITE_STATE), rather than reporting a breakdown.
void require_finite(const Csr &A);
// A LAPACKE info < 0: its work-memory errors are ND_ERR_NOMEM, anything
// else ND_ERR_INTERNAL with the argument.
[[noreturn]] void fail_lapack(int info, const char *what);

}  // namespace nd
