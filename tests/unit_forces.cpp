// Forces out (docs/design.md §8), white-box where the test needs the mass: the
// global balance of every scheme in its own discrete sense,
//   sum_i (M Abar)_i = sum(reactions) + sum(contact force) + sum(loads),
// summed over all DOFs of a component (clamped ones included). K, K_Theta's
// Nitsche part and sigma_n vanish on a translation, so nothing else remains.
// Abar, and the time level of the forces, are the scheme's (TimeScheme::
// mean_weight): the theta-scheme and Newmark balance at t^{n+1}, the hybrid
// scheme at t^{n+1/2} with Abar = (V^{n+1} - V^n)/tau (the momentum change
// itself), generalized-alpha at t^{n+1-alpha}. Also: moving the obstacle's
// point rebuilds nothing.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "capi/handles.hpp"
#include "nitschedyn.h"
// check.h last: it defines a macro `fail` that the library's headers would meet
#include <check.h>

#include "testutil.h"

namespace {

struct Scene {
  nd_problem p = nullptr;
  int dim = 1;
  double volume = 1, top = 1;  // |Omega| and the measure of the traction region
  double b0[3] = {0, 0, 0}, g[3] = {0, 0, 0};
  std::vector<double> nodal;  // n_dofs
  double body(double t, int c) const { return b0[c] * (1 + 0.5 * std::sin(3 * t)); }
};

// A body clamped on one side, with a body force that varies in time, a
// traction, one nodal force, falling on a plane a little below it: free
// flight first, then contact (the contact facets share nodes with the
// clamped side in 2D and 3D).
Scene make_scene(int dim, int degree, int scheme, const double *params, bool lumped, double tau,
                 bool redistributed = false) {
  Scene s;
  s.dim = dim;
  nd_mesh m = nullptr;
  const double up[3] = {dim == 1 ? 1.0 : 0.0, dim == 1 ? 0.0 : 1.0, 0}, o[3] = {dim == 1 ? -0.01 : 0.0, dim == 1 ? 0.0 : -0.01, 0};
  if (dim == 1) {
    const double lo0 = -0.5, hi0 = 0.5, lo1 = 0.5, hi1 = 1.5;
    ND_OK_OR_FAIL(nd_mesh_create_interval(16, 0.0, 1.0, &m));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, &lo0, &hi0));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, &lo1, &hi1));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 3, &lo0, &hi0));  // the traction on the contact end
    s.b0[0] = -1, s.g[0] = -0.2;
  } else {
    const double lo[3] = {0, 0, 0}, hi[3] = {2, 1, 1};
    const double l1[3] = {-1, -1e-3, -1}, h1[3] = {3, 1e-3, 3};    // y = 0: contact
    const double l2[3] = {-1e-3, -1, -1}, h2[3] = {1e-3, 2, 2};    // x = 0: clamped
    const double l3[3] = {-1, 1 - 1e-3, -1}, h3[3] = {3, 1 + 1e-3, 3};  // y = 1: traction
    if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle(6, 3, lo, hi, &m));
    if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box(4, 2, 2, lo, hi, &m));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, l1, h1));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, l2, h2));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 3, l3, h3));
    s.volume = 2, s.top = 2;  // 2D: per unit thickness
    s.b0[1] = -2, s.g[0] = 0.3, s.g[1] = -0.5;
  }
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &s.p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  nd_problem p = s.p;
  ND_OK_OR_FAIL(nd_problem_set_material(p, 10.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 2));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
  ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, redistributed));
  ND_OK_OR_FAIL(nd_problem_set_newton(p, 0, 0, 50));  // to round-off: the balance is exact only then
  ND_OK_OR_FAIL(nd_problem_set_neumann(p, 3, s.g));
  double b[3];
  for (int c = 0; c < 3; ++c) b[c] = s.body(0, c);
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, b));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  s.nodal.assign(static_cast<size_t>(n * dim), 0.0);
  s.nodal[static_cast<size_t>((n / 2) * dim)] = 0.1;  // some node, clamped or not
  s.nodal[static_cast<size_t>((n - 1) * dim + dim - 1)] = -0.15;
  ND_OK_OR_FAIL(nd_problem_set_nodal_forces(p, n, s.nodal.data()));
  return s;
}

std::vector<double> field(nd_problem p, int which) {
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  int dim = 1;
  dim = p->problem.space().dim;
  std::vector<double> f(static_cast<size_t>(n * dim));
  ND_OK_OR_FAIL(nd_get_field(p, which, n, f.data()));
  return f;
}

std::vector<double> pressure_signs(nd_problem p) {
  int64_t nq = 0;
  ND_OK_OR_FAIL(nd_problem_get_contact_point_count(p, &nq));
  std::vector<double> lam(static_cast<size_t>(nq));
  ND_OK_OR_FAIL(nd_get_contact_pressure(p, nq, lam.data()));
  for (double &x : lam) x = x < 0;
  return lam;
}

// sum over all rows of the full mass times a (free on entry, full n_dofs
// vector), per component: the column sums of M over free and clamped rows
std::vector<double> mass_sum(nd_problem p, const std::vector<double> &a_full) {
  const nd::Discretization &d = p->problem.discretization();
  const int dim = p->problem.space().dim;
  std::vector<double> a(static_cast<size_t>(d.dofs.n_free));
  d.dofs.restrict_to_free(a_full.data(), a.data());
  std::vector<double> colsum(a.size(), 0.0);
  auto add = [&](const nd::Csr &M) {
    for (int64_t i = 0; i < M.n; ++i)
      for (int64_t k = M.ptr[i]; k < M.ptr[i + 1]; ++k) colsum[M.col[k]] += M.val[k];
  };
  add(d.M);
  if (d.clamped && !d.lumped) add(d.clamped->M);
  std::vector<double> s(3, 0.0);
  for (size_t dof = 0; dof < d.dofs.free.size(); ++dof)
    if (d.dofs.free[dof] >= 0) s[dof % dim] += colsum[d.dofs.free[dof]] * a[d.dofs.free[dof]];
  return s;
}

std::vector<double> component_sums(const std::vector<double> &f, int dim, double *abs_sum) {
  std::vector<double> s(3, 0.0);
  for (size_t i = 0; i < f.size(); ++i) {
    s[i % dim] += f[i];
    *abs_sum += std::fabs(f[i]);
  }
  return s;
}

struct SchemeCase {
  int scheme;
  double params[2];
  bool lumped;
  double tau;
  double a;  // the weight of t^n in the balance (TimeScheme::mean_weight)
  double am; // generalized-alpha's alpha_m (0 otherwise)
  bool redistributed = false;  // mass redistribution: explicit steps solve the massless DOFs' equilibrium
  int steps = 60;
};

START_TEST(every_scheme_balances_forces_and_momentum) {
  const double rho = 0.8, af = rho / (rho + 1), am = (2 * rho - 1) / (rho + 1);
  const SchemeCase cases[] = {{ND_SCHEME_THETA, {0.5, 0}, false, 0.01, 0, 0},
                              {ND_SCHEME_THETA, {1, 0}, false, 0.01, 0, 0},
                              {ND_SCHEME_NEWMARK, {0.25, 0.5}, false, 0.01, 0, 0},
                              {ND_SCHEME_NEWMARK, {0, 0.5}, true, 5e-4, 0, 0, false, 800},
                              {ND_SCHEME_HYBRID, {0, 0}, false, 0.01, 0.5, 0},
                              {ND_SCHEME_GENERALIZED_ALPHA, {rho, 0}, false, 0.01, af, am},
                              // mass redistribution: the massless DOFs' rows are the static
                              // equilibrium (explicit: solved by Newton to round-off here)
                              {ND_SCHEME_NEWMARK, {0.25, 0.5}, false, 0.01, 0, 0, true},
                              {ND_SCHEME_NEWMARK, {0, 0.5}, true, 5e-4, 0, 0, true, 800},
                              {ND_SCHEME_NEWMARK, {0, 0.5}, false, 2.5e-4, 0, 0, true, 1600}};
  double worst = 0;
  for (int dim = 1; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree)
      for (const SchemeCase &sc : cases) {
        Scene s = make_scene(dim, degree, sc.scheme, sc.params, sc.lumped, sc.tau, sc.redistributed);
        nd_problem p = s.p;
        const int steps = sc.steps;
        int in_contact = 0, in_flight = 0;
        ND_OK_OR_FAIL(nd_problem_setup(p));
        // t^0: Remark 3.2's equilibrium
        std::vector<double> U = field(p, ND_FIELD_DISPLACEMENT), V = field(p, ND_FIELD_VELOCITY),
                            A = field(p, ND_FIELD_ACCELERATION), C = field(p, ND_FIELD_CONTACT_FORCE);
        std::vector<double> sig = pressure_signs(p);
        for (int k = 0; k <= steps; ++k) {
          const double t1 = k * sc.tau, t0 = (k - 1) * sc.tau;
          std::vector<double> Abar = A, Cbar = C;
          double a = 0;
          if (k > 0) {  // the step k-1 -> k
            a = sc.a;
            std::vector<double> V1 = field(p, ND_FIELD_VELOCITY), A1 = field(p, ND_FIELD_ACCELERATION),
                                C1 = field(p, ND_FIELD_CONTACT_FORCE), sig1 = pressure_signs(p);
            for (size_t i = 0; i < Abar.size(); ++i) {
              if (sc.scheme == ND_SCHEME_HYBRID)
                Abar[i] = (V1[i] - V[i]) / sc.tau;
              else
                Abar[i] = (1 - sc.am) * A1[i] + sc.am * A[i];
              Cbar[i] = (1 - a) * C1[i] + a * C[i];
            }
            // the scheme's mean contact force is this mean only when no point
            // changed sides during the step (the contact term is piecewise linear)
            const bool persistent = a == 0 || sig1 == sig;
            V = V1, A = A1, C = C1, sig = sig1;
            if (!persistent) goto next;
          } else if (sc.redistributed) {
            goto next;  // t^0: the given U^0 need not be in equilibrium on the massless DOFs
          }
          {
            const std::vector<double> R = field(p, ND_FIELD_REACTION);
            double scale = 0;
            const std::vector<double> lhs = mass_sum(p, Abar), sr = component_sums(R, dim, &scale),
                                      sc_ = component_sums(Cbar, dim, &scale);
            std::vector<double> mabs(Abar.size());
            for (size_t i = 0; i < Abar.size(); ++i) mabs[i] = std::fabs(Abar[i]);
            const std::vector<double> ma = mass_sum(p, mabs);
            for (int c = 0; c < dim; ++c) {
              double F = 0;
              for (size_t i = c; i < s.nodal.size(); i += dim) F += s.nodal[i];
              F += s.g[c] * s.top + s.volume * ((1 - a) * s.body(t1, c) + a * (k > 0 ? s.body(t0, c) : 0));
              const double sc2 = scale + ma[c] + std::fabs(F);
              const double err = std::fabs(lhs[c] - (sr[c] + sc_[c] + F)) / sc2;
              worst = std::max(worst, err);
              ck_assert_msg(err < 1e-12, "%dD P%d scheme %d (%g)%s%s step %d component %d: sum M Abar = %.17g, "
                            "reactions %.17g + contact %.17g + loads %.17g (relative error %.3g)",
                            dim, degree, sc.scheme, sc.params[0], sc.lumped ? " lumped" : "",
                            sc.redistributed ? " redistributed" : "", k, c, lhs[c], sr[c], sc_[c], F, err);
            }
            double active = 0;
            ND_OK_OR_FAIL(nd_get_scalar(p, ND_ACTIVE_POINTS, &active));
            (active > 0 ? in_contact : in_flight) += 1;
          }
        next:
          if (k == steps) break;
          double b[3];
          for (int c = 0; c < 3; ++c) b[c] = s.body((k + 1) * sc.tau, c);
          ND_OK_OR_FAIL(nd_problem_set_body_force(p, b));  // F^{k+1}
          ND_OK_OR_FAIL(nd_step(p));
        }
        // redistributed P1 in 2D and 3D: the massless contact nodes sag statically
        // under their share of the body force and touch from the first steps
        ck_assert_msg(in_contact > 5 && (in_flight > 5 || sc.redistributed), "%dD P%d scheme %d: %d steps checked in contact, %d in flight",
                      dim, degree, sc.scheme, in_contact, in_flight);
        ND_OK_OR_FAIL(nd_problem_destroy(&p));
      }
  std::printf("balance: worst relative error %.3g\n", worst);
}
END_TEST

// A new point with the same normal changes the gaps only: the discretization,
// the integrator and its factorization stay the same objects.
START_TEST(moving_the_point_rebuilds_nothing) {
  const double nm[2] = {0.25, 0.5};
  Scene s = make_scene(2, 1, ND_SCHEME_NEWMARK, nm, false, 0.01);
  nd::Problem &pr = s.p->problem;
  ND_OK_OR_FAIL(nd_step(s.p));
  const nd::Discretization *d = &pr.discretization();
  const nd::Integrator *in = pr.integrator();
  const nd::Factorization *f = in->A_factor.get();
  const double up[2] = {0, 1};
  for (int k = 0; k < 10; ++k) {
    const double o[2] = {0.3, -0.01 + 0.002 * k};
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(s.p, 1, o, up));
    ND_OK_OR_FAIL(nd_step(s.p));
    ck_assert_ptr_eq(&pr.discretization(), d);
    ck_assert_ptr_eq(pr.integrator(), in);
    ck_assert_ptr_eq(pr.integrator()->A_factor.get(), f);
  }
  // another normal is another obstacle: its rows are assembled anew
  const std::vector<double> row = pr.discretization().contact.a[0].val;
  const size_t nq = pr.discretization().contact.size();
  const double tilted[2] = {0.1, 1}, o[2] = {0, -0.01};
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(s.p, 1, o, tilted));
  ND_OK_OR_FAIL(nd_step(s.p));
  ck_assert(pr.discretization().contact.a[0].val != row);
  ck_assert_uint_eq(pr.discretization().contact.size(), nq);  // replaced, not added
  ND_OK_OR_FAIL(nd_problem_destroy(&s.p));
}
END_TEST

}  // namespace

int main(void) {
  Suite *s = suite_create("forces");
  TCase *tc = tcase_create("forces");
  tcase_set_timeout(tc, 600);
  tcase_add_test(tc, every_scheme_balances_forces_and_momentum);
  tcase_add_test(tc, moving_the_point_rebuilds_nothing);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
