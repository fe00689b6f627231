// The linear-solver seam: every ND_SOLVER_* id is registered and nothing
// else is; every backend solves, refactors numerically, and says when a
// matrix requested as SPD is not positive definite.
#include "common/error.hpp"  // before check.h, whose fail() macro would clash with nd::fail
#include <check.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "assembly/bulk.hpp"
#include "linalg/factorization.hpp"
#include "testutil.h"
#include "unit_fixtures.hpp"

namespace {

#define ND_ID_(name, value, text) name,
const int kSolverIds[] = {ND_SOLVER_LIST(ND_ID_)};
#undef ND_ID_
const int kBackends[] = {ND_SOLVER_DENSE, ND_SOLVER_BANDED, ND_SOLVER_CHOLMOD, ND_SOLVER_UMFPACK, ND_SOLVER_KLU};
using nd::Definiteness;
using nd::Structure;

// c M + K on a 2D P1 rectangle with every DOF free: SPD, n = 2 (nx + 1)^2.
// For nx = 10 (242 unknowns) CHOLMOD picks a simplicial LDL^T.
nd::Csr spd_matrix(int nx) {
  nd::Space s(ndtest::irregular_rectangle(nx), 1);
  nd::DofMap dofs(s, {});
  nd::BulkOperators ops = nd::assemble_bulk(s, dofs, nd::Material{50, 0.25, 1});
  nd::Csr A;
  nd::csr_combine(1e4, ops.M, 1.0, ops.K, A);
  return A;
}

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

int error_code_of_factor(nd::Factorization &f, const nd::Csr &A, Structure s) {
  try {
    f.factor(A, s);
  } catch (const nd::Error &e) {
    return e.code();
  }
  return ND_OK;
}

}  // namespace

START_TEST(every_solver_id_is_registered) {
  const nd::Csr A = spd_matrix(3);
  for (int id : kSolverIds) {
    ck_assert_msg(nd::linear_solver_known(id), "ND_SOLVER %d has no backend", id);
    auto f = nd::make_factorization(id, A, Structure::SymmetricPositiveDefinite);
    f->factor(A, Structure::SymmetricPositiveDefinite);
    ck_assert_double_le(solve_error(*f, A), 1e-10);
  }
}
END_TEST

START_TEST(unknown_solver_ids_are_errors) {
  const nd::Csr A = spd_matrix(3);
  for (int id : {-1, 6, 99, 42}) {
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

int main(void) {
  Suite *s = suite_create("linalg");
  TCase *tc = tcase_create("factorization");
  tcase_add_test(tc, every_solver_id_is_registered);
  tcase_add_test(tc, unknown_solver_ids_are_errors);
  tcase_add_test(tc, auto_choice);
  tcase_add_test(tc, every_backend_reports_indefinite);
  tcase_add_test(tc, every_backend_solves_nonsymmetric);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
