/* Rayleigh damping C = alpha M + beta K (docs/design.md §10.5) and plane stress.
 *  - free decay of a mode: a bar clamped at both ends started in its first
 *    discrete mode stays in it (M, K and C share the eigenvector sin(pi x)),
 *    and its amplitude follows the scheme's own recursion for
 *    x'' + (alpha + beta w^2) x' + w^2 x = 0 to round-off, for every scheme
 *    (theta 1/2, 1, 0; Newmark implicit and explicit, with beta = 0 and
 *    beta > 0; hybrid; generalized-alpha), consistent and lumped mass;
 *  - the decay rate of the trapezoidal schemes is (alpha + beta w^2)/2 to
 *    their O(tau^2) error;
 *  - hybrid, Theta = 1: E_Theta + D_damping - W - W_obstacle never increases,
 *    and is conserved to round-off by every step in which the contact point
 *    does not change sides;
 *  - ND_MATRIX_DAMPING is alpha M + beta K; damping 0, 0 is bitwise the
 *    undamped run; a restart is bitwise;
 *  - plane stress: uniaxial stress on a free rectangle is an equilibrium. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

/* ---- the mode's scalar recursions (m = 1, c = 2 zeta, k = w^2) ---------- */

typedef struct {
  double x, v, a;
} sdof;

/* a(next) of an affine residual f(a1): a1 = -f(0)/(f(1) - f(0)) */
typedef double (*residual_fn)(const double *prm, sdof old, double a1, sdof *next);

/* Newmark(beta, gamma): x1 = x0 + tau v0 + tau^2((1/2 - beta) a0 + beta a1),
   v1 = v0 + tau((1 - gamma) a0 + gamma a1); generalized-alpha: the balance at
   (1 - alpha_m) a1 + alpha_m a0, (1 - alpha_f)(x1, v1) + alpha_f (x0, v0). */
/* prm: tau, c, k, beta, gamma, alpha_m, alpha_f */
static double newmark_residual(const double *prm, sdof o, double a1, sdof *n) {
  const double tau = prm[0], c = prm[1], k = prm[2], be = prm[3], ga = prm[4], am = prm[5], af = prm[6];
  n->a = a1;
  n->x = o.x + tau * o.v + tau * tau * ((0.5 - be) * o.a + be * a1);
  n->v = o.v + tau * ((1 - ga) * o.a + ga * a1);
  return (1 - am) * a1 + am * o.a + c * ((1 - af) * n->v + af * o.v) + k * ((1 - af) * n->x + af * o.x);
}
/* theta: x1 = x0 + tau(theta v1 + (1-theta) v0), v1 = v0 + tau(theta a1 + (1-theta) a0),
   a1 + c v1 + k x1 = 0; theta = 0 as well (then a1 does not enter x1, v1) */
static double theta_residual(const double *prm, sdof o, double a1, sdof *n) {
  const double tau = prm[0], c = prm[1], k = prm[2], th = prm[3];
  n->a = a1;
  n->v = o.v + tau * (th * a1 + (1 - th) * o.a);
  n->x = o.x + tau * (th * n->v + (1 - th) * o.v);
  return a1 + c * n->v + k * n->x;
}
/* hybrid (Crank-Nicolson): x1 - x0 = tau (v1 + v0)/2, (v1 - v0)/tau + c (v1 + v0)/2 + k (x1 + x0)/2 = 0;
   the unknown is a1 = (v1 - v0)/tau */
static double hybrid_residual(const double *prm, sdof o, double a1, sdof *n) {
  const double tau = prm[0], c = prm[1], k = prm[2];
  n->v = o.v + tau * a1;
  n->x = o.x + 0.5 * tau * (n->v + o.v);
  n->a = a1;
  return a1 + c * 0.5 * (n->v + o.v) + k * 0.5 * (n->x + o.x);
}

static sdof sdof_step(residual_fn f, const double *prm, sdof o) {
  sdof n0, n1;
  const double f0 = f(prm, o, 0.0, &n0), f1 = f(prm, o, 1.0, &n1);
  sdof n;
  f(prm, o, -f0 / (f1 - f0), &n);
  return n;
}

/* ---- the bar clamped at both ends ---------------------------------------- */

enum { NX = 20 };

typedef struct {
  int scheme;
  double params[2];
  int lumped;
  double alpha, beta;
  int steps;
  int unstable; /* theta = 0: the guard allows it */
} damped_case;

static nd_problem clamped_bar(const damped_case *dc, double tau, double *phi, int64_t *n_nodes) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo0 = -0.5, hi0 = 0.5, lo1 = 0.5, hi1 = 1.5;
  ND_OK_OR_FAIL(nd_mesh_create_interval(NX, 0.0, 1.0, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, &lo0, &hi0));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, &lo1, &hi1));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.0, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 2));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, dc->scheme, dc->params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, dc->lumped));
  ND_OK_OR_FAIL(nd_problem_set_damping(p, dc->alpha, dc->beta));
  if (dc->unstable) ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_UNSTABLE_SCHEME, 0));
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, n_nodes));
  ck_assert_int_eq(*n_nodes, NX + 1);
  double x[NX + 1];
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, *n_nodes, x));
  for (int i = 0; i <= NX; ++i) phi[i] = sin(M_PI * x[i]);
  return p;
}

/* the mode's amplitude: the projection of the nodal values on phi */
static double amplitude(nd_problem p, int field, const double *phi) {
  double u[NX + 1], num = 0, den = 0;
  ND_OK_OR_FAIL(nd_get_field(p, field, NX + 1, u));
  for (int i = 0; i <= NX; ++i) num += u[i] * phi[i], den += phi[i] * phi[i];
  return num / den;
}

/* w^2 of sin(pi x) on the uniform P1 mesh: K phi = (E/h)(2 - 2 cos t) phi,
   M phi = rho h (4 + 2 cos t)/6 phi (consistent) or rho h phi (lumped), t = pi h */
static double omega2(int lumped) {
  const double h = 1.0 / NX, t = M_PI * h, k = (2 - 2 * cos(t)) / h;
  return k / (lumped ? h : h * (4 + 2 * cos(t)) / 6);
}

static const damped_case kCases[] = {
    {ND_SCHEME_THETA, {0.5, 0}, 0, 0.2, 0.02, 300, 0},
    {ND_SCHEME_THETA, {1, 0}, 0, 0.2, 0.02, 300, 0},
    {ND_SCHEME_THETA, {0, 0}, 1, 0.2, 0.02, 40, 1},
    {ND_SCHEME_NEWMARK, {0.25, 0.5}, 0, 0.2, 0.02, 300, 0},
    {ND_SCHEME_NEWMARK, {0.3025, 0.6}, 1, 0.5, 0.01, 300, 0},
    {ND_SCHEME_NEWMARK, {0, 0.5}, 1, 0.3, 0, 300, 0},     /* explicit, alpha only: a division */
    {ND_SCHEME_NEWMARK, {0, 0.5}, 1, 0.2, 0.002, 300, 0}, /* explicit, beta > 0: M + gamma tau C factored */
    {ND_SCHEME_NEWMARK, {0, 0.6}, 0, 0.2, 0.002, 300, 0},
    {ND_SCHEME_HYBRID, {0, 0}, 0, 0.2, 0.02, 300, 0},
    {ND_SCHEME_HYBRID, {0, 0}, 1, 0, 0.05, 300, 0},
    {ND_SCHEME_GENERALIZED_ALPHA, {0.8, 0}, 0, 0.2, 0.02, 300, 0},
    {ND_SCHEME_GENERALIZED_ALPHA, {1, 0}, 1, 0.2, 0.02, 300, 0},
};
enum { N_CASES = sizeof kCases / sizeof kCases[0] };

/* the scheme's recursion for the mode, and its parameters */
static residual_fn recursion(const damped_case *dc, double tau, double w2, double *prm) {
  prm[0] = tau, prm[1] = dc->alpha + dc->beta * w2, prm[2] = w2;
  if (dc->scheme == ND_SCHEME_THETA) {
    prm[3] = dc->params[0];
    return theta_residual;
  }
  if (dc->scheme == ND_SCHEME_HYBRID) return hybrid_residual;
  double be = dc->params[0], ga = dc->params[1], am = 0, af = 0;
  if (dc->scheme == ND_SCHEME_GENERALIZED_ALPHA) {
    const double rho = dc->params[0];
    am = (2 * rho - 1) / (rho + 1), af = rho / (rho + 1);
    ga = 0.5 - am + af, be = 0.25 * (1 - am + af) * (1 - am + af);
  }
  prm[3] = be, prm[4] = ga, prm[5] = am, prm[6] = af;
  return newmark_residual;
}

/* The library's amplitudes x_n, v_n against the recursion's. Round-off:
   every step solves with a matrix of condition number below 10 here
   (c M + K_Theta + damping C with c >= 1/tau^2 = 1e4, w_max^2 <= 12 NX^2),
   so each step's solve adds a few eps to the terms it sums; those are
   c |x| and s |v|, c <= 4/tau^2 the mass coefficient and s <= 4/tau the
   velocity slope (velocity_slope): relative to x that is 1 + tau^2 c + tau s
   <= 9, and 16 eps each: at most 144 n eps max|x| after n steps. V is taken
   from U with the slope s, multiplying U's round-off by s: the same bound
   for v/(w + 4/tau). */
START_TEST(mode_decays_as_the_scheme_says) {
  const double tau = 0.01;
  for (int k = 0; k < N_CASES; ++k) {
    const damped_case *dc = &kCases[k];
    double phi[NX + 1];
    int64_t n_nodes = 0;
    nd_problem p = clamped_bar(dc, tau, phi, &n_nodes);
    const double w2 = omega2(dc->lumped), w = sqrt(w2);
    double v0[NX + 1];
    for (int i = 0; i <= NX; ++i) v0[i] = 0.3 * w * phi[i];
    ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n_nodes, phi, v0));
    double prm[7];
    const residual_fn f = recursion(dc, tau, w2, prm);
    sdof s = {1.0, 0.3 * w, 0};
    s.a = -prm[1] * s.v - prm[2] * s.x; /* Remark 3.2 with damping */
    double xmax = 1, err = 0;
    for (int n = 1; n <= dc->steps; ++n) {
      ND_OK_OR_FAIL(nd_step(p));
      s = sdof_step(f, prm, s);
      const double x = amplitude(p, ND_FIELD_DISPLACEMENT, phi), v = amplitude(p, ND_FIELD_VELOCITY, phi);
      xmax = fmax(xmax, fabs(s.x));
      err = fmax(err, fmax(fabs(x - s.x), fabs(v - s.v) / (w + 4 / tau)));
      ck_assert_msg(err <= 144 * n * DBL_EPSILON * xmax,
                    "case %d (scheme %d, %g %g, lumped %d) step %d: x %.17g, recursion %.17g, v %.17g vs %.17g", k,
                    dc->scheme, dc->params[0], dc->params[1], dc->lumped, n, x, s.x, v, s.v);
    }
    printf("damped mode, case %2d (scheme %d, %g %g, lumped %d, alpha %g beta %g): |x - x_rec| <= %.2e after %d "
           "steps, D = %.6g\n",
           k, dc->scheme, dc->params[0], dc->params[1], dc->lumped, dc->alpha, dc->beta, err, dc->steps,
           scalar(p, ND_DISSIPATION_DAMPING));
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* The trapezoidal schemes (theta = 1/2, Newmark(1/4, 1/2), hybrid,
   generalized-alpha rho = 1) multiply the mode by R = (1 + z/2)/(1 - z/2),
   z = lambda tau, lambda = -zeta + i w_d, zeta = (alpha + beta w^2)/2,
   |lambda| = w. The amplitudes satisfy x_{n+1} = t x_n - d x_{n-1} with
   d = |R|^2, so the Casoratian D_n = x_n^2 - x_{n-1} x_{n+1} is multiplied by d
   at every step: rate = -ln(D_N/D_1)/(2 (N-1) tau). ln R = 2 artanh(z/2) =
   z + z^3/12 + z^5/80 + ..., so |rate - zeta| <= w^3 tau^2/12 (1 + (w tau)^2)
   (the tail for w tau < 1/2), plus round-off. */
START_TEST(decay_rate_is_half_alpha_plus_beta_omega2) {
  static const damped_case trapezoidal[] = {
      {ND_SCHEME_THETA, {0.5, 0}, 0, 0.2, 0.02, 400, 0},
      {ND_SCHEME_NEWMARK, {0.25, 0.5}, 1, 0.2, 0.02, 400, 0},
      {ND_SCHEME_HYBRID, {0, 0}, 0, 0.5, 0.01, 400, 0},
      {ND_SCHEME_GENERALIZED_ALPHA, {1, 0}, 0, 0, 0.05, 400, 0},
  };
  const double tau = 0.01;
  for (int k = 0; k < 4; ++k) {
    const damped_case *dc = &trapezoidal[k];
    double phi[NX + 1];
    int64_t n_nodes = 0;
    nd_problem p = clamped_bar(dc, tau, phi, &n_nodes);
    ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n_nodes, phi, NULL));
    const double w2 = omega2(dc->lumped), w = sqrt(w2), zeta = 0.5 * (dc->alpha + dc->beta * w2);
    const int N = dc->steps;
    double *x = malloc(sizeof(double) * (size_t)(N + 1));
    x[0] = 1;
    for (int n = 1; n <= N; ++n) {
      ND_OK_OR_FAIL(nd_step(p));
      x[n] = amplitude(p, ND_FIELD_DISPLACEMENT, phi);
    }
    const double D1 = x[1] * x[1] - x[0] * x[2], DN = x[N - 1] * x[N - 1] - x[N - 2] * x[N];
    free(x);
    const double rate = -log(DN / D1) / (2 * (N - 2) * tau);
    const double bound = w * w2 * tau * tau / 12 * (1 + w2 * tau * tau) + 1e-10;
    printf("decay rate, scheme %d: %.10f, (alpha + beta w^2)/2 = %.10f, |difference| %.2e <= %.2e\n", dc->scheme,
           rate, zeta, fabs(rate - zeta), bound);
    ck_assert_msg(fabs(rate - zeta) <= bound, "scheme %d: rate %.12g, expected %.12g +- %.3g", dc->scheme, rate,
                  zeta, bound);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* Hybrid, Theta = 1 (docs/design.md §10.5): dE_Theta = dW + dW_obstacle - D^n - dD_damping,
   D^n = 0 unless the contact point changes sides. Round-off of the ledger:
   each energy is a sum over n = 2 NX terms, so |dL| <= 8 n eps (E0 + |W| + D). */
START_TEST(hybrid_ledger_with_damping) {
  const double g[1] = {-0.5};
  const int degrees[] = {1, 2};
  for (int d = 0; d < 2; ++d) {
    const int nx = 40;
    const double tau = 1.0 / (2 * nx);
    nd_problem p = nd_test_bar_at(nx, degrees[d], ND_SCHEME_HYBRID, NULL, 1.0, 0.2, tau, 0.0, g);
    ND_OK_OR_FAIL(nd_problem_set_damping(p, 0.05, 0.002));
    ND_OK_OR_FAIL(nd_problem_setup(p));
    double L_prev = scalar(p, ND_ENERGY_AUGMENTED);
    const double E0 = L_prev;
    int was_active = 0, conserved = 0, changes = 0;
    for (int k = 0; k < (int)lround(8.0 / tau); ++k) {
      ND_OK_OR_FAIL(nd_step(p));
      const double W = scalar(p, ND_WORK), D = scalar(p, ND_DISSIPATION_DAMPING);
      const double L = scalar(p, ND_ENERGY_AUGMENTED) + D - W - scalar(p, ND_WORK_OBSTACLE);
      const double tol = 8 * 2 * nx * degrees[d] * DBL_EPSILON * (E0 + fabs(W) + D);
      const int active = scalar(p, ND_ACTIVE_POINTS) > 0;
      ck_assert_msg(L <= L_prev + tol, "P%d step %d: the ledger rose from %.17g to %.17g", degrees[d], k + 1, L_prev,
                    L);
      if (active == was_active) {
        ck_assert_msg(fabs(L - L_prev) <= tol, "P%d step %d (no change of side): ledger %.17g -> %.17g",
                      degrees[d], k + 1, L_prev, L);
        ++conserved;
      } else {
        ++changes;
      }
      was_active = active, L_prev = L;
    }
    const double D = scalar(p, ND_DISSIPATION_DAMPING);
    printf("hybrid ledger P%d: %d steps conserved, %d changes of side, D_damping = %.6g of E0 = %.6g\n", degrees[d],
           conserved, changes, D, E0);
    ck_assert_double_gt(D, 0.01 * E0); /* the damping did dissipate */
    ck_assert_int_ge(changes, 2);      /* impacts and releases */
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* the bar of nd_test_bar for a scheme of the whole-run list (explicit:
   lumped mass, a smaller step), damped unless alpha < 0 */
static nd_problem scheme_bar(const nd_test_scheme *s, double alpha, double beta, double *tau) {
  const int expl = nd_test_is_explicit(s);
  *tau = expl ? 1.0 / 400 : 1.0 / 80;
  nd_problem p = nd_test_bar(40, 1, s->scheme, s->params, 1.0, 0.2, *tau);
  if (expl) ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
  if (alpha >= 0) ND_OK_OR_FAIL(nd_problem_set_damping(p, alpha, beta));
  return p;
}

/* the two bars' displacements have the same bits */
static void same_bits(nd_problem a, nd_problem b, const char *what, int k) {
  double ua[41], ub[41];
  ND_OK_OR_FAIL(nd_get_field(a, ND_FIELD_DISPLACEMENT, 41, ua));
  ND_OK_OR_FAIL(nd_get_field(b, ND_FIELD_DISPLACEMENT, 41, ub));
  ck_assert_msg(memcmp(ua, ub, sizeof ua) == 0, "scheme %d: %s", k, what);
}

/* every scheme of the whole-run list runs damped through impacts, and with
   damping 0, 0 gives the undamped bits */
START_TEST(every_scheme_runs_damped_and_zero_is_off) {
  for (int k = 0; k < ND_TEST_N_SCHEMES; ++k) {
    double tau = 0;
    nd_problem a = scheme_bar(&nd_test_schemes[k], -1, 0, &tau), b = scheme_bar(&nd_test_schemes[k], 0, 0, &tau);
    nd_problem c = scheme_bar(&nd_test_schemes[k], 0.1, 0.001, &tau);
    const int steps = (int)lround(4.0 / tau);
    for (int n = 0; n < steps; ++n) {
      ND_OK_OR_FAIL(nd_step(a));
      ND_OK_OR_FAIL(nd_step(b));
      ND_OK_OR_FAIL(nd_step(c));
    }
    same_bits(a, b, "damping 0, 0 changed the bits", k);
    ck_assert_double_eq(scalar(b, ND_DISSIPATION_DAMPING), 0);
    const double Ec = scalar(c, ND_ENERGY_MECHANICAL), Dc = scalar(c, ND_DISSIPATION_DAMPING);
    const double Ea = scalar(a, ND_ENERGY_MECHANICAL);
    printf("scheme %d damped: E %.6g (undamped %.6g), D %.6g\n", k, Ec, Ea, Dc);
    ck_assert_double_gt(Dc, 0);
    ck_assert_double_lt(Ec, Ea);
    ND_OK_OR_FAIL(nd_problem_destroy(&a));
    ND_OK_OR_FAIL(nd_problem_destroy(&b));
    ND_OK_OR_FAIL(nd_problem_destroy(&c));
  }
  /* mass redistribution (massless contact DOFs, alpha only: C = alpha M
     vanishes there), explicit and implicit, through impacts */
  for (int k = 0; k < ND_TEST_N_SCHEMES; ++k) {
    double tau = 0;
    nd_problem p = scheme_bar(&nd_test_schemes[k], 0.2, 0, &tau);
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
    ND_OK_OR_FAIL(nd_problem_setup(p));
    const double E0 = scalar(p, ND_ENERGY_MECHANICAL);
    for (int n = 0; n < (int)lround(4.0 / tau); ++n) ND_OK_OR_FAIL(nd_step(p));
    ck_assert_double_gt(scalar(p, ND_DISSIPATION_DAMPING), 0);
    ck_assert_double_lt(scalar(p, ND_ENERGY_MECHANICAL), E0);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* The central difference with damping taken at A^{n+1}'s time keeps its
   undamped limit w tau <= 2 whatever the damping ratio (at gamma = 1/2 the
   characteristic polynomial at lambda = -1 is 4 - (w tau)^2, with no
   damping term; docs/design.md §10.5). On the clamped bar started with
   every mode (the highest included), with stiffness damping strong on the
   highest modes (xi = beta w_max/2 = 0.1; M + tau/2 C factored): at 0.98 of
   the undamped tau_c the run decays, at 1.05 of it (the critical-step
   guard off) it grows until the energy guard stops it. */
static int central_difference_run(double fraction, double *E_ratio) {
  const damped_case dc = {ND_SCHEME_NEWMARK, {0, 0.5}, 1, 0, 0, 0, 0};
  double phi[NX + 1], u0[NX + 1];
  int64_t n_nodes = 0;
  nd_problem p = clamped_bar(&dc, 1e-3, phi, &n_nodes);
  for (int i = 0; i <= NX; ++i) u0[i] = phi[i] + 0.1 * (i % 2 ? 1 : -1); /* (clamped ends ignored) */
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n_nodes, u0, NULL));
  double tau_c = 0;
  ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tau_c));
  ND_OK_OR_FAIL(nd_problem_set_damping(p, 0.2, 0.2 * tau_c / 2)); /* beta w_max = 0.2 */
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, fraction * tau_c));
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_CRITICAL_TIMESTEP, 0));
  ND_OK_OR_FAIL(nd_problem_setup(p));
  const double E0 = scalar(p, ND_ENERGY_MECHANICAL);
  int status = ND_OK, n = 0;
  for (; n < 2000 && status == ND_OK; ++n) status = nd_step(p);
  *E_ratio = scalar(p, ND_ENERGY_MECHANICAL) / E0;
  printf("central difference at %.2f tau_c, damped: status %d after %d steps, E/E0 = %.3g\n", fraction, status, n,
         *E_ratio);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return status;
}

START_TEST(explicit_damped_critical_step_is_the_undamped_one) {
  double ratio = 0;
  ck_assert_int_eq(central_difference_run(0.98, &ratio), ND_OK);
  ck_assert_double_lt(ratio, 0.5);
  ck_assert_int_eq(central_difference_run(1.05, &ratio), ND_ERR_ENERGY_GROWTH);
}
END_TEST

/* The reactions carry the damping's clamped rows (C_DF Vbar). Summed over
   every row, free and clamped, the hybrid step's equation
   M (V^{n+1} - V^n)/tau + C Vbar + K_Theta Ubar = Fbar (+ R on the clamped
   rows) loses K's row sums (K annihilates translations) and beta K's, and
   keeps alpha M's: the momentum P = sum_i (M V)_i obeys
     P^{n+1} - P^n = tau (sum Fbar + sum R - alpha (P^{n+1} + P^n)/2)
   (no contact: the obstacle far below). Round-off of the sums of n = 41
   terms of size |P| + tau (|F| + |R|): 64 n eps of that. */
START_TEST(reactions_balance_the_damped_momentum) {
  const double g[1] = {-0.5}, alpha = 0.3, beta = 0.01;
  for (int degree = 1; degree <= 2; ++degree) {
    const double tau = 1.0 / 80;
    nd_problem p = nd_test_bar_at(40, degree, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, tau, -10.0, g);
    ND_OK_OR_FAIL(nd_problem_set_damping(p, alpha, beta));
    int64_t nn = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
    double *R = malloc(sizeof(double) * (size_t)nn), worst = 0;
    double P0 = scalar(p, ND_MOMENTUM_X);
    for (int n = 0; n < 200; ++n) {
      ND_OK_OR_FAIL(nd_step(p));
      const double P1 = scalar(p, ND_MOMENTUM_X);
      ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_REACTION, nn, R));
      double sR = 0, aR = 0;
      for (int64_t i = 0; i < nn; ++i) sR += R[i], aR += fabs(R[i]);
      const double F = g[0] * 1.0; /* rho g |Omega|, at both ends of the step */
      const double gap = P1 - P0 - tau * (F + sR - alpha * 0.5 * (P1 + P0));
      const double tol = 64 * (double)nn * DBL_EPSILON * (fabs(P0) + fabs(P1) + tau * (fabs(F) + aR));
      ck_assert_msg(fabs(gap) <= tol, "P%d step %d: momentum balance off by %g (tolerance %g)", degree, n + 1, gap,
                    tol);
      worst = fmax(worst, fabs(gap));
      P0 = P1;
    }
    printf("damped momentum balance with the reactions, P%d: largest gap %.3g over 200 steps\n", degree, worst);
    free(R);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* ND_MATRIX_DAMPING = alpha M + beta K entry by entry (the same operations) */
START_TEST(damping_matrix_export) {
  const double half = 0.5;
  nd_problem p = nd_test_bar(10, 2, ND_SCHEME_THETA, &half, 1.0, 0.2, 0.01);
  const double alpha = 0.3, beta = 0.007;
  ND_OK_OR_FAIL(nd_problem_set_damping(p, alpha, beta));
  int64_t n[3], nnz[3];
  const int which[3] = {ND_MATRIX_MASS, ND_MATRIX_STIFFNESS, ND_MATRIX_DAMPING};
  int64_t *ptr[3], *col[3];
  double *val[3];
  for (int k = 0; k < 3; ++k) {
    ND_OK_OR_FAIL(nd_problem_get_matrix(p, which[k], &n[k], &nnz[k], NULL, NULL, NULL));
    ptr[k] = malloc(sizeof(int64_t) * (size_t)(n[k] + 1));
    col[k] = malloc(sizeof(int64_t) * (size_t)nnz[k]);
    val[k] = malloc(sizeof(double) * (size_t)nnz[k]);
    ND_OK_OR_FAIL(nd_problem_get_matrix(p, which[k], &n[k], &nnz[k], ptr[k], col[k], val[k]));
  }
  ck_assert_int_eq(nnz[0], nnz[2]);
  ck_assert_int_eq(nnz[1], nnz[2]);
  for (int64_t e = 0; e < nnz[2]; ++e) {
    ck_assert_int_eq(col[0][e], col[2][e]);
    ck_assert_double_eq(val[2][e], alpha * val[0][e] + beta * val[1][e]);
  }
  for (int k = 0; k < 3; ++k) free(ptr[k]), free(col[k]), free(val[k]);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* a damped run saved at n = 30 and resumed gives the uninterrupted bits */
START_TEST(damped_restart_is_bitwise) {
  for (int k = 0; k < ND_TEST_N_SCHEMES; ++k) {
    double tau = 0;
    nd_problem a = scheme_bar(&nd_test_schemes[k], 0.1, 0.001, &tau), b = scheme_bar(&nd_test_schemes[k], 0.1, 0.001, &tau);
    for (int n = 0; n < 30; ++n) ND_OK_OR_FAIL(nd_step(a));
    int64_t size = 0;
    unsigned char *buf = nd_test_checkpoint(a, &size);
    ND_OK_OR_FAIL(nd_problem_load_state(b, size, buf));
    free(buf);
    for (int n = 0; n < 60; ++n) {
      ND_OK_OR_FAIL(nd_step(a));
      ND_OK_OR_FAIL(nd_step(b));
    }
    same_bits(a, b, "the restart differs", k);
    ck_assert_double_eq(scalar(a, ND_DISSIPATION_DAMPING), scalar(b, ND_DISSIPATION_DAMPING));
    ND_OK_OR_FAIL(nd_problem_destroy(&a));
    ND_OK_OR_FAIL(nd_problem_destroy(&b));
  }
}
END_TEST

/* Plane stress: a rectangle [0, 2] x [0, 1] pulled by s on x = 2 and -s on
   x = 0, lateral sides free, has the uniaxial solution eps_xx = s/E,
   eps_yy = -nu s/E (sigma_xx = s, sigma_yy = 0): linear, so P1 holds it
   exactly, and started there at rest it is an equilibrium: the acceleration
   is zero and the state stays to round-off. In plane strain the same field is
   not an equilibrium (sigma_yy = lambda (eps_xx + eps_yy) != 0): it moves. */
/* max |A^0| in *acc, returns max |u^20 - u0| */
static double uniaxial_motion(int plane_stress, int degree, double *acc) {
  const double lo[2] = {0, 0}, hi[2] = {2, 1}, E = 3.0, nu = 0.3, s = 0.01;
  const double l0[2] = {-0.1, -0.1}, h0[2] = {0.1, 1.1}, l1[2] = {1.9, -0.1}, h1[2] = {2.1, 1.1};
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_rectangle(8, 4, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, l0, h0));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, l1, h1));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_plane_stress(p, plane_stress));
  ND_OK_OR_FAIL(nd_problem_set_material(p, E, nu, 1.0));
  const double gl[2] = {-s, 0}, gr[2] = {s, 0};
  ND_OK_OR_FAIL(nd_problem_set_neumann(p, 1, gl));
  ND_OK_OR_FAIL(nd_problem_set_neumann(p, 2, gr));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.05));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *x = malloc(sizeof(double) * 2 * (size_t)n), *u0 = malloc(sizeof(double) * 2 * (size_t)n),
         *u = malloc(sizeof(double) * 2 * (size_t)n), *a = malloc(sizeof(double) * 2 * (size_t)n);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
  for (int64_t i = 0; i < n; ++i) {
    u0[2 * i] = s / E * (x[2 * i] - 1);
    u0[2 * i + 1] = -nu * s / E * (x[2 * i + 1] - 0.5);
  }
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, u0, NULL));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, n, a));
  double amax = 0, dmax = 0;
  for (int64_t i = 0; i < 2 * n; ++i) amax = fmax(amax, fabs(a[i]));
  for (int k = 0; k < 20; ++k) ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u));
  for (int64_t i = 0; i < 2 * n; ++i) dmax = fmax(dmax, fabs(u[i] - u0[i]));
  printf("uniaxial stress, plane %s, P%d: max |A^0| = %.3g, max |u - u0| after 20 steps = %.3g (|u0| <= %.3g)\n",
         plane_stress ? "stress" : "strain", degree, amax, dmax, s / E);
  free(x), free(u0), free(u), free(a);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  *acc = amax;
  return dmax;
}

START_TEST(plane_stress_uniaxial) {
  /* round-off: K u0 - F sums a few terms of size s h per row, divided by
     the mass rho h^2/6 (h = 1/4): |A^0| <= 1e3 eps s/(rho h); the
     displacements, about s/E, move by the steps' round-off: 1e3 eps s/E */
  const double s = 0.01, E = 3.0, h = 0.25;
  for (int degree = 1; degree <= 2; ++degree) {
    double acc = 0;
    ck_assert_double_le(uniaxial_motion(1, degree, &acc), 1e3 * DBL_EPSILON * s / E);
    ck_assert_double_le(acc, 1e3 * DBL_EPSILON * s / h);
    ck_assert_double_gt(uniaxial_motion(0, degree, &acc), 1e-2 * s / E); /* plane strain: it moves */
  }
}
END_TEST

START_TEST(plane_stress_outside_2d_refused) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_interval(4, 0.0, 1.0, &m));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ck_assert_int_eq(nd_problem_set_plane_stress(p, 1), ND_ERR_DIMENSION);
  ND_OK_OR_FAIL(nd_problem_set_plane_stress(p, 0));
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(void) {
  Suite *s = suite_create("damping");
  TCase *tc = tcase_create("damping");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, mode_decays_as_the_scheme_says);
  tcase_add_test(tc, decay_rate_is_half_alpha_plus_beta_omega2);
  tcase_add_test(tc, hybrid_ledger_with_damping);
  tcase_add_test(tc, every_scheme_runs_damped_and_zero_is_off);
  tcase_add_test(tc, damping_matrix_export);
  tcase_add_test(tc, reactions_balance_the_damped_momentum);
  tcase_add_test(tc, explicit_damped_critical_step_is_the_undamped_one);
  tcase_add_test(tc, damped_restart_is_bitwise);
  tcase_add_test(tc, plane_stress_uniaxial);
  tcase_add_test(tc, plane_stress_outside_2d_refused);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
