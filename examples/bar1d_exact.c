#include "bar1d_exact.h"

#include <math.h>
#include <stdlib.h>

/* ---- exact solution ----------------------------------------------------- */

phase phase_at(double t) {
  double s = fmod(t, 3.0);
  /* t_n = n tau carries round-off: snap to the phase boundary it aims at, so
     that which side of a jump in v or sigma is sampled does not depend on it. */
  if (fabs(s - nearbyint(s)) < 1e-9) s = nearbyint(s);
  if (s >= 3.0) s -= 3.0;
  phase ph = {(int)floor(s), 0.0};
  ph.r = s - ph.k;
  return ph;
}

/* u, du/dt, du/dx at x; at a kink any side will do (it is a single point). */
exact_value exact_at(phase ph, double x) {
  const double r = ph.r;
  exact_value e = {0, 0, 0};
  switch (ph.k) {
    case 0: /* u = (1 - max(x, r))/2: the part x < r already moves down */
      if (x < r) e = (exact_value){0.5 * (1 - r), -0.5, 0.0};
      else e = (exact_value){0.5 * (1 - x), 0.0, -0.5};
      break;
    case 1: { /* u = -min(x, r, 1-x, 1-r)/2: compression wave in, then out */
      const double mt = fmin(r, 1 - r), mx = fmin(x, 1 - x);
      if (mx < mt) e = (exact_value){-0.5 * mx, 0.0, x < 0.5 ? -0.5 : 0.5};
      else e = (exact_value){-0.5 * mt, r < 0.5 ? -0.5 : 0.5, 0.0};
      break;
    }
    default: /* u = min(r, 1-x)/2: the part x < 1-r moves up */
      if (r < 1 - x) e = (exact_value){0.5 * r, 0.5, 0.0};
      else e = (exact_value){0.5 * (1 - x), 0.0, -0.5};
      break;
  }
  return e;
}

/* sigma(0,t) = u_x(0,t): -1/2 while in contact */
double exact_stress(phase ph) { return ph.k == 1 ? -0.5 : 0.0; }

/* ---- FE fields on the sorted nodes ------------------------------------- */

typedef struct {
  double x;
  int64_t id;
} node_key;

static int cmp_node(const void *a, const void *b) {
  const double xa = ((const node_key *)a)->x, xb = ((const node_key *)b)->x;
  return (xa > xb) - (xa < xb);
}

void grid_free(grid *g) {
  free(g->x);
  free(g->id);
  g->x = NULL;
  g->id = NULL;
}

int grid_init(grid *g, int degree, int64_t n_cells, const double *coords, int64_t n_nodes) {
  g->degree = degree;
  g->n_cells = n_cells;
  g->n_nodes = n_nodes;
  g->x = NULL;
  g->id = NULL;
  if (n_nodes != n_cells * degree + 1) return 1; /* the norms rely on it */
  g->x = malloc((size_t)n_nodes * sizeof *g->x);
  g->id = malloc((size_t)n_nodes * sizeof *g->id);
  node_key *keys = malloc((size_t)n_nodes * sizeof *keys);
  if (!g->x || !g->id || !keys) {
    free(keys);
    grid_free(g);
    return 1;
  }
  for (int64_t i = 0; i < n_nodes; ++i) keys[i] = (node_key){coords[i], i};
  qsort(keys, (size_t)n_nodes, sizeof *keys, cmp_node);
  for (int64_t i = 0; i < n_nodes; ++i) {
    g->x[i] = keys[i].x;
    g->id[i] = keys[i].id;
  }
  free(keys);
  return 0;
}

/* Values and derivatives at x of the Lagrange basis on the m nodes xs. */
static void lagrange(int m, const double *xs, double x, double *phi, double *dphi) {
  for (int j = 0; j < m; ++j) {
    phi[j] = 1.0;
    dphi[j] = 0.0;
    for (int i = 0; i < m; ++i) {
      if (i == j) continue;
      double term = 1.0 / (xs[j] - xs[i]); /* d/dx of factor i, times the others */
      for (int l = 0; l < m; ++l)
        if (l != j && l != i) term *= (x - xs[l]) / (xs[j] - xs[l]);
      dphi[j] += term;
      phi[j] *= (x - xs[i]) / (xs[j] - xs[i]);
    }
  }
}

/* Gauss-Legendre rules on [-1,1] with 3 and 4 points. */
static int gauss_rule(int n, double *pt, double *wt) {
  if (n == 3) {
    const double a = sqrt(0.6);
    pt[0] = -a, pt[1] = 0, pt[2] = a;
    wt[0] = 5.0 / 9, wt[1] = 8.0 / 9, wt[2] = 5.0 / 9;
  } else {
    const double a = sqrt(3.0 / 7 - 2.0 / 7 * sqrt(1.2)), b = sqrt(3.0 / 7 + 2.0 / 7 * sqrt(1.2));
    const double wa = (18 + sqrt(30.0)) / 36, wb = (18 - sqrt(30.0)) / 36;
    pt[0] = -b, pt[1] = -a, pt[2] = a, pt[3] = b;
    wt[0] = wb, wt[1] = wa, wt[2] = wa, wt[3] = wb;
    n = 4;
  }
  return n;
}

/* Adds the squared differences at the ng points of one piece: phi, dphi are
   the basis values at the points (dphi already per unit x). */
static void add_piece(space_norms *s, int m, int ng, const double *uc, const double *vc, const double *xq,
                      const double *wq, const double (*phi)[3], const double (*dphi)[3], phase ph) {
  for (int q = 0; q < ng; ++q) {
    double uh = 0, uhx = 0, vh = 0;
    for (int j = 0; j < m; ++j) {
      uh += phi[q][j] * uc[j];
      uhx += dphi[q][j] * uc[j];
      vh += phi[q][j] * vc[j];
    }
    const exact_value e = exact_at(ph, xq[q]);
    const double w = wq[q];
    s->err[0] += w * (uh - e.u) * (uh - e.u);
    s->err[1] += w * (uhx - e.ux) * (uhx - e.ux);
    s->err[2] += w * (vh - e.v) * (vh - e.v);
    s->ref[0] += w * e.u * e.u;
    s->ref[1] += w * e.ux * e.ux;
    s->ref[2] += w * e.v * e.v;
  }
}

/* Exact integrals of the squared differences: the FE field is a polynomial of
   the cell's degree, the exact one is linear between the kinks x = r, 1 - r,
   so each cell is split at the kinks inside it and each piece gets a Gauss
   rule exact for degree 2*degree + 1 or more. Cells without a kink (all but
   two) use basis values tabulated once on the reference cell. */
space_norms norms_at(const grid *g, const double *U, const double *V, phase ph) {
  space_norms s = {{0, 0, 0}, {0, 0, 0}};
  double pt[4], wt[4];
  const int ng = gauss_rule(g->degree + 2, pt, wt), m = g->degree + 1;
  const double k1 = fmin(ph.r, 1 - ph.r), k2 = fmax(ph.r, 1 - ph.r);
  double ref_nodes[3], ref_phi[4][3], ref_dphi[4][3];
  for (int j = 0; j < m; ++j) ref_nodes[j] = -1.0 + 2.0 * j / (m - 1); /* equispaced in the cell */
  for (int q = 0; q < ng; ++q) lagrange(m, ref_nodes, pt[q], ref_phi[q], ref_dphi[q]);
  for (int64_t c = 0; c < g->n_cells; ++c) {
    const int64_t first = c * g->degree;
    const double *xs = g->x + first;
    double uc[3], vc[3];
    for (int j = 0; j < m; ++j) {
      uc[j] = U[g->id[first + j]];
      vc[j] = V[g->id[first + j]];
    }
    double cuts[4], xq[4], wq[4], phi[4][3], dphi[4][3];
    int nc = 0;
    cuts[nc++] = xs[0];
    if (k1 > xs[0] && k1 < xs[m - 1]) cuts[nc++] = k1;
    if (k2 > xs[0] && k2 < xs[m - 1] && k2 > k1) cuts[nc++] = k2;
    cuts[nc++] = xs[m - 1];
    if (nc == 2) {
      const double mid = 0.5 * (xs[0] + xs[m - 1]), half = 0.5 * (xs[m - 1] - xs[0]);
      for (int q = 0; q < ng; ++q) {
        xq[q] = mid + half * pt[q];
        wq[q] = half * wt[q];
        for (int j = 0; j < m; ++j) dphi[q][j] = ref_dphi[q][j] / half;
      }
      add_piece(&s, m, ng, uc, vc, xq, wq, (const double (*)[3])ref_phi, (const double (*)[3])dphi, ph);
      continue;
    }
    for (int p = 0; p + 1 < nc; ++p) {
      const double mid = 0.5 * (cuts[p] + cuts[p + 1]), half = 0.5 * (cuts[p + 1] - cuts[p]);
      for (int q = 0; q < ng; ++q) {
        xq[q] = mid + half * pt[q];
        wq[q] = half * wt[q];
        lagrange(m, xs, xq[q], phi[q], dphi[q]);
      }
      add_piece(&s, m, ng, uc, vc, xq, wq, (const double (*)[3])phi, (const double (*)[3])dphi, ph);
    }
  }
  return s;
}

/* ---- space-time norms --------------------------------------------------- */

const char *const norm_names[N_NORMS] = {
    "Linf(L2) u", "Linf(H1) u", "Linf(L2) v", "L2(L2) u", "L2(H1) u", "L2(L2) v", "L2 contact stress"};

void acc_add(norm_acc *a, const space_norms *s, double sigma_err, double sigma_ref, double w) {
  const double e[N_NORMS] = {s->err[0], s->err[0] + s->err[1], s->err[2], s->err[0], s->err[0] + s->err[1],
                             s->err[2], sigma_err * sigma_err};
  const double r[N_NORMS] = {s->ref[0], s->ref[0] + s->ref[1], s->ref[2], s->ref[0], s->ref[0] + s->ref[1],
                             s->ref[2], sigma_ref * sigma_ref};
  for (int i = 0; i < N_NORMS; ++i) {
    if (i <= LINF_L2_V) {
      a->err[i] = fmax(a->err[i], e[i]);
      a->ref[i] = fmax(a->ref[i], r[i]);
    } else {
      a->err[i] += w * e[i];
      a->ref[i] += w * r[i];
    }
  }
}

double acc_relative(const norm_acc *a, int i) {
  const double e = sqrt(a->err[i]), r = sqrt(a->ref[i]);
  return r > 0 ? e / r : e;
}
