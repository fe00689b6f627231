// The linear-solver seam: every ND_SOLVER_* id is registered (or, for an
// optional backend this build lacks, refused with ND_ERR_KEY and the reason)
// and nothing else is; every backend solves, refactors numerically, and says
// when a matrix requested as SPD is not positive definite.
//
//   unit_linalg          the whole suite, PETSc backends included when built
//   unit_linalg petsc    the PETSc backends only (CTest: unit_linalg_petsc);
//                        exit status 77, "skipped", in a build without PETSc
#include "common/error.hpp"  // before check.h, whose fail() macro would clash with nd::fail
#include <check.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "assembly/bulk.hpp"
#include "common/simd.hpp"
#include "linalg/backends.hpp"
#include "linalg/factorization.hpp"
#include "linalg/ordering.hpp"
#include "linalg/pcg.hpp"
#include "linalg/supernodal.hpp"
#include "linalg/updatable_cholesky.hpp"
#include "testutil.h"
#include "unit_fixtures.hpp"

namespace {

#define ND_ID_(name, value, text) name,
const int kSolverIds[] = {ND_SOLVER_LIST(ND_ID_)};
#undef ND_ID_
// the direct backends: exact to round-off, and they certify definiteness
const std::vector<int> kBackends = {ND_SOLVER_DENSE, ND_SOLVER_BANDED, ND_SOLVER_CHOLMOD, ND_SOLVER_UMFPACK,
                                    ND_SOLVER_KLU,
#ifdef ND_HAVE_PETSC
                                    ND_SOLVER_PETSC_MUMPS
#endif
};
const int kPetscIds[] = {ND_SOLVER_PETSC_MUMPS, ND_SOLVER_PETSC_GAMG};
using nd::Definiteness;
using nd::Structure;
using ndtest::rel_diff;

using ndtest::spd_matrix;

// Symmetric with one negative eigenvalue at least: a diagonal entry lowered
// by twice the largest diagonal. It stays a large pivot, so UMFPACK and KLU
// keep to the diagonal (symmetric pivoting) and can tell.
nd::Csr indefinite_like(const nd::Csr &A) {
  nd::Csr B = A;
  double dmax = 0;
  for (int64_t i = 0; i < A.n; ++i) dmax = std::max(dmax, A.val[A.find(i, i)]);
  B.val[B.find(A.n / 2, A.n / 2)] -= 2 * dmax;
  return B;
}

// Non-symmetric, same pattern: the strict upper triangle scaled by 1.5.
nd::Csr nonsymmetric_like(const nd::Csr &A) {
  nd::Csr B = A;
  for (int64_t i = 0; i < A.n; ++i)
    for (int64_t k = A.ptr[i]; k < A.ptr[i + 1]; ++k)
      if (A.col[k] > i) B.val[k] *= 1.5;
  return B;
}

// solves A x = A x_exact through f and returns the relative error
double solve_error(const nd::Factorization &f, const nd::Csr &A) {
  std::vector<double> x(static_cast<size_t>(A.n)), b(x.size());
  for (int64_t i = 0; i < A.n; ++i) x[i] = std::sin(0.37 * i) + 0.1 * i / A.n;
  A.multiply(x.data(), b.data());
  f.solve(b.data());
  double err = 0, ref = 0;
  for (int64_t i = 0; i < A.n; ++i) err = std::max(err, std::fabs(b[i] - x[i])), ref = std::max(ref, std::fabs(x[i]));
  return err / ref;
}

// X's k columns (each n long) solved by f as one block into `many` and one
// by one into `one`: the first column whose bits differ, or -1 (2k solves)
int64_t first_column_off(const nd::Factorization &f, const std::vector<double> &X, int64_t n, int64_t k,
                         std::vector<double> &many, std::vector<double> &one) {
  many = X, one = X;
  f.solve_many(many.data(), n, k);
  for (int64_t j = 0; j < k; ++j) f.solve(one.data() + j * n);
  for (int64_t j = 0; j < k; ++j)
    if (std::memcmp(many.data() + j * n, one.data() + j * n, sizeof(double) * static_cast<size_t>(n)) != 0) return j;
  return -1;
}

int error_code_of_factor(nd::Factorization &f, const nd::Csr &A, Structure s) {
  try {
    f.factor(A, s);
  } catch (const nd::Error &e) {
    return e.code();
  }
  return ND_OK;
}

}  // namespace

// Thrown by make_factorization (ND_OK if none).
static int error_code_of_make(int id, const nd::Csr &A, Structure s, std::string *what = nullptr) {
  try {
    nd::make_factorization(id, A, s);
  } catch (const nd::Error &e) {
    if (what) *what = e.what();
    return e.code();
  }
  return ND_OK;
}

// Csr::add_outer refuses a coupling outside the pattern (ND_ERR_INTERNAL
// naming the entry) instead of adding it to the entry lower_bound finds
// next to it: a tridiagonal pattern has no (0, 2), whose neighbour (0, 1)
// must keep its value.
START_TEST(add_outer_refuses_entries_outside_the_pattern) {
  nd::Csr T = nd::csr_from_rows({{0, 1}, {0, 1, 2}, {1, 2}});
  const double u[2] = {1, 1}, v[2] = {1, 1};
  T.add_outer({0, 1}, u, v, 2.0);  // inside: every entry of the 2x2 block
  ck_assert(T.val[T.find(0, 0)] == 2 && T.val[T.find(0, 1)] == 2 && T.val[T.find(1, 1)] == 2);
  int code = 0;
  std::string what;
  try {
    T.add_outer({0, 2}, u, v, 1.0);
  } catch (const nd::Error &e) {
    code = e.code(), what = e.what();
  }
  ck_assert_int_eq(code, ND_ERR_INTERNAL);
  ck_assert_msg(what.find("(0, 2)") != std::string::npos, "%s", what.c_str());
  ck_assert(T.find(0, 2) < 0 && T.val[T.find(0, 1)] == 2);  // the neighbour untouched
}
END_TEST

START_TEST(every_solver_id_is_registered) {
  const nd::Csr A = spd_matrix(3);
  for (int id : kSolverIds) {
    if (const char *why = nd::linear_solver_unavailable(id)) {  // optional, not in this build
      ck_assert(!nd::linear_solver_known(id));
      std::string what;
      ck_assert_int_eq(error_code_of_make(id, A, Structure::SymmetricPositiveDefinite, &what), ND_ERR_KEY);
      ck_assert_str_eq(what.c_str(), why);
      std::printf("unit_linalg: ND_SOLVER %d not built, refused as it should: %s\n", id, why);
      continue;
    }
    ck_assert_msg(nd::linear_solver_known(id), "ND_SOLVER %d has no backend", id);
    auto f = nd::make_factorization(id, A, Structure::SymmetricPositiveDefinite);
    f->factor(A, Structure::SymmetricPositiveDefinite);
    ck_assert_double_le(solve_error(*f, A), 1e-10);
  }
}
END_TEST

START_TEST(unknown_solver_ids_are_errors) {
  const nd::Csr A = spd_matrix(3);
  for (int id : {-1, 8, 99, 42}) {
    ck_assert(!nd::linear_solver_unavailable(id));
    ck_assert(!nd::linear_solver_known(id));
    for (Structure s : {Structure::SymmetricPositiveDefinite, Structure::General}) {
      try {
        nd::make_factorization(id, A, s);
        ck_abort_msg("solver %d was accepted", id);
      } catch (const nd::Error &e) {
        ck_assert_int_eq(e.code(), ND_ERR_KEY);
        const std::string expected = "solver " + std::to_string(id) + " is not an ND_SOLVER_* value";
        ck_assert_str_eq(e.what(), expected.c_str());
      }
    }
  }
}
END_TEST

START_TEST(auto_choice) {
  const nd::Csr small = spd_matrix(3), large = spd_matrix(10);  // 32 and 242 unknowns
  nd::Space bar(ndtest::irregular_interval(100, 0, 1), 2);
  nd::DofMap bar_dofs(bar, {});
  const nd::Csr band = nd::assemble_bulk(bar, bar_dofs, nd::Material{1, 0.3, 1}).M;  // 201 unknowns
  const Structure spd = Structure::SymmetricPositiveDefinite, gen = Structure::General;
  ck_assert_str_eq(nd::make_factorization(ND_SOLVER_AUTO, small, gen)->name(), "dense");
  ck_assert_str_eq(nd::make_factorization(ND_SOLVER_AUTO, band, spd)->name(), "banded");
  ck_assert_str_eq(nd::make_factorization(ND_SOLVER_AUTO, large, spd)->name(), "cholmod");
  ck_assert_str_eq(nd::make_factorization(ND_SOLVER_AUTO, large, gen)->name(), "umfpack");
  ck_assert_str_eq(nd::make_factorization(ND_SOLVER_CHOLMOD, small, gen)->name(), "umfpack");
}
END_TEST

START_TEST(every_backend_reports_indefinite) {
  const nd::Csr A = spd_matrix(10), B = indefinite_like(A);
  const Structure spd = Structure::SymmetricPositiveDefinite;
  for (int id : kBackends) {
    auto f = nd::make_factorization(id, A, spd);
    ck_assert_int_eq(static_cast<int>(f->definiteness()), static_cast<int>(Definiteness::Unknown));
    f->factor(A, spd);
    ck_assert_msg(f->definiteness() == Definiteness::PositiveDefinite, "%s: SPD not recognized", f->name());
    ck_assert_msg(solve_error(*f, A) <= 1e-10, "%s: SPD solve off by %g", f->name(), solve_error(*f, A));
    ck_assert_msg(error_code_of_factor(*f, B, spd) == ND_ERR_INDEFINITE, "%s: indefinite not reported", f->name());
    ck_assert_msg(f->definiteness() == Definiteness::NotPositiveDefinite, "%s", f->name());
    f->factor(A, spd);  // the same symbolic analysis serves again
    ck_assert_msg(solve_error(*f, A) <= 1e-10, "%s: refactored SPD solve off", f->name());
  }
}
END_TEST

START_TEST(every_backend_solves_nonsymmetric) {
  const nd::Csr A = spd_matrix(10), N = nonsymmetric_like(A);
  for (int id : kBackends) {
    auto f = nd::make_factorization(id, N, Structure::General);
    f->factor(N, Structure::General);
    ck_assert_msg(f->definiteness() == Definiteness::Unknown, "%s", f->name());
    ck_assert_msg(solve_error(*f, N) <= 1e-10, "%s: solve off by %g", f->name(), solve_error(*f, N));
  }
}
END_TEST

// k right-hand sides at once: on one process every backend gives each column
// the bits of a solve of it alone (ContactColumns relies on it: a column's
// bits may not depend on which others were made with it), whole or only at
// some unknowns, and counts one solve per right-hand side.
START_TEST(every_backend_solves_many_as_one_by_one) {
  const nd::Csr A = spd_matrix(10);
  const int64_t n = A.n, k = 5;
  std::vector<double> X(static_cast<size_t>(n * k));
  for (size_t i = 0; i < X.size(); ++i) X[i] = std::sin(0.11 * static_cast<double>(i)) + (i % 7 == 0 ? 1.0 : 0.0);
  for (int id : kBackends) {
    nd::Counters counters;
    auto f = nd::make_factorization(id, A, Structure::SymmetricPositiveDefinite, &counters);
    f->factor(A, Structure::SymmetricPositiveDefinite);
    std::vector<double> many, one;
    ck_assert_msg(first_column_off(*f, X, n, k, many, one) < 0,
                  "%s: a block of right-hand sides differs from one by one", f->name());
    ck_assert_int_eq(counters.solves, 2 * k);
    // only some unknowns kept (the contact columns on split rows): those bits
    const std::vector<int64_t> at = {0, 3, 4, 17, n - 1};
    std::vector<double> picked(at.size() * static_cast<size_t>(k)), scratch = X;
    f->solve_many_at(scratch.data(), n, k, at, picked.data());
    ck_assert_int_eq(counters.solves, 3 * k);
    for (int64_t j = 0; j < k; ++j)
      for (size_t i = 0; i < at.size(); ++i)
        ck_assert_msg(std::memcmp(&picked[static_cast<size_t>(j) * at.size() + i], &one[j * n + at[i]], sizeof(double)) == 0,
                      "%s: column %lld at unknown %lld", f->name(), static_cast<long long>(j),
                      static_cast<long long>(at[i]));
    ck_assert_int_eq(counters.values_received, 0);  // one process
    ck_assert_double_le(solve_error(*f, A), 1e-10);
  }
}
END_TEST

// right-hand sides with nonzeros at: a contact point's few neighbouring
// rows; one row at each end; rows in distant parts of the mesh; none (the
// 5th); every row (the 6th)
std::vector<double> sparse_columns(int64_t n, int64_t &k) {
  const std::vector<std::vector<int64_t>> nonzeros = {
      {40, 41, 42, 43}, {0}, {n - 1}, {7, n / 3, n / 2 + 5, n - 20}, {}, {}};
  k = static_cast<int64_t>(nonzeros.size());
  std::vector<double> X(static_cast<size_t>(n * k), 0.0);
  for (int64_t j = 0; j < k; ++j)
    for (int64_t i : nonzeros[j]) X[j * n + i] = 1.0 + 0.25 * static_cast<double>(i % 5);
  for (int64_t i = 0; i < n; ++i) X[(k - 1) * n + i] = std::cos(0.3 * static_cast<double>(i));
  return X;
}

// A CHOLMOD factor large enough to be supernodal (1,922 unknowns), with
// the right-hand sides of sparse_columns
struct SupernodalCase {
  SupernodalCase() : A(spd_matrix(30)), n(A.n), X(sparse_columns(n, k)) {
    ck_assert(nd::cholmod_is_supernodal(A));  // else the paths under test are not taken
    f = nd::make_factorization(ND_SOLVER_CHOLMOD, A, Structure::SymmetricPositiveDefinite, &counters);
    f->factor(A, Structure::SymmetricPositiveDefinite);
  }
  nd::Csr A;
  int64_t n, k = 0;
  std::vector<double> X;
  nd::Counters counters;
  std::unique_ptr<nd::Factorization> f;
};

// A supernodal CHOLMOD factor is solved by the library's own loops for its
// small diagonal blocks and by the BLAS for the wide ones: on a factor with
// both, a whole right-hand side must solve A x = b as a different code
// does (UMFPACK's LU), to the round-off of each (measured 2.5e-15 both, 6e-16 apart).
START_TEST(cholmod_supernodal_solve_agrees_with_lu) {
  SupernodalCase c;
  const nd::Csr &A = c.A;
  const int64_t n = c.n;
  ck_assert_int_gt(nd::cholmod_widest_supernode(A), nd::kCholmodOwnTriangle);  // both kinds of block
  auto lu = nd::make_factorization(ND_SOLVER_UMFPACK, A, Structure::General);
  lu->factor(A, Structure::General);
  const double own = solve_error(*c.f, A), other = solve_error(*lu, A);
  std::vector<double> x(static_cast<size_t>(n)), y;
  for (int64_t i = 0; i < n; ++i) x[i] = std::cos(0.21 * static_cast<double>(i)) + (i % 11 == 0 ? 2.0 : 0.0);
  y = x;
  c.f->solve(x.data());
  lu->solve(y.data());
  double diff = 0, ref = 0;
  for (int64_t i = 0; i < n; ++i) diff = std::max(diff, std::fabs(x[i] - y[i])), ref = std::max(ref, std::fabs(y[i]));
  std::printf("unit_linalg: supernodal solve error %.2e (UMFPACK %.2e), the two apart %.2e\n", own, other, diff / ref);
  ck_assert_double_le(own, 1e-13);
  ck_assert_double_le(other, 1e-13);
  ck_assert_double_le(diff / ref, 1e-13);
}
END_TEST

// CHOLMOD's forward solve of a column with few nonzeros runs only over the
// supernodes they reach (the contact points' columns): each column must
// still be the bits of solve(), whatever its nonzeros, on a factor large
// enough to be supernodal (1,922 unknowns).
START_TEST(cholmod_solves_sparse_columns_as_one_by_one) {
  SupernodalCase c;
  const nd::Csr &A = c.A;
  const int64_t n = c.n, k = c.k;
  const std::vector<double> &X = c.X;
  const nd::Factorization *f = c.f.get();
  const nd::Counters &counters = c.counters;
  std::vector<double> many, one;
  const int64_t off = first_column_off(*f, X, n, k, many, one);
  ck_assert_msg(off < 0, "column %lld differs from solve()'s", static_cast<long long>(off));
  ck_assert_int_eq(counters.solves, 2 * k);
  for (int64_t i = 0; i < n; ++i) ck_assert(many[4 * n + i] == 0);  // the zero column stays zero
  // and they solve: A x = b for the column with nonzeros in distant rows
  std::vector<double> Ax(static_cast<size_t>(n));
  A.multiply(many.data() + 3 * n, Ax.data());
  double err = 0;
  for (int64_t i = 0; i < n; ++i) err = std::max(err, std::fabs(Ax[i] - X[3 * n + i]));
  ck_assert_double_le(err, 1e-12);
}
END_TEST

// CHOLMOD's solve of a block kept at a few rows (the contact points' DOFs)
// runs its backward solve only over the supernodes of those rows and their
// ancestors: each kept value must be the bits of solve()'s, whatever the
// rows; a factor too small to be supernodal solves whole, as before.
START_TEST(cholmod_solves_columns_at_few_rows_as_whole) {
  SupernodalCase c;
  const int64_t n = c.n, k = c.k;
  const std::vector<double> &X = c.X;
  const nd::Factorization *f = c.f.get();
  const nd::Counters &counters = c.counters;
  // a few rows need a part of the backward solve; every row all of it
  const double share = f->backward_share_at({40, 41, 42, 43});
  ck_assert_msg(share > 0 && share < 0.5, "%g", share);
  std::vector<double> whole = X;
  for (int64_t j = 0; j < k; ++j) f->solve(whole.data() + j * n);
  // kept rows: a few neighbours; the first; the last; spread out (unsorted); every row
  std::vector<int64_t> every(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) every[i] = i;
  const std::vector<std::vector<int64_t>> kept = {{40, 41, 42, 43}, {0}, {n - 1}, {n - 20, 7, n / 2, n / 3}, every};
  for (const std::vector<int64_t> &at : kept) {
    const size_t m = at.size();
    std::vector<double> x = X, out(m * static_cast<size_t>(k));
    const int64_t before = counters.solves;
    f->solve_many_at(x.data(), n, k, at, out.data());
    ck_assert_int_eq(counters.solves - before, k);
    if (m == static_cast<size_t>(n)) ck_assert(f->backward_share_at(at) == 1.0);
    for (int64_t j = 0; j < k; ++j)
      for (size_t i = 0; i < m; ++i)
        ck_assert_msg(std::memcmp(&out[j * m + i], &whole[j * n + at[i]], sizeof(double)) == 0,
                      "column %lld at row %lld: %.17g, solve() %.17g", static_cast<long long>(j),
                      static_cast<long long>(at[i]), out[j * m + i], whole[j * n + at[i]]);
  }
  // simplicial: whole solves, the same values
  const nd::Csr B = spd_matrix(4);
  ck_assert(!nd::cholmod_is_supernodal(B));
  auto g = nd::make_factorization(ND_SOLVER_CHOLMOD, B, Structure::SymmetricPositiveDefinite);
  g->factor(B, Structure::SymmetricPositiveDefinite);
  ck_assert(g->backward_share_at({3, 1}) == 1.0);
  std::vector<double> b(static_cast<size_t>(B.n)), b_whole, b_out(2);
  for (int64_t i = 0; i < B.n; ++i) b[i] = std::sin(1.0 + static_cast<double>(i));
  b_whole = b;
  g->solve(b_whole.data());
  g->solve_many_at(b.data(), B.n, 1, {3, 1}, b_out.data());
  ck_assert(b_out[0] == b_whole[3] && b_out[1] == b_whole[1]);
}
END_TEST

START_TEST(petsc_ids_are_refused_or_solve) {
  const nd::Csr A = spd_matrix(10);
  for (int id : kPetscIds) {
#ifdef ND_HAVE_PETSC
    ck_assert(nd::linear_solver_known(id) && !nd::linear_solver_unavailable(id));
    auto f = nd::make_factorization(id, A, Structure::SymmetricPositiveDefinite);
    f->factor(A, Structure::SymmetricPositiveDefinite);
    ck_assert_msg(solve_error(*f, A) <= (id == ND_SOLVER_PETSC_GAMG ? 1e-9 : 1e-10), "%s: off by %g", f->name(),
                  solve_error(*f, A));
#else
    ck_assert(!nd::linear_solver_known(id));
    ck_assert_ptr_nonnull(nd::linear_solver_unavailable(id));
    for (Structure s : {Structure::SymmetricPositiveDefinite, Structure::General}) {
      std::string what;
      ck_assert_int_eq(error_code_of_make(id, A, s, &what), ND_ERR_KEY);
      ck_assert_msg(what.find("ND_WITH_PETSC") != std::string::npos, "%s", what.c_str());
    }
#endif
  }
}
END_TEST

#ifdef ND_HAVE_PETSC
// MUMPS: SPD certified (LDL^T inertia), indefinite refused, LU for the rest;
// each after a failure as well (a failed factorization is not reused).
START_TEST(petsc_mumps_conformance) {
  const nd::Csr A = spd_matrix(10), B = indefinite_like(A), N = nonsymmetric_like(A);
  const Structure spd = Structure::SymmetricPositiveDefinite, gen = Structure::General;
  auto f = nd::make_factorization(ND_SOLVER_PETSC_MUMPS, A, spd);
  ck_assert_str_eq(f->name(), "petsc-mumps");
  ck_assert_int_eq(error_code_of_factor(*f, B, spd), ND_ERR_INDEFINITE);
  ck_assert(f->definiteness() == Definiteness::NotPositiveDefinite);
  f->factor(A, spd);
  ck_assert(f->definiteness() == Definiteness::PositiveDefinite);
  ck_assert_double_le(solve_error(*f, A), 1e-10);
  f->factor(N, gen);  // the same object, analysed again for LU
  ck_assert(f->definiteness() == Definiteness::Unknown);
  ck_assert_double_le(solve_error(*f, N), 1e-10);
  f->factor(B, gen);  // indefinite is fine as General
  ck_assert_double_le(solve_error(*f, B), 1e-8);
  // a structurally fine but singular matrix: a zero row and column
  nd::Csr S = A;
  for (int64_t k = S.ptr[3]; k < S.ptr[4]; ++k) S.val[k] = 0;
  for (int64_t i = 0; i < S.n; ++i)
    if (int64_t k = S.find(i, 3); k >= 0) S.val[k] = 0;
  ck_assert_int_eq(error_code_of_factor(*f, S, gen), ND_ERR_SINGULAR);
  ck_assert_int_eq(error_code_of_factor(*f, S, spd), ND_ERR_INDEFINITE);
  nd::Csr bad = A;
  bad.val[5] = NAN;
  ck_assert_int_eq(error_code_of_factor(*f, bad, spd), ND_ERR_NONFINITE_STATE);
  f->factor(A, spd);
  ck_assert_double_le(solve_error(*f, A), 1e-10);
}
END_TEST

// GAMG: solves to the Krylov tolerance (rtol 1e-12 on the true residual: the
// error is within cond(A) 1e-12), with CG for SPD and GMRES otherwise, with and
// without the rigid-body near-null space; an indefinite matrix requested as
// SPD is refused when CG meets negative curvature (factor() cannot tell).
START_TEST(petsc_gamg_conformance) {
  const nd::Csr A = spd_matrix(10), B = indefinite_like(A), N = nonsymmetric_like(A);
  const Structure spd = Structure::SymmetricPositiveDefinite, gen = Structure::General;
  nd::Space s(ndtest::irregular_rectangle(10), 1);
  nd::DofGeometry g;
  g.dim = 2;
  g.x.resize(static_cast<size_t>(2 * A.n));
  g.component.resize(static_cast<size_t>(A.n));
  for (int64_t i = 0; i < A.n; ++i) {
    g.component[i] = static_cast<int>(i % 2);
    g.x[2 * i] = s.node_x(i / 2)[0], g.x[2 * i + 1] = s.node_x(i / 2)[1];
  }
  const nd::DofGeometry *geometries[] = {nullptr, &g};
  for (const nd::DofGeometry *geometry : geometries) {
    auto f = nd::make_factorization(ND_SOLVER_PETSC_GAMG, A, spd, nullptr, geometry);
    ck_assert_str_eq(f->name(), "petsc-gamg");
    f->factor(A, spd);
    ck_assert(f->definiteness() == Definiteness::Unknown);
    ck_assert_double_le(solve_error(*f, A), 1e-9);
    f->factor(N, gen);
    ck_assert_double_le(solve_error(*f, N), 1e-9);
    int code = error_code_of_factor(*f, B, spd);
    if (code == ND_OK) try {
        std::vector<double> x(static_cast<size_t>(A.n), 1.0);
        f->solve(x.data());
      } catch (const nd::Error &e) {
        code = e.code();
      }
    std::string what;
    if (code != ND_ERR_INDEFINITE) try {
        f->factor(B, spd);
        std::vector<double> x(static_cast<size_t>(A.n), 1.0);
        f->solve(x.data());
      } catch (const nd::Error &e) {
        what = e.what();
      }
    ck_assert_msg(code == ND_ERR_INDEFINITE, "GAMG on an indefinite matrix: %d (%s)", code, what.c_str());
    ck_assert(f->definiteness() == Definiteness::NotPositiveDefinite);
    f->factor(A, spd);
    ck_assert_double_le(solve_error(*f, A), 1e-9);
    std::vector<double> zero(static_cast<size_t>(A.n), 0.0);  // a zero right-hand side: x = 0
    f->solve(zero.data());
    for (double z : zero) ck_assert(z == 0);
  }
}
END_TEST
#endif

// Columns on cliques of A's graph (an element's DOFs: each row a neighbour
// of the others), as the contact points' columns are: count of them, of
// 4 to 6 entries, the j-th at scale sqrt(scale)
nd::SparseColumns clique_columns(const nd::Csr &A, int64_t count, double scale) {
  nd::SparseColumns C;
  for (int64_t j = 0; j < count; ++j) {
    const int64_t i = (j * 617 + 5) % A.n;
    std::vector<int64_t> clique{i};
    for (int64_t k = A.ptr[i]; k < A.ptr[i + 1] && clique.size() < 6; ++k) {
      bool joined = A.col[k] != i;
      for (int64_t c : clique) joined = joined && A.find(A.col[k], c) >= 0;
      if (joined) clique.push_back(A.col[k]);
    }
    ck_assert_int_ge(static_cast<int64_t>(clique.size()), 4);
    for (size_t e = 0; e < clique.size(); ++e) {
      C.idx.push_back(clique[e]);
      C.val.push_back(std::sqrt(scale) * (1 + 0.1 * static_cast<double>(e) - 0.2 * static_cast<double>(j % 3)));
    }
    C.ptr.push_back(static_cast<int64_t>(C.idx.size()));
  }
  return C;
}

// column j of C alone
nd::SparseColumns column_of(const nd::SparseColumns &C, int64_t j) {
  nd::SparseColumns one;
  one.idx.assign(C.idx.begin() + C.ptr[j], C.idx.begin() + C.ptr[j + 1]);
  one.val.assign(C.val.begin() + C.ptr[j], C.val.begin() + C.ptr[j + 1]);
  one.ptr.push_back(static_cast<int64_t>(one.idx.size()));
  return one;
}

// The updatable factor alone, in both of its forms (supernodal LL^T with our
// updates where CHOLMOD's analysis is supernodal, else simplicial LDL^T with
// CHOLMOD's): L L^T + C C^T then - C C^T, each against a factorization of
// the modified matrix (1e-12); and its cost model, which decides between
// updating and refactoring: a set of columns costs the sum of its columns,
// each positive and below a factorization (a path holds at most nnz(L)
// entries), and a factor made anew on the same pattern gives the same
// costs (the model reads the structure, not the clock). The work counted
// (modified_entries, ND_STAT_FACTOR_MODIFIED_ENTRIES) is the model's
// bound: in the supernodal form the kernel counts the entries it rotates,
// those of each column's path (the columns from its first row to the root,
// where its entries fill in) but where a vector's entries stay zero (exact
// zeros of L's blocks; 47 of 26,855 entries here); the simplicial form counts
// the paths.
START_TEST(updatable_cholesky_updates_and_costs) {
  bool seen[2] = {false, false};
  for (int nx : {30, 3}) {  // 1,922 unknowns (supernodal), 32 (simplicial)
    const nd::Csr A = spd_matrix(nx);
    const bool super = nd::cholmod_is_supernodal(A);
    seen[super] = true;
    const nd::SparseColumns C = clique_columns(A, 3, 1e4);
    nd::Csr B = A;  // A + C C^T, in A's pattern (the rows of a column are neighbours)
    for (int64_t j = 0; j < C.count(); ++j)
      for (int64_t a = C.ptr[j]; a < C.ptr[j + 1]; ++a)
        for (int64_t b = C.ptr[j]; b < C.ptr[j + 1]; ++b) {
          const int64_t k = B.find(C.idx[a], C.idx[b]);
          ck_assert_msg(k >= 0, "column %lld leaves the pattern", static_cast<long long>(j));
          B.val[k] += C.val[a] * C.val[b];
        }
    nd::UpdatableCholesky f(A, nullptr), g(A, nullptr);
    f.factor(A);
    g.factor(B);
    ck_assert_int_eq(f.modified_entries(), 0);
    ck_assert(f.modify(true, C));
    const double path = f.path_entries(C);
    ck_assert(path > C.count());
    const int64_t updated = f.modified_entries();
    if (super) ck_assert(updated <= path && updated >= 0.99 * path);
    else ck_assert_int_eq(updated, static_cast<int64_t>(path));
    std::vector<double> x(static_cast<size_t>(A.n)), y(x.size());
    for (int64_t i = 0; i < A.n; ++i) x[i] = y[i] = std::cos(0.3 * i);
    f.solve(x.data());
    g.solve(y.data());
    ck_assert_msg(rel_diff(x, y) <= 1e-12, "n = %lld: updated %g from the factor", static_cast<long long>(A.n),
                  rel_diff(x, y));
    ck_assert(f.modify(false, C));  // back to A
    const int64_t downdated = f.modified_entries() - updated;
    if (super) ck_assert(downdated <= path && downdated >= 0.99 * path);
    else ck_assert_int_eq(downdated, static_cast<int64_t>(path));
    std::printf("unit_linalg: n = %lld, %s: entries rotated %lld and %lld, on the paths %.0f\n",
                static_cast<long long>(A.n), super ? "supernodal" : "simplicial", static_cast<long long>(updated),
                static_cast<long long>(downdated), path);
    g.factor(A);
    for (int64_t i = 0; i < A.n; ++i) x[i] = y[i] = std::cos(0.3 * i);
    f.solve(x.data());
    g.solve(y.data());
    ck_assert_msg(rel_diff(x, y) <= 1e-12, "n = %lld: downdated %g from the factor", static_cast<long long>(A.n),
                  rel_diff(x, y));

    double sum = 0;
    for (int64_t j = 0; j < C.count(); ++j) {
      const double c = f.modify_cost(column_of(C, j));
      ck_assert_msg(c > 0 && c < f.factor_cost(), "column %lld costs %g, a factorization %g",
                    static_cast<long long>(j), c, f.factor_cost());
      sum += c;
    }
    ck_assert_double_eq_tol(f.modify_cost(C), sum, 1e-12 * sum);
    ck_assert_double_eq(g.modify_cost(C), f.modify_cost(C));
    ck_assert_double_eq(g.factor_cost(), f.factor_cost());
  }
  ck_assert(seen[0] && seen[1]);
}
END_TEST

// The supernodal updates (linalg/supernodal.hpp) take their columns kBatch
// at a time up their paths, each column of L modified by one after the
// other: the bits of one column per call, in the scalar form as in the
// wide one (AVX2, common/simd.hpp). Checked on the solves after 2 kBatch + 3
// columns (three batches, the last not full), updated then downdated.
START_TEST(supernodal_updates_in_batches_have_the_bits_one_by_one) {
  const nd::Csr A = spd_matrix(30);
  ck_assert(nd::cholmod_is_supernodal(A));
  const nd::SparseColumns C = clique_columns(A, 2 * nd::SupernodalModifier::kBatch + 3, 1e4);
  std::vector<double> b(static_cast<size_t>(A.n));
  for (int64_t i = 0; i < A.n; ++i) b[i] = std::cos(0.3 * i);
  const bool simd_before = nd::simd_on();
  std::vector<std::vector<double>> solutions;  // batched, one by one, batched without the wide form
  for (int way = 0; way < 3; ++way) {
    nd::set_simd(way == 2 ? false : simd_before);
    nd::UpdatableCholesky f(A, nullptr);
    f.factor(A);
    for (bool add : {true, false}) {
      if (way == 1) {
        for (int64_t j = 0; j < C.count(); ++j) ck_assert(f.modify(add, column_of(C, j)));
      } else {
        ck_assert(f.modify(add, C));
      }
      std::vector<double> x = b;
      f.solve(x.data());
      solutions.push_back(x);
    }
  }
  nd::set_simd(simd_before);
  for (size_t k = 2; k < solutions.size(); ++k)
    ck_assert_msg(std::memcmp(solutions[k].data(), solutions[k % 2].data(), b.size() * sizeof(double)) == 0,
                  "solve %zu differs from the batched one's bits", k);
  ck_assert(std::memcmp(solutions[0].data(), solutions[1].data(), b.size() * sizeof(double)) != 0);
}
END_TEST

// What an update refuses, in the supernodal form: a downdate that leaves
// the matrix indefinite (false, and no factor until the next factor(): a
// solve is then an internal error), and a column with a row where its first
// column of L has none (it would fill L: false)
START_TEST(supernodal_updates_refuse_indefinite_and_fill) {
  const nd::Csr A = spd_matrix(30);
  ck_assert(nd::cholmod_is_supernodal(A));
  nd::UpdatableCholesky f(A, nullptr);
  f.factor(A);
  ck_assert(!f.modify(false, clique_columns(A, 2, 1e8)));  // A - C C^T: far from positive
  int code = ND_OK;
  std::vector<double> x(static_cast<size_t>(A.n), 1.0);
  try {
    f.solve(x.data());
  } catch (const nd::Error &e) {
    code = e.code();
  }
  ck_assert_int_eq(code, ND_ERR_INTERNAL);
  f.factor(A);
  nd::SparseColumns far;  // two unknowns far apart: no entry of A, nor of L, joins them
  far.idx = {0, A.n - 1};
  far.val = {1.0, 1.0};
  far.ptr.push_back(2);
  ck_assert(A.find(0, A.n - 1) < 0);
  ck_assert(!f.modify(true, far));
  f.factor(A);
  ck_assert(f.modify(true, clique_columns(A, 2, 1e4)));  // factored anew: updates go on
}
END_TEST

// A factor made like another (make_factorization's ordered_like: the
// coercivity check reuses the step matrix's ordering) takes that ordering:
// given the ordering of another pattern of as many unknowns (a chain), its
// solves still reach round-off, and their bits differ from those of the
// matrix's own ordering; given its own matrix's factor, they are those bits.
START_TEST(cholmod_factor_made_like_another) {
  const nd::Csr A = spd_matrix(20);
  std::vector<std::vector<int64_t>> chain(static_cast<size_t>(A.n));
  for (int64_t i = 0; i < A.n; ++i)
    for (int64_t j = std::max<int64_t>(0, i - 1); j <= std::min<int64_t>(A.n - 1, i + 1); ++j) chain[i].push_back(j);
  nd::Csr B = nd::csr_from_rows(std::move(chain));
  B.val.assign(B.col.size(), -1.0);
  for (int64_t i = 0; i < B.n; ++i) B.val[B.find(i, i)] = 4.0;
  const Structure spd = Structure::SymmetricPositiveDefinite;
  auto own = nd::make_factorization(ND_SOLVER_CHOLMOD, A, spd);
  auto chain_factor = nd::make_factorization(ND_SOLVER_CHOLMOD, B, spd);
  auto like_chain = nd::make_factorization(ND_SOLVER_CHOLMOD, A, spd, nullptr, nullptr, chain_factor.get());
  auto like_own = nd::make_factorization(ND_SOLVER_CHOLMOD, A, spd, nullptr, nullptr, own.get());
  for (auto *f : {own.get(), like_chain.get(), like_own.get()}) f->factor(A, spd);
  for (auto *f : {own.get(), like_chain.get(), like_own.get()})
    ck_assert_msg(solve_error(*f, A) <= 1e-12, "error %g", solve_error(*f, A));
  std::vector<double> x(static_cast<size_t>(A.n)), y, z;
  for (int64_t i = 0; i < A.n; ++i) x[i] = std::cos(0.3 * static_cast<double>(i));
  y = x, z = x;
  own->solve(y.data());
  like_chain->solve(z.data());
  ck_assert(std::memcmp(y.data(), z.data(), y.size() * sizeof(double)) != 0);
  z = x;
  like_own->solve(z.data());
  ck_assert(std::memcmp(y.data(), z.data(), y.size() * sizeof(double)) == 0);
}
END_TEST

// METIS's ordering of the pattern's supervariables (linalg/nested_dissection.cpp):
// a permutation in which consecutive rows with the same columns (a node's
// DOFs) stay consecutive and in order, in 1D (no two such rows: METIS's
// ordering of the whole graph), 2D and 3D, P1 and P2, and with one
// component of some nodes removed (a node's DOFs then differ in number).
START_TEST(nested_dissection_keeps_nodes_together) {
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  const std::vector<std::shared_ptr<nd::Mesh>> meshes = {
      ndtest::irregular_interval(40, 0, 1), ndtest::irregular_rectangle(12),
      std::make_shared<nd::Mesh>(nd::make_box(3, 3, 3, lo, hi))};
  for (const auto &mesh : meshes)
    for (int degree = 1; degree <= 2; ++degree)
      for (int removed = 0; removed <= 1; ++removed) {
        nd::Space sp(mesh, degree);
        nd::DofMap dofs(sp, {});
        nd::Csr A = nd::assemble_bulk(sp, dofs, nd::Material{50, 0.25, 1}).K;
        const int dim = sp.dim;
        if (removed) {  // the first component of every fifth node
          std::vector<int64_t> keep(static_cast<size_t>(A.n), -1);
          int64_t kept = 0;
          for (int64_t i = 0; i < A.n; ++i)
            if (!(i % dim == 0 && (i / dim) % 5 == 0)) keep[i] = kept++;
          std::vector<std::vector<int64_t>> rows(static_cast<size_t>(kept));
          for (int64_t i = 0; i < A.n; ++i)
            for (int64_t k = A.ptr[i]; k < A.ptr[i + 1] && keep[i] >= 0; ++k)
              if (keep[A.col[k]] >= 0) rows[keep[i]].push_back(keep[A.col[k]]);
          A = nd::csr_from_rows(std::move(rows));
        }
        const std::vector<int64_t> perm = nd::nested_dissection(A);
        ck_assert_int_eq(static_cast<int64_t>(perm.size()), A.n);
        std::vector<int64_t> at(static_cast<size_t>(A.n), -1);
        for (int64_t r = 0; r < A.n; ++r) {
          ck_assert(perm[r] >= 0 && perm[r] < A.n && at[perm[r]] < 0);
          at[perm[r]] = r;
        }
        int64_t joined = 0;  // rows with their predecessor's columns
        for (int64_t i = 1; i < A.n; ++i) {
          const bool same = A.ptr[i + 1] - A.ptr[i] == A.ptr[i] - A.ptr[i - 1] &&
                            std::equal(A.col.begin() + A.ptr[i], A.col.begin() + A.ptr[i + 1],
                                       A.col.begin() + A.ptr[i - 1]);
          if (!same) continue;
          ++joined;
          ck_assert_msg(at[i] == at[i - 1] + 1, "dim %d P%d: row %lld at %lld, row %lld at %lld", dim, degree,
                        static_cast<long long>(i), static_cast<long long>(at[i]), static_cast<long long>(i - 1),
                        static_cast<long long>(at[i - 1]));
        }
        // a node's DOFs share their columns (and so may two nodes with the
        // same neighbours, at a corner); in 1D no two rows do
        if (dim == 1) ck_assert_int_eq(joined, 0);
        else if (!removed) ck_assert_int_ge(joined, sp.n_nodes * (dim - 1));
        else ck_assert(joined > 0);
      }
}
END_TEST

// Conjugate gradients on the mass matrix (P1 and P2): a random right-hand
// side solved to the factored answer's round-off within a few dozen
// iterations; and an honest failure where the method does not apply (a
// non-positive diagonal; the singular stiffness of a free body, on which the
// residual stagnates), for the caller to factor instead.
START_TEST(conjugate_gradients_on_the_mass_matrix) {
  for (int degree = 1; degree <= 2; ++degree) {
    nd::Space sp(ndtest::irregular_rectangle(30), degree);
    nd::DofMap dofs(sp, {});
    const nd::BulkOperators ops = nd::assemble_bulk(sp, dofs, nd::Material{50, 0.25, 1});
    std::vector<double> x(static_cast<size_t>(ops.M.n)), y;
    for (size_t i = 0; i < x.size(); ++i) x[i] = std::sin(1.3 * static_cast<double>(i)) + 0.2;
    y = x;
    const nd::PcgResult r = nd::pcg_jacobi(ops.M, x.data(), 1e-15, 300);
    ck_assert_msg(r.converged && r.residual <= 1e-15, "P%d: %d iterations, residual %g", degree, r.iterations,
                  r.residual);
    ck_assert_int_le(r.iterations, 100);
    auto f = nd::make_factorization(ND_SOLVER_CHOLMOD, ops.M, Structure::SymmetricPositiveDefinite);
    f->factor(ops.M, Structure::SymmetricPositiveDefinite);
    f->solve(y.data());
    ck_assert_msg(rel_diff(x, y) <= 1e-13, "P%d: %g from the factored solve", degree, rel_diff(x, y));
    std::printf("unit_linalg: mass matrix P%d, n = %lld: %d CG iterations, %.2g from the factored solve\n", degree,
                static_cast<long long>(ops.M.n), r.iterations, rel_diff(x, y));
    // on toward 1e-16 while the residual falls (the initial acceleration's
    // solve): converged, with a residual no larger, within 1e-15 still
    std::vector<double> w(x.size());
    for (size_t i = 0; i < w.size(); ++i) w[i] = std::sin(1.3 * static_cast<double>(i)) + 0.2;
    const nd::PcgResult polished = nd::pcg_jacobi(ops.M, w.data(), 1e-15, 300, 1e-16);
    ck_assert_msg(polished.converged && polished.residual <= r.residual && polished.iterations >= r.iterations,
                  "P%d: polished: %d iterations, residual %g", degree, polished.iterations, polished.residual);
    ck_assert_msg(rel_diff(w, y) <= 1e-13, "P%d: polished: %g from the factored solve", degree, rel_diff(w, y));
    std::printf("unit_linalg: toward 1e-16: %d CG iterations, residual %.2g (%.2g at 1e-15)\n", polished.iterations,
                polished.residual, r.residual);

    std::vector<double> z(x.size(), 1.0);
    nd::Csr bad = ops.M;
    bad.val[bad.find(3, 3)] = -1;
    ck_assert(!nd::pcg_jacobi(bad, z.data(), 1e-15, 300).converged);
    for (size_t i = 0; i < z.size(); ++i) z[i] = std::cos(0.7 * static_cast<double>(i));
    ck_assert(!nd::pcg_jacobi(ops.K, z.data(), 1e-15, 300).converged);  // K has the rigid motions as kernel
    for (size_t i = 0; i < z.size(); ++i) z[i] = std::cos(0.7 * static_cast<double>(i));
    ck_assert(!nd::pcg_jacobi(ops.K, z.data(), 1e-15, 300, 1e-16).converged);
  }
}
END_TEST

int main(int argc, char **argv) {
  Suite *s = suite_create("linalg");
  TCase *tc = tcase_create("factorization");
  const bool petsc_only = argc > 1 && std::strcmp(argv[1], "petsc") == 0;
  if (!petsc_only) {
    tcase_add_test(tc, every_solver_id_is_registered);
    tcase_add_test(tc, add_outer_refuses_entries_outside_the_pattern);
    tcase_add_test(tc, unknown_solver_ids_are_errors);
    tcase_add_test(tc, auto_choice);
    tcase_add_test(tc, every_backend_reports_indefinite);
    tcase_add_test(tc, every_backend_solves_nonsymmetric);
    tcase_add_test(tc, every_backend_solves_many_as_one_by_one);
    tcase_add_test(tc, cholmod_supernodal_solve_agrees_with_lu);
    tcase_add_test(tc, cholmod_solves_sparse_columns_as_one_by_one);
    tcase_add_test(tc, cholmod_solves_columns_at_few_rows_as_whole);
    tcase_add_test(tc, updatable_cholesky_updates_and_costs);
    tcase_add_test(tc, supernodal_updates_in_batches_have_the_bits_one_by_one);
    tcase_add_test(tc, supernodal_updates_refuse_indefinite_and_fill);
    tcase_add_test(tc, nested_dissection_keeps_nodes_together);
    tcase_add_test(tc, cholmod_factor_made_like_another);
    tcase_add_test(tc, conjugate_gradients_on_the_mass_matrix);
  }
  tcase_add_test(tc, petsc_ids_are_refused_or_solve);
#ifdef ND_HAVE_PETSC
  tcase_add_test(tc, petsc_mumps_conformance);
  tcase_add_test(tc, petsc_gamg_conformance);
#else
  if (petsc_only) {
    std::printf("unit_linalg petsc: skipped, this build has no PETSc (configure with -DND_WITH_PETSC=ON)\n");
    suite_add_tcase(s, tc);
    const int status = nd_test_run(s);
    return status == EXIT_SUCCESS ? 77 : status;  // CTest: SKIP_RETURN_CODE 77, once the refusal holds
  }
#endif
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
