// Mass redistribution (assembly/redistribution.hpp): the contact nodes' rows
// of M are zero, M stays symmetric (to round-off) and positive definite on the other DOFs,
// the total mass is kept, and with P2 (every cell's other nodes span R^d) all
// moments of order 0, 1, 2 are kept: p^T M' q = p^T M q for p, q in {1, x_k}.
// The clamped rows that the reactions read (problem/forces.hpp) hold the same
// redistributed mass as the free ones.
#include <cmath>
#include <limits>

#include "assembly/bulk.hpp"
#include "assembly/redistribution.hpp"
#include "common/error.hpp"  // before check.h, which defines fail
#include "linalg/factorization.hpp"
#include "problem/forces.hpp"
#include "testutil.h"
#include "unit_fixtures.hpp"

#include <check.h>

namespace {

const nd::Material steel_like{3.0, 0.3, 2.5};

// meshes with a contact region 1 on the side x_last = lowest coordinate
std::shared_ptr<nd::Mesh> with_contact(std::shared_ptr<nd::Mesh> m, double at) {
  const double inf = std::numeric_limits<double>::infinity();
  double lo[3] = {-inf, -inf, -inf}, hi[3] = {inf, inf, inf};
  lo[m->dim - 1] = hi[m->dim - 1] = at;
  nd::add_region_box(*m, 1, lo, hi);
  return m;
}

double form(const nd::Csr &A, const std::vector<double> &u, const std::vector<double> &v) {
  std::vector<double> y(u.size());
  A.multiply(v.data(), y.data());
  return nd::dot(A.n, u.data(), y.data());
}

// scalar affine function f (0: 1, k: x_k) on component `comp`, over all DOFs
std::vector<double> affine(const nd::Space &s, int f, int comp) {
  std::vector<double> u(s.n_dofs(), 0.0);
  for (int64_t i = 0; i < s.n_nodes; ++i) u[i * s.dim + comp] = f == 0 ? 1.0 : s.node_x(i)[f - 1];
  return u;
}

}  // namespace

START_TEST(moments_kernel_and_symmetry) {
  const double lo3[3] = {0, 0, 0}, hi3[3] = {1, 1, 1};
  const std::shared_ptr<nd::Mesh> meshes[] = {
      with_contact(ndtest::irregular_interval(9, 0.3, 2.0), 0.3), with_contact(ndtest::irregular_rectangle(4), 0.0),
      with_contact(std::make_shared<nd::Mesh>(nd::make_box(2, 2, 2, lo3, hi3)), 0.0)};
  for (int m = 0; m < 3; ++m)
    for (int degree = 1; degree <= 2; ++degree) {
      nd::Space s(meshes[m], degree);
      nd::DofMap dofs(s, {});
      const std::vector<nd::ContactPlane> planes = {{1, {0, 0, 0}, {0, 0, 1}}};
      const std::vector<char> on = nd::contact_nodes(s, planes);
      const nd::BulkOperators ref = nd::assemble_bulk(s, dofs, steel_like);
      const nd::BulkOperators red = nd::assemble_bulk(s, dofs, steel_like, &on);
      const int d = s.dim;
      // zero rows (and so columns) on the contact nodes
      int n_contact = 0;
      double mmax = 0;
      for (double x : red.M.val) mmax = std::max(mmax, std::fabs(x));
      for (int64_t i = 0; i < red.M.n; ++i) {
        const bool c = on[i / d];
        n_contact += c;
        ck_assert(!c || red.M_lumped[i] == 0);
        ck_assert(c || red.M_lumped[i] > 0);
        for (int64_t k = red.M.ptr[i]; k < red.M.ptr[i + 1]; ++k) {
          if (c) ck_assert_double_eq(red.M.val[k], 0.0);
          // symmetric to round-off, as the original (w phi_i phi_j is not bitwise w phi_j phi_i)
          ck_assert_double_eq_tol(red.M.val[k], red.M.val[red.M.find(red.M.col[k], i)], 1e-14 * mmax);
        }
      }
      ck_assert_int_gt(n_contact, 0);
      // the moments; round-off: a sum of O(n) terms of the size of the total
      const int nf = degree == 2 ? d + 1 : 1;  // P1: the mass only
      const double tol = 1e-13 * static_cast<double>(s.n_dofs());
      for (int comp = 0; comp < d; ++comp)
        for (int f = 0; f < nf; ++f)
          for (int g = 0; g < nf; ++g) {
            const std::vector<double> u = affine(s, f, comp), v = affine(s, g, comp);
            const double a = form(ref.M, u, v), b = form(red.M, u, v);
            ck_assert_msg(std::fabs(a - b) <= tol * std::fabs(form(ref.M, affine(s, 0, comp), affine(s, 0, comp))),
                          "dim %d P%d moment (%d,%d): %.17g vs %.17g", d, degree, f, g, a, b);
          }
      double lumped = 0, total = 0;
      for (int64_t i = 0; i < red.M.n; ++i) lumped += red.M_lumped[i], total += ref.M_lumped[i];
      ck_assert_double_eq_tol(lumped, total, 1e-14 * total * static_cast<double>(s.n_dofs()));
      // positive definite on the other DOFs: M + the identity on the contact DOFs factors
      nd::Csr A = red.M;
      for (int64_t i = 0; i < A.n; ++i)
        if (on[i / d]) A.val[A.find(i, i)] = 1;
      auto fct = nd::make_factorization(ND_SOLVER_DENSE, A, nd::Structure::SymmetricPositiveDefinite);
      fct->factor(A, nd::Structure::SymmetricPositiveDefinite);
    }
}
END_TEST

START_TEST(clamped_rows_hold_the_redistributed_mass) {
  // clamped on x = 0, in contact on y = 0 (the corner node is both)
  auto m = with_contact(ndtest::irregular_rectangle(4), 0.0);
  const double inf = std::numeric_limits<double>::infinity(), lo[3] = {0, -inf, -inf}, hi[3] = {0, inf, inf};
  nd::add_region_box(*m, 2, lo, hi);
  for (int degree = 1; degree <= 2; ++degree) {
    nd::Space s(m, degree);
    const nd::DofMap dofs(s, {2}), all(s, {});
    const std::vector<char> on = nd::contact_nodes(s, {{1, {0, 0, 0}, {0, 1, 0}}});
    const nd::ClampedRows cr = nd::clamped_rows(s, dofs, steel_like, &on);
    const nd::Csr full = nd::assemble_bulk(s, all, steel_like, &on).M;  // every DOF free: full = DOF index
    std::vector<int64_t> dof_of(static_cast<size_t>(dofs.n_free));
    for (size_t k = 0; k < dofs.free.size(); ++k)
      if (dofs.free[k] >= 0) dof_of[dofs.free[k]] = static_cast<int64_t>(k);
    double mmax = 0, worst = 0;
    for (double x : full.val) mmax = std::max(mmax, std::fabs(x));
    int touched = 0;  // clamped rows that redistribution changed
    const nd::ClampedRows plain = nd::clamped_rows(s, dofs, steel_like);
    for (int64_t r = 0; r < cr.M.n; ++r)
      for (int64_t k = cr.M.ptr[r]; k < cr.M.ptr[r + 1]; ++k) {
        const int64_t f = full.find(cr.dofs[r], dof_of[cr.M.col[k]]);
        const double ref = f >= 0 ? full.val[f] : 0.0;
        worst = std::max(worst, std::fabs(cr.M.val[k] - ref));
        touched += std::fabs(plain.M.val[k] - cr.M.val[k]) > 1e-12 * mmax;
      }
    ck_assert_msg(worst <= 1e-14 * mmax, "P%d: clamped mass rows off by %g", degree, worst);
    ck_assert_int_gt(touched, 0);  // the scene does test something
  }
}
END_TEST

START_TEST(a_cell_with_only_contact_nodes_is_refused) {
  auto m = with_contact(std::make_shared<nd::Mesh>(nd::make_interval(1, 0.0, 1.0)), 0.0);
  const double lo[1] = {1}, hi[1] = {1};
  nd::add_region_box(*m, 1, lo, hi);  // both ends in contact
  nd::Space s(m, 1);
  nd::DofMap dofs(s, {});
  const std::vector<char> on = nd::contact_nodes(s, {{1, {0, 0, 0}, {1, 0, 0}}});
  try {
    nd::assemble_bulk(s, dofs, steel_like, &on);
    ck_abort_msg("not refused");
  } catch (const nd::Error &e) {
    ck_assert_int_eq(e.code(), ND_ERR_VALUE);
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("redistribution");
  TCase *tc = tcase_create("mass");
  tcase_add_test(tc, moments_kernel_and_symmetry);
  tcase_add_test(tc, a_cell_with_only_contact_nodes_is_refused);
  tcase_add_test(tc, clamped_rows_hold_the_redistributed_mass);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
