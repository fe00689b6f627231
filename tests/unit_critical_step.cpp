// The Lanczos estimate of omega_max (monitor/critical_step.hpp) against a
// dense generalized eigensolver (LAPACK dsygv) on K_Theta + sym(T_c), with
// consistent and lumped mass, P1 and P2, Theta = 1, 0, -1, the bar and the
// disk; with mass redistribution on the DOFs that keep a mass. The estimate must never be below the exact omega_max by more than
// round-off (a smaller omega_max would give a larger, unsafe tau_c) and
// within 1e-3 above it.
#include <lapacke.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "capi/handles.hpp"
#include "monitor/critical_step.hpp"
#include "nitschedyn.h"
// check.h last: it defines a macro `fail`
#include <check.h>

#include "testutil.h"

namespace {

double dense_omega_max(const nd::Discretization &d) {
  const int n = static_cast<int>(d.dofs.n_free);
  std::vector<double> K(static_cast<size_t>(n) * n, 0.0), M(static_cast<size_t>(n) * n, 0.0), w(n);
  for (int i = 0; i < n; ++i)
    for (int64_t k = d.K_theta.ptr[i]; k < d.K_theta.ptr[i + 1]; ++k) {
      K[static_cast<size_t>(i) * n + d.K_theta.col[k]] = d.K_theta.val[k];
      M[static_cast<size_t>(i) * n + d.M.col[k]] = d.M.val[k];
    }
  const nd::ContactPoints &cp = d.contact;
  for (size_t q = 0; q < cp.size(); ++q) {  // + (w/gamma) (b p^T + p b^T)/2
    const auto &a = cp.a[q], &s = cp.s[q];
    for (size_t i = 0; i < a.idx.size(); ++i)
      for (size_t j = 0; j < a.idx.size(); ++j) {
        const double bi = a.val[i] - d.theta * cp.gamma[q] * s.val[i], pi = a.val[i] - cp.gamma[q] * s.val[i];
        const double bj = a.val[j] - d.theta * cp.gamma[q] * s.val[j], pj = a.val[j] - cp.gamma[q] * s.val[j];
        K[a.idx[i] * n + a.idx[j]] += cp.w[q] / cp.gamma[q] * 0.5 * (bi * pj + pi * bj);
      }
  }
  // mass redistribution: the massless DOFs held fixed (their rows and columns out)
  std::vector<int> keep;
  for (int i = 0; i < n; ++i)
    if (d.massless.empty() || !d.massless[i]) keep.push_back(i);
  const int m = static_cast<int>(keep.size());
  std::vector<double> Kr(static_cast<size_t>(m) * m), Mr(Kr.size());
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      Kr[static_cast<size_t>(i) * m + j] = K[static_cast<size_t>(keep[i]) * n + keep[j]];
      Mr[static_cast<size_t>(i) * m + j] = M[static_cast<size_t>(keep[i]) * n + keep[j]];
    }
  ck_assert_int_eq(LAPACKE_dsygv(LAPACK_ROW_MAJOR, 1, 'N', 'U', m, Kr.data(), m, Mr.data(), m, w.data()), 0);
  return std::sqrt(w[m - 1]);
}

void compare(nd_problem p, const char *what) {
  nd::Discretization &d = const_cast<nd::Discretization &>(p->problem.discretization());
  const nd::CriticalStep est = nd::estimate_omega_max(d, ND_SOLVER_AUTO);
  const double exact = dense_omega_max(d), rel = (est.omega_max - exact) / exact;
  std::printf("%-34s n = %4lld: omega_max %.10g, Lanczos %.10g in %d iterations (relative %+.2e)\n", what,
              static_cast<long long>(d.dofs.n_free), exact, est.omega_max, est.iterations, rel);
  ck_assert_msg(rel >= -1e-10 && rel <= 1e-3, "%s: relative error %g", what, rel);
}

START_TEST(lanczos_matches_the_dense_eigenvalue) {
  const double nm[2] = {0, 0.5};
  const double thetas[] = {1, 0, -1};
  char what[128];
  for (int degree = 1; degree <= 2; ++degree)
    for (int lumped = 0; lumped <= 1; ++lumped)
      for (double theta : thetas)
        for (double gamma0 : {0.2, 0.01}) {
          nd_problem p = nd_test_bar(40, degree, ND_SCHEME_NEWMARK, nm, theta, gamma0, 0.001);
          ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
          std::snprintf(what, sizeof what, "bar P%d %s Theta %g gamma0 %g", degree, lumped ? "lumped" : "consistent",
                        theta, gamma0);
          compare(p, what);
          ND_OK_OR_FAIL(nd_problem_destroy(&p));
        }
  for (int cells : {4, 6})  // small rectangles on the plane: a start poor in the top mode
    for (int degree = 1; degree <= 2; ++degree)
      for (int lumped = 0; lumped <= 1; ++lumped)
        for (double gamma0 : {1e-3, 1.0}) {
          nd_mesh m = nullptr;
          nd_problem p = nullptr;
          const double lo[2] = {0, 0}, hi[2] = {1, 1}, blo[2] = {-1, -1}, bhi[2] = {2, 1e-9}, o[2] = {0, 0},
                       up[2] = {0, 1};
          ND_OK_OR_FAIL(nd_mesh_create_rectangle(cells, cells, lo, hi, &m));
          ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
          ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
          ND_OK_OR_FAIL(nd_mesh_destroy(&m));
          ND_OK_OR_FAIL(nd_problem_set_material(p, 1, 0.3, 1));
          ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
          ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, gamma0));
          ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
          std::snprintf(what, sizeof what, "rect %dx%d P%d %s gamma0 %g", cells, cells, degree,
                        lumped ? "lumped" : "consistent", gamma0);
          compare(p, what);
          ND_OK_OR_FAIL(nd_problem_destroy(&p));
        }
  for (int degree = 1; degree <= 2; ++degree)  // mass redistribution (implicit scheme: tau_c is a query)
    for (int lumped = 0; lumped <= 1; ++lumped) {
      nd_problem p = nd_test_bar(40, degree, ND_SCHEME_HYBRID, nullptr, 1.0, 0.2, 0.001);
      ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
      ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
      std::snprintf(what, sizeof what, "bar P%d %s redistributed", degree, lumped ? "lumped" : "consistent");
      compare(p, what);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
  for (int degree = 1; degree <= 2; ++degree)
    for (int lumped = 0; lumped <= 1; ++lumped) {
      nd_mesh m = nullptr;
      nd_problem p = nullptr;
      const double o[2] = {0, 0}, up[2] = {0, 1};
      ND_OK_OR_FAIL(nd_mesh_read_gmsh(ND_MESH_DIR "/disk_h4.msh", &m));
      ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
      ND_OK_OR_FAIL(nd_mesh_destroy(&m));
      ND_OK_OR_FAIL(nd_problem_set_material(p, 50, 0.25, 1));
      ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
      ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
      ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
      std::snprintf(what, sizeof what, "disk h4 P%d %s", degree, lumped ? "lumped" : "consistent");
      compare(p, what);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

}  // namespace

int main(void) {
  Suite *s = suite_create("critical_step");
  TCase *tc = tcase_create("lanczos");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, lanczos_matches_the_dense_eigenvalue);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
