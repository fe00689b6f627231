/* The 1D bar of docs/design.md §7: its exact solution, and relative space-time error
 * norms of a P1/P2 solution against it. Shared by examples/bar1d.c and the
 * convergence test. */
#ifndef ND_BAR1D_EXACT_H
#define ND_BAR1D_EXACT_H
#include <stdint.h>

/* Phase of the period-3 motion: k = 0 flight, 1 contact, 2 release; r in [0,1). */
typedef struct {
  int k;
  double r;
} phase;

typedef struct {
  double u, v, ux;
} exact_value;

/* The FE nodes sorted by coordinate: cell c holds sorted nodes
   c*degree .. c*degree + degree, whatever the library's numbering. */
typedef struct {
  int degree;
  int64_t n_nodes, n_cells;
  double *x;    /* sorted coordinates */
  int64_t *id;  /* id[i] = library index of the i-th sorted node */
} grid;

/* Squared L2 norms at one time level: [0] u, [1] u_x, [2] v. */
typedef struct {
  double err[3], ref[3];
} space_norms;

enum { LINF_L2_U, LINF_H1_U, LINF_L2_V, L2_L2_U, L2_H1_U, L2_L2_V, L2_SIGMA, N_NORMS };

/* Running max (Linf) or trapezoidal sum (L2) of the squares, error and exact. */
typedef struct {
  double err[N_NORMS], ref[N_NORMS];
} norm_acc;

extern const char *const norm_names[N_NORMS];

phase phase_at(double t);
/* u, du/dt, du/dx at x; at a kink any side will do (it is a single point). */
exact_value exact_at(phase ph, double x);
/* sigma(0,t) = u_x(0,t): -1/2 while in contact */
double exact_stress(phase ph);

/* Sorts the n_nodes FE nodes of a P(degree) interval mesh of n_cells cells
   (coordinates in library order); returns non-zero when out of memory or
   when the node count is not n_cells*degree + 1. */
int grid_init(grid *g, int degree, int64_t n_cells, const double *coords, int64_t n_nodes);
void grid_free(grid *g);

/* Exact squared L2 norms at one time level of U, V (library node order). */
space_norms norms_at(const grid *g, const double *U, const double *V, phase ph);
/* Adds one time level with trapezoidal weight w (L2 norms) or max (Linf). */
void acc_add(norm_acc *a, const space_norms *s, double sigma_err, double sigma_ref, double w);
/* The relative error of norm i (the absolute one when the exact norm is 0). */
double acc_relative(const norm_acc *a, int i);

#endif
