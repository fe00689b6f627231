// The time-scheme registry, and generalized-alpha's damping measured on the
// bar's highest mode against the scheme's amplification matrix, derived here
// independently (single-degree-of-freedom form of Chung & Hulbert 1993).
#include <lapacke.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <limits>
#include <cstdio>
#include <vector>

#include "capi/handles.hpp"
#include "common/error.hpp"
#include "nitschedyn.h"
#include "solve/contact_law.hpp"
#include "time/scheme.hpp"
#include "time/state.hpp"
#include "time/step_control.hpp"
// check.h last: it defines a macro `fail` that the library's headers would meet
#include <check.h>

#include "testutil.h"

namespace {

// Every ND_SCHEME_* of the header is in the registry, with a valid parameter
// set that makes it; ids next to them are refused with ND_ERR_SCHEME.
START_TEST(every_listed_scheme_is_registered) {
  int count = 0, max_id = 0;
#define ND_CHECK_SCHEME_(name, value, text)                                        \
  {                                                                                \
    const int n = nd::scheme_parameter_count(name);                                \
    ck_assert_int_ge(n, 0);                                                        \
    const auto scheme = nd::make_scheme(name, std::vector<double>(n, 0.5));        \
    ck_assert_ptr_nonnull(scheme.get());                                           \
    ++count;                                                                       \
    max_id = value > max_id ? value : max_id;                                      \
  }
  ND_SCHEME_LIST(ND_CHECK_SCHEME_)
#undef ND_CHECK_SCHEME_
  ck_assert_int_eq(count, 4);
  for (int id : {0, -1, max_id + 1, 1000}) {
    try {
      nd::scheme_parameter_count(id);
      ck_abort_msg("scheme %d accepted", id);
    } catch (const nd::Error &e) {
      ck_assert_int_eq(e.code(), ND_ERR_SCHEME);
    }
  }
  try {  // a wrong parameter count is refused, never read past
    nd::make_scheme(ND_SCHEME_NEWMARK, {0.25});
    ck_abort_msg("Newmark with one parameter accepted");
  } catch (const nd::Error &e) {
    ck_assert_int_eq(e.code(), ND_ERR_SCHEME);
  }
}
END_TEST

// The contact term a scheme's rule gives with the frictionless law is, bit
// for bit, the scheme's term as the paper and docs/design.md §3 write it
// (what each scheme computed itself before the rule was the law's): [P]_+
// (theta, Newmark), [Y]_+ with slope 1 - alpha_f at Y = (1 - alpha_f) P +
// alpha_f P^n (generalized-alpha), H(P^n) [(P^n + P)/2]_+ + H(-P^n)
// ([P^n]_+ + [P]_+)/2 with H(0) = 1/2 (hybrid); ContactLaw::law gives it
// whichever way it takes (inline where the rule is AtEnd); a rule AtEnd is
// [P]_+, which the passes then apply inline. Signed zeros, subnormals, NaN.
START_TEST(positive_part_flag_tells_the_truth) {
  const struct {
    int id;
    std::vector<double> params;
  } cases[] = {{ND_SCHEME_THETA, {0.5}},      {ND_SCHEME_THETA, {1.0}},          {ND_SCHEME_NEWMARK, {0.25, 0.5}},
               {ND_SCHEME_NEWMARK, {0.0, 0.5}}, {ND_SCHEME_HYBRID, {}},          {ND_SCHEME_GENERALIZED_ALPHA, {0.0}},
               {ND_SCHEME_GENERALIZED_ALPHA, {0.5}}, {ND_SCHEME_GENERALIZED_ALPHA, {1.0}}};
  const double tiny = std::numeric_limits<double>::denorm_min(), nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> Ps = {-3, -1, -tiny, -0.0, 0.0, tiny, 1e-300, 0.5, 2, nan};
  std::vector<double> Pn = {-2, -0.5, -0.0, 0.0, tiny, 0.5, 2};
  // the schemes' terms as written (the bits of the former TimeScheme::contact)
  auto written = [](int id, double rho, double P, double pn, double &value, double &slope) {
    if (id == ND_SCHEME_HYBRID) {
      const double h_pos = pn > 0 ? 1 : pn < 0 ? 0 : 0.5, h_neg = 1 - h_pos;
      const double mid = 0.5 * (pn + P);
      value = h_pos * (mid > 0 ? mid : 0) + h_neg * 0.5 * ((pn > 0 ? pn : 0) + (P > 0 ? P : 0));
      slope = h_pos * (mid > 0 ? 0.5 : 0) + h_neg * (P > 0 ? 0.5 : 0);
    } else if (id == ND_SCHEME_GENERALIZED_ALPHA) {
      const double af = rho / (rho + 1), Y = (1 - af) * P + af * pn;
      value = Y > 0 ? Y : 0;
      slope = Y > 0 ? 1 - af : 0;
    } else {
      value = P > 0 ? P : 0;
      slope = P > 0 ? 1 : 0;
    }
  };
  nd::ContactPoints cp;  // (the law reads only P^n from its point)
  int positive = 0, other = 0;
  for (const auto &c : cases) {
    const auto scheme = nd::make_scheme(c.id, c.params);
    bool differs = false;
    for (size_t k = 0; k < Pn.size(); ++k) {
      nd::ContactLaw law{&cp, 1.0, scheme.get(), &Pn};
      for (double P : Ps) {
        double v, sl, lv, lsl, wv, wsl;
        nd::frictionless_law().over_step(scheme->contact_rule(), P, Pn[k], v, sl);
        written(c.id, c.params.empty() ? 0 : c.params[0], P, Pn[k], wv, wsl);
        law.law(k, P, lv, lsl);
        ck_assert_msg(std::memcmp(&v, &wv, sizeof v) == 0 && std::memcmp(&sl, &wsl, sizeof sl) == 0,
                      "scheme %d at P = %g, P^n = %g: (%g, %g), written (%g, %g)", c.id, P, Pn[k], v, sl, wv, wsl);
        ck_assert(std::memcmp(&lv, &v, sizeof v) == 0 && std::memcmp(&lsl, &sl, sizeof sl) == 0);
        differs |= v != (P > 0 ? P : 0) || sl != (P > 0 ? 1 : 0);
      }
    }
    if (scheme->contact_rule().kind == nd::TimeRule::AtEnd) {
      ck_assert_msg(!differs, "scheme %d says [P]_+ and is not", c.id);
      ++positive;
    } else {
      other += differs;
    }
  }
  ck_assert_int_eq(positive, 4);  // theta and Newmark
  ck_assert_int_eq(other, 3);     // hybrid, generalized-alpha at rho_inf 0.5 and 1
}
END_TEST

// Generalized-alpha on m u'' + k u = 0 (m = 1, k = w^2), state x = (u, v, a):
//   (1-am) a1 + am a0 + w^2 ((1-af) u1 + af u0) = 0
//   u1 = u0 + tau v0 + tau^2 ((1/2 - beta) a0 + beta a1),  v1 = v0 + tau ((1-g) a0 + g a1)
struct Alpha {
  double am, af, g, beta;
  explicit Alpha(double rho)
      : am((2 * rho - 1) / (rho + 1)), af(rho / (rho + 1)), g(0.5 - am + af), beta(0.25 * (1 - am + af) * (1 - am + af)) {}
  void step(double w2, double tau, const double x0[3], double x1[3]) const {
    const double a1 = -(am * x0[2] + w2 * (x0[0] + (1 - af) * (tau * x0[1] + tau * tau * (0.5 - beta) * x0[2]))) /
                      (1 - am + w2 * (1 - af) * tau * tau * beta);
    x1[0] = x0[0] + tau * x0[1] + tau * tau * ((0.5 - beta) * x0[2] + beta * a1);
    x1[1] = x0[1] + tau * ((1 - g) * x0[2] + g * a1);
    x1[2] = a1;
  }
  // the eigenvalues of the 3x3 amplification matrix
  std::vector<std::complex<double>> eigenvalues(double w2, double tau) const {
    double G[9];  // column-major: column j = one step from e_j
    for (int j = 0; j < 3; ++j) {
      double e[3] = {0, 0, 0};
      e[j] = 1;
      step(w2, tau, e, &G[3 * j]);
    }
    double wr[3], wi[3];
    ck_assert_int_eq(LAPACKE_dgeev(LAPACK_COL_MAJOR, 'N', 'N', 3, G, 3, wr, wi, nullptr, 1, nullptr, 1), 0);
    return {{wr[0], wi[0]}, {wr[1], wi[1]}, {wr[2], wi[2]}};
  }
  double spectral_radius(double w2, double tau) const {
    double r = 0;
    for (auto z : eigenvalues(w2, tau)) r = std::max(r, std::abs(z));
    return r;
  }
};

START_TEST(amplification_matrix_tends_to_rho_inf) {
  // the derivation above, checked at its two ends: no damping at w tau -> 0,
  // spectral radius rho_inf at w tau -> infinity
  for (double rho : {0.0, 0.5, 0.8, 1.0}) {
    const Alpha ga(rho);
    ck_assert_double_eq_tol(ga.spectral_radius(1e-8, 1.0), 1.0, 1e-6);
    // at infinity -rho_inf is a triple, defective eigenvalue: round-off moves
    // it by about eps^(1/3) = 6e-6, hence the tolerance
    ck_assert_double_eq_tol(ga.spectral_radius(1e20, 1.0), rho, 1e-4);
  }
}
END_TEST

// The bar (P1, 20 cells, clamped at x = 1, no obstacle) started in its
// highest mode phi (K phi = w^2 M phi, phi' M phi = 1): the scheme applied to
// M U'' + K U = 0 acts on the modal coordinates (q, q', q'') = phi' M (U, V, A)
// exactly as on the single oscillator, so they must follow x_n = G^n x_0, and
// their measured decay per step is the spectral radius of G.
START_TEST(highest_mode_decays_at_the_spectral_radius) {
  for (double rho : {1.0, 0.8, 0.5, 0.0}) {
    nd_mesh m = nullptr;
    nd_problem p = nullptr;
    const double lo = 0.5, hi = 1.5;
    ND_OK_OR_FAIL(nd_mesh_create_interval(20, 0.0, 1.0, &m));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, &lo, &hi));
    ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
    ND_OK_OR_FAIL(nd_mesh_destroy(&m));
    ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.0, 1.0));
    ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 2));
    ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_GENERALIZED_ALPHA, &rho));
    const nd::Discretization &d = p->problem.discretization();
    const int n = static_cast<int>(d.dofs.n_free);
    std::vector<double> K(n * n, 0.0), M(n * n, 0.0), w2(n);
    for (int i = 0; i < n; ++i)
      for (int64_t k = d.K.ptr[i]; k < d.K.ptr[i + 1]; ++k) {
        K[i * n + d.K.col[k]] = d.K.val[k];
        M[i * n + d.M.col[k]] = d.M.val[k];
      }
    const std::vector<double> Mcopy = M;
    ck_assert_int_eq(LAPACKE_dsygv(LAPACK_COL_MAJOR, 1, 'V', 'U', n, K.data(), n, M.data(), n, w2.data()), 0);
    const double *phi = &K[(n - 1) * n];  // eigenvectors are M-orthonormal
    const double omega2 = w2[n - 1], tau = 3.0 / std::sqrt(omega2);  // w tau = 3
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
    int64_t nodes = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
    std::vector<double> full(nodes), u(n);
    d.dofs.extend_to_full(phi, full.data());
    ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nodes, full.data(), nullptr));
    auto modal = [&](int field) {  // phi' M x
      ND_OK_OR_FAIL(nd_get_field(p, field, nodes, full.data()));
      p->problem.discretization().dofs.restrict_to_free(full.data(), u.data());
      double s = 0;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) s += phi[i] * Mcopy[i * n + j] * u[j];
      return s;
    };
    const Alpha ga(rho);
    double x[3] = {1, 0, -omega2};  // A^0 from the equilibrium (Remark 3.2)
    std::vector<double> q;
    double worst = 0;
    for (int step = 1; step <= 120; ++step) {
      ND_OK_OR_FAIL(nd_step(p));
      double next[3];
      ga.step(omega2, tau, x, next);
      std::copy(next, next + 3, x);
      const double got[3] = {modal(ND_FIELD_DISPLACEMENT), modal(ND_FIELD_VELOCITY), modal(ND_FIELD_ACCELERATION)};
      const double scale[3] = {1, std::sqrt(omega2), omega2};  // |x_0| in each component
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::fabs(got[k] - x[k]) / scale[k]);
      q.push_back(got[0]);
    }
    // decay per step of the dominant complex pair: for q_n = Re(c z^n),
    // D_n = q_{n+1} q_{n-1} - q_n^2 is proportional to |z|^{2n}. Measured
    // where the mode is still 1e7 times above round-off (at rho_inf = 0 it
    // falls by 0.56 a step) and the third, real root has long died out.
    const double radius = ga.spectral_radius(omega2, tau);
    const size_t N = std::min(q.size() - 2, static_cast<size_t>(std::log(1e-7) / std::log(radius)));
    const double D1 = q[N + 1] * q[N - 1] - q[N] * q[N], D0 = q[N] * q[N - 2] - q[N - 1] * q[N - 1];
    const double measured = std::sqrt(D1 / D0);
    std::printf("rho_inf %.1f, w tau = 3: decay per step measured %.12f (at step %zu), spectral radius %.12f; "
                "per period (%.2f steps) %.6f; modal trajectory off by %.2e\n",
                rho, measured, N, radius, 2 * M_PI / 3.0, std::pow(measured, 2 * M_PI / 3.0), worst);
    ck_assert_msg(worst < 1e-9, "rho_inf %g: the modal trajectory is off by %g", rho, worst);
    if (rho < 1) ck_assert_double_lt(radius, 1.0);
    ck_assert_msg(std::fabs(measured - radius) < 1e-6 * radius, "rho_inf %g: decay %.12g, spectral radius %.12g", rho,
                  measured, radius);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

// A used state's memory handed to the next step (reuse_storage) comes back
// as a new state: every vector empty (its capacity kept, the point of it)
// but the products' four, every other field as State{} has it.
// The first-touch cut reads the points' normal values alone: with friction
// the tangential values follow them in P (here positive, as a sliding
// landing gives), and it read them as points, past its other arrays' ends
// (valgrind found it in the stability suite's adaptive reruns). Point 1 of
// 2 touches at a quarter of the step: u_n from -0.1 at the rate 0.4 over 1.
START_TEST(first_touch_reads_the_normal_values) {
  const std::vector<double> un = {-0.5, -0.1}, rate = {0.4, 0.4}, P_old = {-0.5, -0.1};
  const std::vector<double> P_new = {-0.1, 0.3};
  const double s = nd::first_touch(P_old, P_new, un, rate, 1.0);
  ck_assert_double_eq_tol(s, 0.25, 1e-15);
  std::vector<double> P_old_t = P_old, P_new_t = P_new;
  for (double x : {0.7, 0.9}) P_old_t.push_back(x), P_new_t.push_back(x);  // (the tangential values)
  ck_assert_double_eq(nd::first_touch(P_old_t, P_new_t, un, rate, 1.0), s);
}
END_TEST

START_TEST(reused_storage_is_a_new_state) {
  nd::State used;
  nd::Products used_p;  // (the products, a cache held beside the state)
  used.t = 1, used.n = 3, used.t_ref = 0.5, used.tau_ref = 0.25, used.n_ref = 1;
  for (std::vector<double> *v : {&used.U, &used.V, &used.A, &used.F_fixed, &used.gap, &used.reaction, &used.phi,
                                 &used_p.MU, &used_p.MV, &used_p.MA, &used_p.KU,
                                 &used_p.points.P, &used_p.points.un, &used.tangent_log.x})
    v->assign(5, 2.0);
  used.tangent_log.i.assign(5, 7);
  used.partial = used.A_valid = used_p.points.partial = used_p.points.summed = true;
  used.F = std::make_shared<const std::vector<double>>(5, 1.0);
  used_p.points.ref = std::make_shared<const nd::PointReference>();
  used_p.of = 9, used_p.n = 5, used_p.kinetic = used_p.strain = 4;
  used_p.points.sums.force = 6;
  used.W = used.W_obstacle = 8, used.last_iterations = 2, used.total_iterations = 10;
  used.guard.E0 = used.guard.budget = 3;
  const double *U_memory = used.U.data();

  const nd::State s = nd::reuse_storage(std::move(used));
  const nd::Products p = nd::reuse_storage(std::move(used_p));
  const nd::State fresh;
  const nd::Products fresh_p;
  ck_assert_ptr_eq(s.U.data(), U_memory);  // the memory, not a copy
  for (const std::vector<double> *v : {&s.U, &s.V, &s.A, &s.F_fixed, &s.gap, &s.reaction, &s.phi,
                                       &p.points.P, &p.points.un, &s.tangent_log.x}) {
    ck_assert(v->empty());
    ck_assert_uint_ge(v->capacity(), 5);
  }
  // the products' vectors keep their sizes (the next pass writes every
  // entry, not filled with zeros first); of = 0 below says they are not computed
  for (const std::vector<double> *v : {&p.MU, &p.MV, &p.MA, &p.KU})
    ck_assert_uint_eq(v->size(), 5);
  ck_assert(s.tangent_log.i.empty());
  ck_assert(s.t == fresh.t && s.n == fresh.n && s.t_ref == fresh.t_ref && s.tau_ref == fresh.tau_ref &&
            s.n_ref == fresh.n_ref && s.W == fresh.W && s.W_obstacle == fresh.W_obstacle);
  ck_assert(s.partial == fresh.partial && s.A_valid == fresh.A_valid);
  ck_assert(!s.F && !p.rows && !p.points.ref);
  ck_assert(p.of == fresh_p.of && p.n == fresh_p.n &&
            p.kinetic == fresh_p.kinetic && p.strain == fresh_p.strain);
  ck_assert(!p.points.partial && !p.points.summed && p.points.sums.force == 0);
  ck_assert(s.last_iterations == fresh.last_iterations && s.total_iterations == fresh.total_iterations);
  ck_assert(s.guard.E0 == fresh.guard.E0 && s.guard.budget == fresh.guard.budget);
}
END_TEST

}  // namespace

int main(void) {
  Suite *s = suite_create("schemes");
  TCase *tc = tcase_create("registry_and_damping");
  tcase_add_test(tc, every_listed_scheme_is_registered);
  tcase_add_test(tc, positive_part_flag_tells_the_truth);
  tcase_add_test(tc, amplification_matrix_tends_to_rho_inf);
  tcase_add_test(tc, highest_mode_decays_at_the_spectral_radius);
  tcase_add_test(tc, reused_storage_is_a_new_state);
  tcase_add_test(tc, first_touch_reads_the_normal_values);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
