/* Operators out and contact on the host's operators (docs/design.md §10.4),
 * through the public API:
 *  - a host loop with its own arrays, time scheme and semi-smooth Newton,
 *    the library giving only M, K, K_Theta - K, F and the contact term,
 *    follows nd_step's trajectory for every implicit scheme: the
 *    theta-scheme, Newmark, generalized-alpha (N at the shifted U, and the
 *    step form) and the hybrid scheme (the step form,
 *    nd_problem_contact_step_residual: its Phi_q switches per point on the
 *    sign of P_q^n), in 2D and 3D, P1 and P2 (the C twin of
 *    examples/host_newmark.f90). The bound, step by step: with Theta = 1
 *    (b_q = p_q) the host's step map G_h(U) = A U + kappa N_h(U) - r_h, N_h
 *    its contact term with its own U^n, is strongly monotone with constant
 *    lambda_min(A): N_h = sum_q (w_q/gamma_q) phi_q(P_q(U)) p_q with each
 *    phi_q nondecreasing in P_q (at the end, at generalized-alpha's
 *    Y = (1-af) U + af U^n, and the hybrid Phi_q for a fixed P_q^n alike), so
 *      |U_host - U_lib| <= (|G_h(U_host)| + |G_h(U_lib)|) / lambda_min(A),
 *    the host's equation at the library's solution holding every difference
 *    of history (r_h - r_l, and U^n where the contact term reads it), the
 *    first term below the Newton tolerance rtol (|r| + c |M U|);
 *  - the operators: M 1 per component is the mass rho |Omega|, K and
 *    K_Theta - K annihilate the rigid motions, K_Theta - K is symmetric,
 *    STEP = c M + K + NITSCHE entrywise, the lumped mass keeps the mass;
 *  - N' by central differences where no point changes side (N is linear
 *    there: exact to round-off); the contact values at the state's U are
 *    nd_get_scalar's; the state's checkpoint is bitwise the same after every
 *    call;
 *  - the momentum: its change over a Newmark step is the impulse of the
 *    load and the contact force, (1 - gamma) and gamma weighted, plus the
 *    step equations' residuals;
 *  - the step form is the at-end form bitwise for theta and Newmark, and for
 *    the hybrid scheme at u_old = u; its tangent by central differences. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

static const double kRtol = 1e-10; /* the library's default Newton rtol, asked of both */

/* ---- the host's dense linear algebra ---------------------------------------- */

typedef nd_test_csr csr;
static csr get_matrix(nd_problem p, int which) { return nd_test_get_matrix(p, which); }
static void csr_free(csr *a) { nd_test_csr_free(a); }

/* dense n x n, row-major, from a CSR */
static double *dense(const csr *a) {
  double *d = calloc((size_t)(a->n * a->n), sizeof(double));
  for (int64_t i = 0; i < a->n; ++i)
    for (int64_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k) d[i * a->n + a->col[k]] += a->val[k];
  return d;
}

static void matvec(int64_t n, const double *A, const double *x, double *y) {
  for (int64_t i = 0; i < n; ++i) {
    double s = 0;
    for (int64_t j = 0; j < n; ++j) s += A[i * n + j] * x[j];
    y[i] = s;
  }
}

static double norm2(int64_t n, const double *x) {
  double s = 0;
  for (int64_t i = 0; i < n; ++i) s += x[i] * x[i];
  return sqrt(s);
}

/* x <- T^{-1} x, Gaussian elimination with partial pivoting (T copied) */
static void solve(int64_t n, const double *T, double *x) {
  double *a = malloc(sizeof(double) * (size_t)(n * n));
  memcpy(a, T, sizeof(double) * (size_t)(n * n));
  for (int64_t k = 0; k < n; ++k) {
    int64_t piv = k;
    for (int64_t i = k + 1; i < n; ++i)
      if (fabs(a[i * n + k]) > fabs(a[piv * n + k])) piv = i;
    if (piv != k) {
      for (int64_t j = 0; j < n; ++j) {
        const double t = a[k * n + j];
        a[k * n + j] = a[piv * n + j], a[piv * n + j] = t;
      }
      const double t = x[k];
      x[k] = x[piv], x[piv] = t;
    }
    for (int64_t i = k + 1; i < n; ++i) {
      const double f = a[i * n + k] / a[k * n + k];
      for (int64_t j = k; j < n; ++j) a[i * n + j] -= f * a[k * n + j];
      x[i] -= f * x[k];
    }
  }
  for (int64_t i = n - 1; i >= 0; --i) {
    double s = x[i];
    for (int64_t j = i + 1; j < n; ++j) s -= a[i * n + j] * x[j];
    x[i] = s / a[i * n + i];
  }
  free(a);
}

/* whether A - mu I has a Cholesky factor (then lambda_min(A) > mu) */
static int cholesky_ok(int64_t n, const double *A, double mu) {
  double *l = malloc(sizeof(double) * (size_t)(n * n));
  int ok = 1;
  for (int64_t i = 0; i < n && ok; ++i)
    for (int64_t j = 0; j <= i && ok; ++j) {
      double s = A[i * n + j] - (i == j ? mu : 0);
      for (int64_t k = 0; k < j; ++k) s -= l[i * n + k] * l[j * n + k];
      if (i == j) {
        if (!(s > 0)) ok = 0;
        else l[i * n + i] = sqrt(s);
      } else {
        l[i * n + j] = s / l[j * n + j];
      }
    }
  free(l);
  return ok;
}

/* a certified lower bound of lambda_min(A), A symmetric positive definite:
   the Rayleigh quotient of inverse iteration (>= lambda_min) lowered until
   A - mu I factors */
static double lambda_min_lower(int64_t n, const double *A) {
  double *x = malloc(sizeof(double) * (size_t)n), *y = malloc(sizeof(double) * (size_t)n);
  for (int64_t i = 0; i < n; ++i) x[i] = 1.0 + 0.1 * (double)(i % 7);
  double q = 0;
  for (int it = 0; it < 40; ++it) {
    const double s = norm2(n, x);
    for (int64_t i = 0; i < n; ++i) x[i] /= s;
    memcpy(y, x, sizeof(double) * (size_t)n);
    solve(n, A, y);
    double xy = 0;
    for (int64_t i = 0; i < n; ++i) xy += x[i] * y[i];
    q = 1.0 / xy;
    memcpy(x, y, sizeof(double) * (size_t)n);
  }
  double mu = 0.999 * q;
  while (!cholesky_ok(n, A, mu)) mu *= 0.5;
  free(x), free(y);
  return mu;
}

/* ---- the scene: a free block dropped on a plane ----------------------------- */

/* in_flight: no load, the plane far below (free flight) */
static nd_problem drop_scene(int dim, int degree, int scheme, const double *params, int in_flight) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo[3] = {0, 0.002, 0}, hi[3] = {1, 0.252, 0.5}, lo3[3] = {0, 0, 0.002}, hi3[3] = {1, 0.5, 0.252};
  const double blo[3] = {-1, -1, -1}, bhi2[3] = {2, 0.0021, 2}, bhi3[3] = {2, 2, 0.0021};
  if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle(4, 1, lo, hi, &m));
  if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box(2, 1, 1, lo3, hi3, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, dim == 2 ? bhi2 : bhi3));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  const double below[3] = {0, in_flight ? -100 : 0, in_flight ? -100 : 0}, up2[3] = {0, 1, 0}, up3[3] = {0, 0, 1};
  const double g2[3] = {0.05, -1, 0}, g3[3] = {0.05, 0.02, -1};
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, below, dim == 2 ? up2 : up3));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0));
  if (!in_flight) ND_OK_OR_FAIL(nd_problem_set_body_force(p, dim == 2 ? g2 : g3));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.01));
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  double *x = malloc(sizeof(double) * (size_t)(nn * dim)), *v0 = calloc((size_t)(nn * dim), sizeof(double));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, nn, x));
  for (int64_t i = 0; i < nn; ++i) { /* falling, sliding and spinning a little */
    v0[i * dim] = 0.2 - 0.3 * x[i * dim + dim - 1] + 0.1 * x[i * dim] * x[i * dim]; /* (and stretching) */
    v0[i * dim + dim - 1] = -0.5 + 0.3 * (x[i * dim] - 0.5);
  }
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nn, NULL, v0));
  free(x), free(v0);
  return p;
}

static nd_problem drop(int dim, int degree, int scheme, const double *params) {
  return drop_scene(dim, degree, scheme, params, 0);
}

/* a state's field on the free DOFs */
static void free_field(nd_problem p, int field, int64_t n, const int64_t *node, const int *comp, int dim,
                       double *out) {
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  double *full = malloc(sizeof(double) * (size_t)(nn * dim));
  ND_OK_OR_FAIL(nd_get_field(p, field, nn, full));
  for (int64_t i = 0; i < n; ++i) out[i] = full[node[i] * dim + comp[i]];
  free(full);
}

/* ---- the host ---------------------------------------------------------------- */

typedef struct {
  int kind; /* 0 theta, 1 Newmark, 2 generalized-alpha, 3 hybrid */
  double theta, beta, gamma, am, af;
  double c, kappa;
  int step_form; /* the contact term by nd_problem_contact_step_residual (U^n given) */
  /* Rayleigh damping (Newmark and hybrid here): C V^{n+1} with
     V^{n+1} = gamma/(beta tau) (U - U^n) + (1 - gamma/beta) V^n + tau (1 - gamma/(2 beta)) A^n,
     or twice C (U - U^n)/tau for the hybrid scheme (C at the midpoint): cd C joins A */
  double cd;
} scheme_t;

static scheme_t make_scheme(int scheme, const double *prm, double tau, int step_form) {
  scheme_t s = {0, 0, 0, 0, 0, 0, 0, 1, step_form, 0};
  if (scheme == ND_SCHEME_HYBRID) {
    s.kind = 3, s.c = 4 / (tau * tau), s.kappa = 2, s.step_form = 1, s.cd = 2 / tau; /* (design.md §3) */
  } else if (scheme == ND_SCHEME_THETA) {
    s.kind = 0, s.theta = prm[0], s.c = 1 / (tau * tau * s.theta * s.theta);
  } else if (scheme == ND_SCHEME_NEWMARK) {
    s.kind = 1, s.beta = prm[0], s.gamma = prm[1], s.c = 1 / (s.beta * tau * tau), s.cd = s.gamma / (s.beta * tau);
  } else {
    const double r = prm[0];
    s.kind = 2, s.am = (2 * r - 1) / (r + 1), s.af = r / (r + 1);
    s.gamma = 0.5 - s.am + s.af, s.beta = 0.25 * (1 - s.am + s.af) * (1 - s.am + s.af);
    s.c = (1 - s.am) / ((1 - s.af) * s.beta * tau * tau), s.kappa = 1 / (1 - s.af);
  }
  return s;
}

typedef struct {
  nd_problem p;
  int64_t n;
  double *M, *K, *KT, *A; /* dense: mass, stiffness, K_Theta, c M + K_Theta (+ cd C) */
  double *C;              /* dense: the damping alpha M + beta K (zeros when off) */
  double *F;
  int64_t tnnz;
  int64_t *tptr, *tcol;
  double *tval;
} host;

static host host_make(nd_problem p, double c, double cd) {
  host h;
  memset(&h, 0, sizeof h);
  h.p = p;
  csr M = get_matrix(p, ND_MATRIX_MASS), K = get_matrix(p, ND_MATRIX_STIFFNESS), N = get_matrix(p, ND_MATRIX_NITSCHE);
  csr C = get_matrix(p, ND_MATRIX_DAMPING);
  h.n = M.n;
  h.M = dense(&M), h.K = dense(&K), h.C = dense(&C);
  double *NT = dense(&N);
  const int64_t nn = h.n * h.n;
  h.KT = malloc(sizeof(double) * (size_t)nn), h.A = malloc(sizeof(double) * (size_t)nn);
  for (int64_t k = 0; k < nn; ++k) h.KT[k] = h.K[k] + NT[k], h.A[k] = c * h.M[k] + h.KT[k] + cd * h.C[k];
  free(NT);
  csr_free(&M), csr_free(&K), csr_free(&N), csr_free(&C);
  h.F = malloc(sizeof(double) * (size_t)h.n);
  ND_OK_OR_FAIL(nd_problem_get_load(p, h.n, h.F));
  ND_OK_OR_FAIL(nd_problem_contact_tangent(p, h.n, NULL, &h.tnnz, NULL, NULL, NULL));
  h.tptr = malloc(sizeof(int64_t) * (size_t)(h.n + 1));
  h.tcol = malloc(sizeof(int64_t) * (size_t)(h.tnnz + 1));
  h.tval = malloc(sizeof(double) * (size_t)(h.tnnz + 1));
  return h;
}

static void host_free(host *h) {
  free(h->M), free(h->K), free(h->C), free(h->KT), free(h->A), free(h->F), free(h->tptr), free(h->tcol), free(h->tval);
}

/* the step's right-hand side r from a state (U, V, A) at t^n */
static void rhs(const host *h, const scheme_t *s, double tau, const double *U, const double *V, const double *A,
                double *r) {
  const int64_t n = h->n;
  double *w = malloc(sizeof(double) * (size_t)n), *Mw = malloc(sizeof(double) * (size_t)n);
  if (s->kind == 0) {
    const double th = s->theta;
    for (int64_t i = 0; i < n; ++i) w[i] = s->c * U[i] + V[i] / (tau * th * th) + (1 - th) / th * A[i];
  } else {
    const double b = s->beta;
    for (int64_t i = 0; i < n; ++i) w[i] = U[i] / (b * tau * tau) + V[i] / (b * tau) + (1 / (2 * b) - 1) * A[i];
  }
  if (s->kind == 3) /* 2 F - K_Theta U^n + M (c U^n + 4/tau V^n) */
    for (int64_t i = 0; i < n; ++i) w[i] = s->c * U[i] + 4 / tau * V[i];
  matvec(n, h->M, w, Mw);
  if (s->kind == 3) {
    double *KU = malloc(sizeof(double) * (size_t)n);
    matvec(n, h->KT, U, KU);
    for (int64_t i = 0; i < n; ++i) r[i] = 2 * h->F[i] - KU[i] + Mw[i];
    free(KU);
  } else if (s->kind < 2) {
    for (int64_t i = 0; i < n; ++i) r[i] = h->F[i] + Mw[i];
  } else {
    double *KU = malloc(sizeof(double) * (size_t)n), *MA = malloc(sizeof(double) * (size_t)n);
    matvec(n, h->KT, U, KU);
    matvec(n, h->M, A, MA);
    for (int64_t i = 0; i < n; ++i)
      r[i] = (h->F[i] - s->af * KU[i] - s->am * MA[i] + (1 - s->am) * Mw[i]) / (1 - s->af);
    free(KU), free(MA);
  }
  /* damping: C times the part of the damping velocity without U^{n+1} */
  if (s->kind == 1 || s->kind == 3) {
    const double b = s->beta, g = s->gamma;
    for (int64_t i = 0; i < n; ++i)
      w[i] = s->kind == 3 ? 2 / tau * U[i]
                          : g / (b * tau) * U[i] - (1 - g / b) * V[i] - tau * (1 - g / (2 * b)) * A[i];
    matvec(n, h->C, w, Mw);
    for (int64_t i = 0; i < n; ++i) r[i] += Mw[i];
  }
  free(w), free(Mw);
}

/* G(U) = A U + kappa N(Y) - r, Y = (1 - af) U + af U^n; in the step form
   kappa times the scheme's contact term from U^n to U */
static void residual(const host *h, const scheme_t *s, const double *Un, const double *r, const double *U,
                     double *G) {
  const int64_t n = h->n;
  double *Y = calloc((size_t)n, sizeof(double)), *N = calloc((size_t)n, sizeof(double));
  for (int64_t i = 0; i < n; ++i) Y[i] = (1 - s->af) * U[i] + s->af * Un[i];
  if (s->step_form) ND_OK_OR_FAIL(nd_problem_contact_step_residual(h->p, n, U, Un, N));
  else ND_OK_OR_FAIL(nd_problem_contact_residual(h->p, n, Y, N));
  matvec(n, h->A, U, G);
  for (int64_t i = 0; i < n; ++i) G[i] += s->kappa * N[i] - r[i];
  free(Y), free(N);
}

/* Newton on G from the predictor U (in place): until the contact tangent
   (so the active set) repeats and |G| <= rtol (|r| + c |M U|), as nd_step
   (docs/design.md §3). Returns |G| at the solution. */
static double newton(host *h, const scheme_t *s, const double *Un, const double *r, double *U) {
  const int64_t n = h->n;
  double *G = malloc(sizeof(double) * (size_t)n), *T = malloc(sizeof(double) * (size_t)(n * n));
  double *Y = calloc((size_t)n, sizeof(double)), *MU = calloc((size_t)n, sizeof(double));
  double *last = calloc((size_t)(h->tnnz + 1), sizeof(double));
  double g = 0;
  int it = 0, same = 0;
  for (;; ++it) {
    ck_assert_msg(it < 50, "the host's Newton did not converge");
    residual(h, s, Un, r, U, G);
    matvec(n, h->M, U, MU);
    g = norm2(n, G);
    const double tol = kRtol * (norm2(n, r) + s->c * norm2(n, MU));
    for (int64_t i = 0; i < n; ++i) Y[i] = (1 - s->af) * U[i] + s->af * Un[i];
    if (s->step_form) /* the Jacobian in U: kappa times it */
      ND_OK_OR_FAIL(nd_problem_contact_step_tangent(h->p, n, U, Un, &h->tnnz, h->tptr, h->tcol, h->tval));
    else
      ND_OK_OR_FAIL(nd_problem_contact_tangent(h->p, n, Y, &h->tnnz, h->tptr, h->tcol, h->tval));
    same = it > 0 && memcmp(last, h->tval, sizeof(double) * (size_t)h->tnnz) == 0;
    if (same && g <= tol) break;
    memcpy(last, h->tval, sizeof(double) * (size_t)h->tnnz);
    memcpy(T, h->A, sizeof(double) * (size_t)(n * n));
    /* kappa N'(Y) dY/dU = kappa (1 - af) N'(Y) = N'(Y); the step form's is in U */
    const double f = s->step_form ? s->kappa : 1;
    for (int64_t i = 0; i < n; ++i)
      for (int64_t k = h->tptr[i]; k < h->tptr[i + 1]; ++k) T[i * n + h->tcol[k]] += f * h->tval[k];
    for (int64_t i = 0; i < n; ++i) G[i] = -G[i];
    solve(n, T, G);
    for (int64_t i = 0; i < n; ++i) U[i] += G[i];
  }
  free(G), free(T), free(Y), free(MU), free(last);
  return g;
}

/* V, A at t^{n+1} from U^{n+1} */
static void update(const scheme_t *s, double tau, int64_t n, const double *U0, const double *V0, const double *A0,
                   const double *U, double *V, double *A) {
  for (int64_t i = 0; i < n; ++i) {
    if (s->kind == 3) { /* Crank-Nicolson; no acceleration */
      V[i] = 2 * (U[i] - U0[i]) / tau - V0[i];
      A[i] = 0;
    } else if (s->kind == 0) {
      const double th = s->theta;
      V[i] = (U[i] - U0[i]) / (tau * th) - (1 - th) / th * V0[i];
      A[i] = (V[i] - V0[i]) / (tau * th) - (1 - th) / th * A0[i];
    } else {
      const double b = s->beta;
      A[i] = (U[i] - U0[i]) / (b * tau * tau) - V0[i] / (b * tau) - (1 / (2 * b) - 1) * A0[i];
      V[i] = V0[i] + tau * ((1 - s->gamma) * A0[i] + s->gamma * A[i]);
    }
  }
}

/* M A^0 = F - K_Theta U^0 - N(U^0) - C V^0 (Remark 3.2) */
static void initial_acceleration(const host *h, const double *U, const double *V, double *A) {
  const int64_t n = h->n;
  double *N = malloc(sizeof(double) * (size_t)n), *CV = malloc(sizeof(double) * (size_t)n);
  matvec(n, h->KT, U, A);
  matvec(n, h->C, V, CV);
  ND_OK_OR_FAIL(nd_problem_contact_residual(h->p, n, U, N));
  for (int64_t i = 0; i < n; ++i) A[i] = h->F[i] - A[i] - N[i] - CV[i];
  solve(n, h->M, A);
  free(N), free(CV);
}

/* The host's trajectory against nd_step's over `steps` steps; returns the
   largest |U_host - U_lib|_max, each step's checked against its bound. */
static double host_damped(int dim, int degree, int scheme, const double *prm, int step_form, int steps,
                          double alpha, double beta) {
  nd_problem p = drop(dim, degree, scheme, prm);
  ND_OK_OR_FAIL(nd_problem_set_damping(p, alpha, beta));
  const double tau = 0.01;
  const scheme_t s = make_scheme(scheme, prm, tau, step_form);
  host h = host_make(p, s.c, s.cd);
  const int64_t n = h.n;
  const double lam = lambda_min_lower(n, h.A);
  int64_t *node = malloc(sizeof(int64_t) * (size_t)n);
  int *comp = malloc(sizeof(int) * (size_t)n);
  ND_OK_OR_FAIL(nd_problem_get_dof_map(p, n, node, comp));
  double *v[12];
  for (int k = 0; k < 12; ++k) v[k] = calloc((size_t)n, sizeof(double));
  double *U = v[0], *V = v[1], *A = v[2], *U1 = v[3], *V1 = v[4], *A1 = v[5];
  double *Ul = v[6], *Vl = v[7], *Al = v[8], *rh = v[9], *rl = v[10], *G = v[11];
  free_field(p, ND_FIELD_DISPLACEMENT, n, node, comp, dim, U);
  free_field(p, ND_FIELD_VELOCITY, n, node, comp, dim, V);
  if (s.kind != 3) initial_acceleration(&h, U, V, A); /* (the hybrid scheme carries none: predictor U + tau V) */
  double worst = 0, worst_bound = 0;
  int contact_steps = 0;
  for (int step = 0; step < steps; ++step) {
    free_field(p, ND_FIELD_DISPLACEMENT, n, node, comp, dim, Ul);
    free_field(p, ND_FIELD_VELOCITY, n, node, comp, dim, Vl);
    free_field(p, ND_FIELD_ACCELERATION, n, node, comp, dim, Al);
    rhs(&h, &s, tau, U, V, A, rh);
    rhs(&h, &s, tau, Ul, Vl, Al, rl);
    memcpy(U1, U, sizeof(double) * (size_t)n); /* predictor U + tau V + tau^2/2 A */
    for (int64_t i = 0; i < n; ++i) U1[i] += tau * V[i] + 0.5 * tau * tau * A[i];
    const double gh = newton(&h, &s, U, rh, U1);
    update(&s, tau, n, U, V, A, U1, V1, A1);
    const int status = nd_step(p);
    ck_assert_msg(status == ND_OK, "nd_step: %s", nd_last_error());
    double *Ulib = malloc(sizeof(double) * (size_t)n);
    free_field(p, ND_FIELD_DISPLACEMENT, n, node, comp, dim, Ulib);
    residual(&h, &s, U, rh, Ulib, G); /* the host's equation (its r_h, its U^n) at U_lib */
    const double bound = (gh + norm2(n, G)) / lam;
    double diff2 = 0, diff = 0;
    for (int64_t i = 0; i < n; ++i) {
      diff2 += (U1[i] - Ulib[i]) * (U1[i] - Ulib[i]);
      diff = fmax(diff, fabs(U1[i] - Ulib[i]));
    }
    ck_assert_msg(sqrt(diff2) <= bound, "%dD P%d scheme %d step %d: |U_host - U_lib| = %g > bound %g", dim,
                  degree, scheme, step, sqrt(diff2), bound);
    worst = fmax(worst, diff), worst_bound = fmax(worst_bound, bound);
    double active = 0;
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_ACTIVE_POINTS, &active));
    contact_steps += active > 0;
    memcpy(U, U1, sizeof(double) * (size_t)n), memcpy(V, V1, sizeof(double) * (size_t)n);
    memcpy(A, A1, sizeof(double) * (size_t)n);
    free(Ulib);
  }
  ck_assert_msg(contact_steps >= 3, "the scene must touch the plane (%d contact steps)", contact_steps);
  printf("host loop %dD P%d scheme %d (%.3g)%s%s: %d steps (%d in contact), max |U_host - U_lib| = %.3g, "
         "largest bound %.3g\n",
         dim, degree, scheme, prm[0], s.step_form ? " step form" : "", alpha + beta > 0 ? " damped" : "", steps,
         contact_steps, worst, worst_bound);
  for (int k = 0; k < 12; ++k) free(v[k]);
  free(node), free(comp);
  host_free(&h);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return worst;
}

static double host_against_library(int dim, int degree, int scheme, const double *prm, int step_form, int steps) {
  return host_damped(dim, degree, scheme, prm, step_form, steps, 0, 0);
}

START_TEST(host_loop_follows_nd_step) {
  const double half = 0.5, one = 1, nm[2] = {0.25, 0.5}, ga = 0.8, none = 0;
  const struct {
    int scheme;
    const double *prm; /* (the hybrid scheme reads none) */
    int step_form;
  } schemes[] = {{ND_SCHEME_NEWMARK, nm, 0},           {ND_SCHEME_THETA, &half, 0}, {ND_SCHEME_THETA, &one, 0},
                 {ND_SCHEME_GENERALIZED_ALPHA, &ga, 0}, {ND_SCHEME_GENERALIZED_ALPHA, &ga, 1},
                 {ND_SCHEME_HYBRID, &none, 1}};
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  for (size_t k = 0; k < sizeof schemes / sizeof schemes[0]; ++k)
    host_against_library(dim, degree, schemes[k].scheme, schemes[k].prm, schemes[k].step_form, 30);
  /* damped (docs/design.md §10.5): the host adds C to its Newmark and hybrid steps */
  host_damped(dim, degree, ND_SCHEME_NEWMARK, nm, 0, 30, 0.5, 0.01);
  host_damped(dim, degree, ND_SCHEME_HYBRID, &none, 1, 30, 0.5, 0.01);
}
END_TEST

/* ---- the operators ----------------------------------------------------------- */

START_TEST(operators_agree_with_the_library) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  const double nm[2] = {0.25, 0.5};
  nd_problem p = drop(dim, degree, ND_SCHEME_NEWMARK, nm);
  csr M = get_matrix(p, ND_MATRIX_MASS), K = get_matrix(p, ND_MATRIX_STIFFNESS);
  csr N = get_matrix(p, ND_MATRIX_NITSCHE), S = get_matrix(p, ND_MATRIX_STEP), L = get_matrix(p, ND_MATRIX_LUMPED_MASS);
  const int64_t n = M.n;
  ck_assert_int_eq(K.n, n);
  ck_assert_int_eq(N.n, n);
  ck_assert_int_eq(S.n, n);
  ck_assert_int_eq(L.n, n);
  ck_assert_int_eq(L.nnz, n);
  ck_assert_int_eq(K.nnz, N.nnz); /* one pattern */
  int64_t *node = malloc(sizeof(int64_t) * (size_t)n), nn = 0, ncells = 0;
  int *comp = malloc(sizeof(int) * (size_t)n), npc = 0;
  ND_OK_OR_FAIL(nd_problem_get_dof_map(p, n, node, comp));
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  ck_assert_int_eq(n, nn * dim); /* no Dirichlet region: every DOF free */
  double *x = malloc(sizeof(double) * (size_t)(nn * dim));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, nn, x));
  /* the mass: rho |Omega| per component (the block 1 x 0.25 (x 0.5), rho = 1) */
  const double mass = dim == 2 ? 0.25 : 0.125;
  for (int c = 0; c < dim; ++c) {
    double sm = 0, sl = 0, abs_sum = 0;
    for (int64_t i = 0; i < n; ++i) {
      if (comp[i] != c) continue;
      for (int64_t k = M.ptr[i]; k < M.ptr[i + 1]; ++k) sm += M.val[k], abs_sum += fabs(M.val[k]);
      sl += L.val[i];
    }
    ck_assert_msg(fabs(sm - mass) <= 4 * DBL_EPSILON * (double)M.nnz * abs_sum, "M 1 = %.17g", sm);
    ck_assert_msg(fabs(sl - mass) <= 4 * DBL_EPSILON * (double)n * mass, "lumped: %.17g", sl);
  }
  /* the rigid motions: translations and the rotation about the axis e_z
     (x, y) -> (-y, x) are in the kernel of K and of K_Theta - K */
  double *rigid = malloc(sizeof(double) * (size_t)n);
  for (int mode = 0; mode <= dim; ++mode) {
    for (int64_t i = 0; i < n; ++i) {
      const double *xi = x + node[i] * dim;
      rigid[i] = mode < dim ? (comp[i] == mode) : (comp[i] == 0 ? -xi[1] : comp[i] == 1 ? xi[0] : 0);
    }
    const csr *ops[2] = {&K, &N};
    for (int o = 0; o < 2; ++o) {
      const csr *a = ops[o];
      for (int64_t i = 0; i < n; ++i) { /* (K_Theta - K carries K's rounding: K's size counts) */
        double s = 0, scale = 0;
        for (int64_t k = a->ptr[i]; k < a->ptr[i + 1]; ++k)
          s += a->val[k] * rigid[a->col[k]], scale += (fabs(a->val[k]) + fabs(K.val[k])) * fabs(rigid[a->col[k]]);
        ck_assert_msg(fabs(s) <= 64 * DBL_EPSILON * scale + DBL_MIN, "operator %d, mode %d, row %ld: %g (scale %g)",
                      o, mode, (long)i, s, scale);
      }
    }
  }
  /* K_Theta - K symmetric (bitwise: s_q^T s_q's entries are added alike), and
     STEP = c M + K + NITSCHE entrywise to the round-off of one subtraction */
  double *dN = dense(&N), *dM = dense(&M), *dK = dense(&K), *dS = dense(&S);
  const double c = 1 / (0.25 * 0.01 * 0.01);
  int nonzero = 0;
  double *rowmax = calloc((size_t)n, sizeof(double)); /* max_j |K_ij| + |K_Theta,ij| */
  for (int64_t i = 0; i < n; ++i)
    for (int64_t j = 0; j < n; ++j) rowmax[i] = fmax(rowmax[i], fabs(dK[i * n + j]) + fabs(dK[i * n + j] + dN[i * n + j]));
  for (int64_t i = 0; i < n; ++i)
    for (int64_t j = 0; j < n; ++j) {
      const int64_t k = i * n + j;
      /* symmetric to the round-off of the assembly: K's entries are sums of
         element terms (its zeros after cancellation, ~1e-19, are not
         symmetric bit for bit), K_Theta - K carries it */
      const double sym = 8 * DBL_EPSILON * (rowmax[i] + rowmax[j]);
      ck_assert_msg(fabs(dN[k] - dN[j * n + i]) <= sym, "NITSCHE not symmetric at (%ld, %ld): %.17g %.17g",
                    (long)i, (long)j, dN[k], dN[j * n + i]);
      nonzero += dN[k] != 0;
      const double sum = c * dM[k] + dK[k] + dN[k];
      ck_assert_msg(fabs(dS[k] - sum) <= 4 * DBL_EPSILON * (fabs(c * dM[k]) + 2 * fabs(dK[k]) + 2 * fabs(dN[k])),
                    "STEP (%ld, %ld) = %.17g, c M + K + NITSCHE = %.17g", (long)i, (long)j, dS[k], sum);
    }
  ck_assert(nonzero > 0);
  /* the cells: their node count, and every node of the space in some cell */
  ND_OK_OR_FAIL(nd_problem_get_cells(p, &ncells, &npc, NULL));
  ck_assert_int_eq(npc, degree == 1 ? dim + 1 : (dim + 1) * (dim + 2) / 2);
  int64_t *cells = malloc(sizeof(int64_t) * (size_t)(ncells * npc));
  ND_OK_OR_FAIL(nd_problem_get_cells(p, &ncells, &npc, cells));
  char *seen = calloc((size_t)nn, 1);
  for (int64_t k = 0; k < ncells * npc; ++k) {
    ck_assert(cells[k] >= 0 && cells[k] < nn);
    seen[cells[k]] = 1;
  }
  for (int64_t i = 0; i < nn; ++i) ck_assert(seen[i]);
  /* P2: each edge node (after the vertices) is the midpoint of its cell's edge (i, j), i < j, lexicographically */
  if (degree == 2)
    for (int64_t cell = 0; cell < ncells; ++cell) {
      int e = dim + 1;
      for (int a = 0; a <= dim; ++a)
        for (int b = a + 1; b <= dim; ++b, ++e) {
          const int64_t *nd_ = cells + cell * npc;
          for (int k = 0; k < dim; ++k)
            ck_assert(fabs(x[nd_[e] * dim + k] - 0.5 * (x[nd_[a] * dim + k] + x[nd_[b] * dim + k])) <= 1e-15);
        }
    }
  free(rowmax), free(seen), free(cells), free(dN), free(dM), free(dK), free(dS), free(rigid), free(x), free(node), free(comp);
  csr_free(&M), csr_free(&K), csr_free(&N), csr_free(&S), csr_free(&L);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* ---- the contact term at the host's U ---------------------------------------- */

START_TEST(contact_by_differences_and_state_untouched) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  const double nm[2] = {0.25, 0.5};
  nd_problem p = drop(dim, degree, ND_SCHEME_NEWMARK, nm);
  for (int k = 0; k < 12; ++k) ND_OK_OR_FAIL(nd_step(p)); /* into contact */
  int64_t before_size = 0, after_size = 0;
  unsigned char *before = nd_test_checkpoint(p, &before_size);
  int64_t n = 0, nnz = 0;
  ND_OK_OR_FAIL(nd_problem_get_matrix(p, ND_MATRIX_MASS, &n, &nnz, NULL, NULL, NULL));
  int64_t *node = malloc(sizeof(int64_t) * (size_t)n);
  int *comp = malloc(sizeof(int) * (size_t)n);
  ND_OK_OR_FAIL(nd_problem_get_dof_map(p, n, node, comp));
  double *U = malloc(sizeof(double) * (size_t)n), *d = malloc(sizeof(double) * (size_t)n);
  double *Np = malloc(sizeof(double) * (size_t)n), *Nm = malloc(sizeof(double) * (size_t)n);
  double *Td = calloc((size_t)n, sizeof(double));
  free_field(p, ND_FIELD_DISPLACEMENT, n, node, comp, dim, U);
  /* the values at the state's U are nd_get_scalar's, bit for bit */
  double values[4], scal[4];
  const int keys[4] = {ND_CONTACT_FORCE, ND_ACTIVE_POINTS, ND_ENERGY_NITSCHE, ND_MAX_PENETRATION};
  ND_OK_OR_FAIL(nd_problem_contact_values(p, n, U, 4, values));
  for (int k = 0; k < 4; ++k) {
    ND_OK_OR_FAIL(nd_get_scalar(p, keys[k], &scal[k]));
    ck_assert_msg(values[k] == scal[k], "value %d: %.17g, nd_get_scalar %.17g", k, values[k], scal[k]);
  }
  ck_assert_msg(values[1] > 0, "the block must be in contact");
  /* N' by central differences along d, where no point changes side */
  int64_t tn = 0;
  ND_OK_OR_FAIL(nd_problem_contact_tangent(p, n, NULL, &tn, NULL, NULL, NULL));
  int64_t *ptr = malloc(sizeof(int64_t) * (size_t)(n + 1)), *col = malloc(sizeof(int64_t) * (size_t)tn);
  double *val = malloc(sizeof(double) * (size_t)tn), *val2 = malloc(sizeof(double) * (size_t)tn);
  ND_OK_OR_FAIL(nd_problem_contact_tangent(p, n, U, &tn, ptr, col, val));
  for (int64_t i = 0; i < n; ++i) d[i] = sin(1.0 + 0.7 * (double)i);
  for (int64_t i = 0; i < n; ++i)
    for (int64_t k = ptr[i]; k < ptr[i + 1]; ++k) Td[i] += val[k] * d[col[k]];
  double umax = 0;
  for (int64_t i = 0; i < n; ++i) umax = fmax(umax, fabs(U[i]));
  const double h = 1e-7 * umax;
  double *Ux = malloc(sizeof(double) * (size_t)n);
  for (int sgn = -1; sgn <= 1; sgn += 2) { /* the same active set (tangent) on both sides */
    for (int64_t i = 0; i < n; ++i) Ux[i] = U[i] + sgn * h * d[i];
    ND_OK_OR_FAIL(nd_problem_contact_tangent(p, n, Ux, &tn, ptr, col, val2));
    ck_assert_msg(memcmp(val, val2, sizeof(double) * (size_t)tn) == 0, "a point changes side within h");
    ND_OK_OR_FAIL(nd_problem_contact_residual(p, n, Ux, sgn < 0 ? Nm : Np));
  }
  { /* Newmark's step form is the law at the end: the same bits, whatever U^n */
    double *S = malloc(sizeof(double) * (size_t)n);
    ND_OK_OR_FAIL(nd_problem_contact_step_residual(p, n, Ux, d, S)); /* (Ux = U + h d, as Np's) */
    ck_assert(memcmp(S, Np, sizeof(double) * (size_t)n) == 0);
    ND_OK_OR_FAIL(nd_problem_contact_step_tangent(p, n, U, d, &tn, ptr, col, val2));
    ck_assert(memcmp(val, val2, sizeof(double) * (size_t)tn) == 0);
    free(S);
  }
  double err = 0, scale = 0;
  for (int64_t i = 0; i < n; ++i) {
    err = fmax(err, fabs((Np[i] - Nm[i]) / (2 * h) - Td[i]));
    scale = fmax(scale, fabs(Np[i]) + fabs(Nm[i]));
  }
  /* N linear on the segment: only the round-off of N(U +- h d), over 2h */
  ck_assert_msg(err <= 64 * DBL_EPSILON * scale / (2 * h), "N' d against differences: %g (round-off %g)", err,
                64 * DBL_EPSILON * scale / (2 * h));
  printf("contact %dD P%d: |N' d - differences| = %.3g (|N' d| %.3g)\n", dim, degree, err, norm2(n, Td));
  /* the calls changed nothing: the checkpoint is the same, bit for bit */
  double F[1024];
  ck_assert(n <= 1024);
  ND_OK_OR_FAIL(nd_problem_get_load(p, n, F));
  unsigned char *after = nd_test_checkpoint(p, &after_size);
  ck_assert_int_eq(before_size, after_size);
  ck_assert(memcmp(before, after, (size_t)before_size) == 0);
  free(before), free(after), free(Ux), free(ptr), free(col), free(val), free(val2);
  free(U), free(d), free(Np), free(Nm), free(Td), free(node), free(comp);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* The hybrid scheme's step form: at u_old = u its Phi_q is [P_q]_+ bit for bit
   ((P + P)/2 = P exactly; ([P]_+ + [P]_+)/2 = 0 where P < 0), so the step
   residual is the at-end one; its tangent against central differences in u,
   u_old fixed, where no point changes side (Phi_q linear there). */
START_TEST(hybrid_step_form_by_differences) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  const double none = 0;
  nd_problem p = drop(dim, degree, ND_SCHEME_HYBRID, &none);
  for (int k = 0; k < 12; ++k) ND_OK_OR_FAIL(nd_step(p)); /* into contact */
  int64_t n = 0, nnz = 0, tn = 0;
  ND_OK_OR_FAIL(nd_problem_get_matrix(p, ND_MATRIX_MASS, &n, &nnz, NULL, NULL, NULL));
  int64_t *node = malloc(sizeof(int64_t) * (size_t)n);
  int *comp = malloc(sizeof(int) * (size_t)n);
  ND_OK_OR_FAIL(nd_problem_get_dof_map(p, n, node, comp));
  double *U = malloc(sizeof(double) * (size_t)n), *Un = malloc(sizeof(double) * (size_t)n);
  double *d = malloc(sizeof(double) * (size_t)n), *Ux = malloc(sizeof(double) * (size_t)n);
  double *R = malloc(sizeof(double) * (size_t)n), *S = malloc(sizeof(double) * (size_t)n);
  double *Np = malloc(sizeof(double) * (size_t)n), *Nm = malloc(sizeof(double) * (size_t)n);
  double *Td = calloc((size_t)n, sizeof(double));
  free_field(p, ND_FIELD_DISPLACEMENT, n, node, comp, dim, U);
  ND_OK_OR_FAIL(nd_problem_contact_residual(p, n, U, R));
  ND_OK_OR_FAIL(nd_problem_contact_step_residual(p, n, U, U, S));
  ck_assert(memcmp(R, S, sizeof(double) * (size_t)n) == 0);
  double umax = 0;
  for (int64_t i = 0; i < n; ++i) umax = fmax(umax, fabs(U[i]));
  for (int64_t i = 0; i < n; ++i) d[i] = sin(1.0 + 0.7 * (double)i), Un[i] = U[i] - 0.3 * umax * cos(0.4 * (double)i);
  ND_OK_OR_FAIL(nd_problem_contact_step_tangent(p, n, NULL, NULL, &tn, NULL, NULL, NULL));
  int64_t *ptr = malloc(sizeof(int64_t) * (size_t)(n + 1)), *col = malloc(sizeof(int64_t) * (size_t)tn);
  double *val = malloc(sizeof(double) * (size_t)tn), *val2 = malloc(sizeof(double) * (size_t)tn);
  ND_OK_OR_FAIL(nd_problem_contact_step_tangent(p, n, U, Un, &tn, ptr, col, val));
  int nonzero = 0;
  for (int64_t k = 0; k < tn; ++k) nonzero += val[k] != 0;
  ck_assert_msg(nonzero > 0, "some point must be active over the step");
  for (int64_t i = 0; i < n; ++i)
    for (int64_t k = ptr[i]; k < ptr[i + 1]; ++k) Td[i] += val[k] * d[col[k]];
  const double h = 1e-7 * umax;
  for (int sgn = -1; sgn <= 1; sgn += 2) {
    for (int64_t i = 0; i < n; ++i) Ux[i] = U[i] + sgn * h * d[i];
    ND_OK_OR_FAIL(nd_problem_contact_step_tangent(p, n, Ux, Un, &tn, ptr, col, val2));
    ck_assert_msg(memcmp(val, val2, sizeof(double) * (size_t)tn) == 0, "a point changes side within h");
    ND_OK_OR_FAIL(nd_problem_contact_step_residual(p, n, Ux, Un, sgn < 0 ? Nm : Np));
  }
  double err = 0, scale = 0;
  for (int64_t i = 0; i < n; ++i) {
    err = fmax(err, fabs((Np[i] - Nm[i]) / (2 * h) - Td[i]));
    scale = fmax(scale, fabs(Np[i]) + fabs(Nm[i]));
  }
  ck_assert_msg(err <= 64 * DBL_EPSILON * scale / (2 * h), "step form N' d against differences: %g (round-off %g)",
                err, 64 * DBL_EPSILON * scale / (2 * h));
  printf("hybrid step form %dD P%d: |N' d - differences| = %.3g (|N' d| %.3g)\n", dim, degree, err, norm2(n, Td));
  free(U), free(Un), free(d), free(Ux), free(R), free(S), free(Np), free(Nm), free(Td);
  free(ptr), free(col), free(val), free(val2), free(node), free(comp);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* ---- the momentum ------------------------------------------------------------ */

/* Newmark: V^{n+1} - V^n = tau ((1-g) A^n + g A^{n+1}), so the change of
   sum_c (M V) is tau sum_c ((1-g) M A^n + g M A^{n+1}), and each step's
   equation says M A = F + C - K_Theta U + G (C the nodal contact force,
   ND_FIELD_CONTACT_FORCE, -N summed over a component; K_Theta U sums to 0
   over a component, translations being rigid; G the equation's residual,
   computed here from the fields). Round-off: the sums over n terms. */
START_TEST(momentum_is_the_impulse) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  const double nm[2] = {0.25, 0.5}, tau = 0.01, g = 0.5;
  nd_problem p = drop(dim, degree, ND_SCHEME_NEWMARK, nm);
  host h = host_make(p, 0, 0);
  const int64_t n = h.n;
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  int64_t *node = malloc(sizeof(int64_t) * (size_t)n);
  int *comp = malloc(sizeof(int) * (size_t)n);
  ND_OK_OR_FAIL(nd_problem_get_dof_map(p, n, node, comp));
  double *U = malloc(sizeof(double) * (size_t)n), *A = malloc(sizeof(double) * (size_t)n);
  double *C = malloc(sizeof(double) * (size_t)n), *MA = malloc(sizeof(double) * (size_t)n);
  double *KU = malloc(sizeof(double) * (size_t)n), *N = malloc(sizeof(double) * (size_t)n);
  /* per component: the force F + C + G summed, and its absolute sum (round-off scale) */
  double force[2][3], abs_force[2][3], L[2][3];
  int contact = 0;
  for (int step = 0; step <= 25; ++step) {
    const int now = step % 2;
    if (step > 0) ND_OK_OR_FAIL(nd_step(p));
    free_field(p, ND_FIELD_DISPLACEMENT, n, node, comp, dim, U);
    free_field(p, ND_FIELD_ACCELERATION, n, node, comp, dim, A);
    free_field(p, ND_FIELD_CONTACT_FORCE, n, node, comp, dim, C);
    matvec(n, h.M, A, MA);
    matvec(n, h.KT, U, KU);
    ND_OK_OR_FAIL(nd_problem_contact_residual(p, n, U, N));
    for (int c = 0; c < 3; ++c) force[now][c] = abs_force[now][c] = 0;
    for (int64_t i = 0; i < n; ++i) {
      const double G = MA[i] + KU[i] + N[i] - h.F[i]; /* the step equation's residual */
      force[now][comp[i]] += h.F[i] + C[i] + G;
      abs_force[now][comp[i]] += fabs(h.F[i]) + fabs(C[i]) + fabs(MA[i]) + fabs(KU[i]) + fabs(N[i]);
    }
    for (int c = 0; c < dim; ++c) ND_OK_OR_FAIL(nd_get_scalar(p, ND_MOMENTUM_X + c, &L[now][c]));
    for (int c = dim; c < 3; ++c) { /* the components a body of this dimension has not */
      double z = 1;
      ND_OK_OR_FAIL(nd_get_scalar(p, ND_MOMENTUM_X + c, &z));
      ck_assert(z == 0);
    }
    double active = 0;
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_ACTIVE_POINTS, &active));
    contact += active > 0;
    if (step == 0) continue;
    const int was = 1 - now;
    for (int c = 0; c < dim; ++c) {
      const double impulse = tau * ((1 - g) * force[was][c] + g * force[now][c]);
      const double dL = L[now][c] - L[was][c];
      const double round = 8 * DBL_EPSILON * (double)n *
                           (fabs(L[now][c]) + fabs(L[was][c]) + tau * (abs_force[was][c] + abs_force[now][c]));
      ck_assert_msg(fabs(dL - impulse) <= round, "%dD P%d step %d component %d: dL %.17g, impulse %.17g (round %g)",
                    dim, degree, step, c, dL, impulse, round);
    }
  }
  ck_assert(contact >= 3);
  free(U), free(A), free(C), free(MA), free(KU), free(N), free(node), free(comp);
  host_free(&h);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* Free flight without load: the momenta are conserved to round-off, the
   angular one included (K_Theta annihilates the infinitesimal rotations). */
START_TEST(momentum_conserved_in_free_flight) {
  const double nm[2] = {0.25, 0.5};
  for (int dim = 2; dim <= 3; ++dim) {
    nd_problem p = drop_scene(dim, 2, ND_SCHEME_NEWMARK, nm, 1);
    double L0[6], L[6], scale = 0;
    int64_t n = 0, nnz = 0;
    ND_OK_OR_FAIL(nd_problem_get_matrix(p, ND_MATRIX_MASS, &n, &nnz, NULL, NULL, NULL));
    for (int k = 0; k < 6; ++k) {
      ND_OK_OR_FAIL(nd_get_scalar(p, ND_MOMENTUM_X + k, &L0[k]));
      scale += fabs(L0[k]);
    }
    const int steps = 20;
    for (int s = 0; s < steps; ++s) ND_OK_OR_FAIL(nd_step(p));
    /* each step's change is the round-off of sums over the n DOFs */
    const double round = 8 * (double)(steps * n) * DBL_EPSILON * scale;
    double worst = 0;
    for (int k = 0; k < 6; ++k) {
      ND_OK_OR_FAIL(nd_get_scalar(p, ND_MOMENTUM_X + k, &L[k]));
      worst = fmax(worst, fabs(L[k] - L0[k]));
      ck_assert_msg(fabs(L[k] - L0[k]) <= round, "%dD momentum %d: %.17g then %.17g (round-off %g)", dim, k, L0[k],
                    L[k], round);
    }
    printf("free flight %dD P2: momenta changed by %.3g at most in %d steps (round-off bound %.3g)\n", dim, worst,
           steps, round);
    ck_assert(L0[dim - 1] != 0 && (dim == 3 || L0[5] != 0));
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

static Suite *host_suite(void) {
  Suite *s = suite_create("host_newmark");
  TCase *t = tcase_create("host");
  tcase_set_timeout(t, 600);
  tcase_add_loop_test(t, host_loop_follows_nd_step, 0, 4);
  tcase_add_loop_test(t, operators_agree_with_the_library, 0, 4);
  tcase_add_loop_test(t, contact_by_differences_and_state_untouched, 0, 4);
  tcase_add_loop_test(t, hybrid_step_form_by_differences, 0, 4);
  tcase_add_loop_test(t, momentum_is_the_impulse, 0, 4);
  tcase_add_test(t, momentum_conserved_in_free_flight);
  suite_add_tcase(s, t);
  return s;
}

int main(void) { return nd_test_run(host_suite()); }
