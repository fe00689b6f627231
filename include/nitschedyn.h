/*
 * nitschedyn.h - the public C interface of libnitschedyn.
 *
 * Nitsche's method for dynamic frictionless unilateral contact of a linear
 * elastic body with a rigid obstacle (Chouly, Hild, Renard, M2AN 49(2) 2015).
 * This is the public header; nitschedyn_mpi.h adds the one call that takes an
 * MPI_Comm (builds with PETSc). No C++ type crosses it.
 *
 * Conventions (see libnitschedyn(3)):
 *  - every function returns an int status: ND_OK (0) on success, a negative
 *    ND_ERR_* code on error; nd_last_error() then tells what went wrong;
 *  - handles are typed and opaque; create functions write them through an
 *    out-parameter, destroy functions take their address and set it to NULL;
 *  - sizes and indices are int64_t, booleans are int, arrays come with their
 *    lengths and are copied;
 *  - distinct handles may be used from distinct threads at the same time,
 *    one handle from one thread at a time.
 */
#ifndef NITSCHEDYN_H
#define NITSCHEDYN_H

#include <stdint.h>

#define ND_VERSION_MAJOR 0
#define ND_VERSION_MINOR 1
#define ND_VERSION_PATCH 0
#define ND_VERSION_STRING "0.1.0"

#if defined(ND_BUILDING_LIBRARY) && defined(__GNUC__)
#define ND_EXPORT __attribute__((visibility("default")))
#else
#define ND_EXPORT
#endif

#ifdef __cplusplus
extern "C" {
#endif

/*
 * Every list of constants is an X-macro: the C enums below, nd_strerror()
 * and the Fortran parameters are all generated from these lists. Values are
 * explicit and only ever appended.
 */

/* Status codes: X(name, value, message) */
#define ND_STATUS_LIST(X)                                                              \
  X(ND_OK, 0, "success")                                                               \
  X(ND_MONITOR_STOP, 1, "the step was accepted and the monitor asked to stop")        \
  X(ND_ERR_NULL, -1, "a required handle or pointer is NULL")                           \
  X(ND_ERR_DIMENSION, -2, "the space dimension is not 1, 2 or 3, or does not match")   \
  X(ND_ERR_SIZE, -3, "a count is not positive or an array length does not match")      \
  X(ND_ERR_INDEX, -4, "an index is out of range")                                      \
  X(ND_ERR_NONFINITE, -5, "an input value is NaN or infinite")                         \
  X(ND_ERR_DEGENERATE, -6, "a cell has zero or negative measure")                      \
  X(ND_ERR_DEGREE, -7, "the polynomial degree is not 1 or 2")                          \
  X(ND_ERR_MATERIAL, -8, "a material parameter is out of range")                       \
  X(ND_ERR_NITSCHE, -9, "a Nitsche parameter is out of range")                         \
  X(ND_ERR_TIMESTEP, -10, "the time step is not positive and finite")                  \
  X(ND_ERR_SCHEME, -11, "unknown time scheme or scheme parameter out of range")        \
  X(ND_ERR_KEY, -12, "unknown field, scalar key or option value")                      \
  X(ND_ERR_INCOMPLETE, -13, "the problem is not complete enough for this call")        \
  X(ND_ERR_REGION, -14, "a region or facet is invalid")                                \
  X(ND_ERR_VALUE, -15, "an option value is out of range")                              \
  X(ND_ERR_NEWTON, -16, "Newton's method did not converge; the step was not taken")    \
  X(ND_ERR_NONFINITE_STATE, -17, "the step produced NaN or infinite values; not taken")\
  X(ND_ERR_INDEFINITE, -18, "the step operator c*M + K_Theta is not positive definite")\
  X(ND_ERR_SINGULAR, -19, "a matrix is singular")                                      \
  X(ND_ERR_NOMEM, -20, "out of memory")                                                \
  X(ND_ERR_INTERNAL, -21, "internal error")                                           \
  X(ND_ERR_STATE, -22, "the call is not allowed in the problem's current state")      \
  X(ND_ERR_IO, -23, "a file could not be opened, read or written")                     \
  X(ND_ERR_FORMAT, -24, "a file is malformed or uses an unsupported format")          \
  X(ND_ERR_NOT_COERCIVE, -25, "K_Theta is not positive semi-definite: gamma0 too large for Theta") \
  X(ND_ERR_UNSTABLE, -26, "the scheme is unstable with this time step (explicit, or theta < 1/2)") \
  X(ND_ERR_ENERGY_GROWTH, -27, "the energy guard refused the step: energy grew past the loads' work") \
  X(ND_ERR_PENETRATION, -28, "the penetration guard refused the step or the initial state") \
  X(ND_ERR_CALLBACK, -30, "a user callback failed (returned non-zero); the step was not taken") \
  X(ND_ERR_ACCURACY, -31, "adaptive steps: the error estimate stayed above the tolerance at tau_min; not taken")

/* Time schemes for nd_problem_set_scheme: X(name, value, parameters) */
#define ND_SCHEME_LIST(X)                                                              \
  X(ND_SCHEME_THETA, 1, "theta in [0,1]; theta = 0 is explicit")                       \
  X(ND_SCHEME_NEWMARK, 2, "beta in [0,1/2], gamma in [0,1]; beta = 0 is explicit")     \
  X(ND_SCHEME_HYBRID, 3, "no parameter")                                               \
  X(ND_SCHEME_GENERALIZED_ALPHA, 4, "rho_inf in [0,1]")

/* Fields for nd_get_field: X(name, value, description) */
#define ND_FIELD_LIST(X)                                                               \
  X(ND_FIELD_DISPLACEMENT, 1, "displacement u")                                        \
  X(ND_FIELD_VELOCITY, 2, "velocity v")                                                \
  X(ND_FIELD_ACCELERATION, 3, "acceleration a")                                        \
  X(ND_FIELD_CONTACT_FORCE, 4, "nodal contact force, obstacle on body")                \
  X(ND_FIELD_REACTION, 5, "reactions on the clamped DOFs, support on body (0 elsewhere)")

/* Scalars for nd_get_scalar: X(name, value, description) */
#define ND_SCALAR_LIST(X)                                                              \
  X(ND_TIME, 1, "time t^n")                                                            \
  X(ND_STEP_INDEX, 2, "number of accepted steps n")                                    \
  X(ND_ENERGY_MECHANICAL, 3, "E = 1/2 V'MV + 1/2 U'KU")                                \
  X(ND_ENERGY_NITSCHE, 4, "R = 1/2 sum_q w_q (gamma_q (s_q U)^2 - [P_q]_+^2/gamma_q)") \
  X(ND_ENERGY_AUGMENTED, 5, "E_Theta = E - Theta R")                                   \
  X(ND_WORK, 6, "W, work of the external loads since t = 0")                           \
  X(ND_CONTACT_FORCE, 7, "sum_q w_q [P_q]_+/gamma_q, resultant normal contact force")  \
  X(ND_NEWTON_ITERATIONS, 8, "Newton iterations (linear solves) of the last step")     \
  X(ND_ACTIVE_POINTS, 9, "number of contact points with P_q > 0")                      \
  X(ND_MAX_PENETRATION, 10, "max_q (u_n - g0)_+ at the contact points")                \
  X(ND_NEWTON_ITERATIONS_TOTAL, 11, "Newton iterations of all accepted steps")         \
  X(ND_TIMESTEP, 12, "the time step tau (adaptive steps: the size the next step tries)") \
  X(ND_GAMMA0, 13, "gamma0 in use (the automatic value when 0 was set)")               \
  X(ND_GAMMA0_LIMIT, 14, "largest gamma0 keeping K_Theta >= 0 (element bound; inf if Theta <= 0)") \
  X(ND_WORK_OBSTACLE, 15, "work of the moving obstacle on the body since t = 0")       \
  X(ND_STAT_FACTORIZATIONS, 16, "numeric factorizations of any matrix since nd_problem_create")       \
  X(ND_STAT_SYMBOLIC_ANALYSES, 17, "symbolic analyses (orderings) of a pattern since creation")         \
  X(ND_STAT_SOLVES, 18, "forward/backward solves with a factor, one per right-hand side")                \
  X(ND_STAT_MATRIX_ASSEMBLIES, 19, "matrices assembled (M, K, K_Theta, A = c M + K_Theta)")            \
  X(ND_STAT_LOAD_ASSEMBLIES, 20, "load vectors built (body force and tractions, nodal forces)")        \
  X(ND_STAT_TANGENT_UPDATES, 21, "Newton tangents: low-rank capacitance builds or tangent assemblies") \
  X(ND_STAT_CONTACT_EVALUATIONS, 22, "passes evaluating P_q over all contact points")                  \
  X(ND_STAT_SPMV, 23, "sparse matrix-vector products (a step's one pass over M and K counts once)")   \
  X(ND_CONTACT_FORCE_APPLIED, 24, "sum_q w_q phi_q/gamma_q, resultant contact force the last step applied") \
  X(ND_STAT_POINT_EVALUATIONS, 25, "P_q of one contact point evaluated by a step, summed over the ranks")  \
  X(ND_STAT_POINT_EVALUATIONS_OWN, 26, "the same, by this rank (the points of its cells)")            \
  X(ND_STAT_CONTACT_BOUNDS, 27, "contact checks settled by a bound from the last evaluated P_q, no point evaluated")   \
  X(ND_STAT_MATRIX_ENTRIES_OWN, 28, "entries of M, K and K_Theta this rank holds now (its rows when split)") \
  X(ND_STAT_VALUES_RECEIVED, 29, "values this rank received from the other ranks (gathered work and solutions)") \
  X(ND_STAT_POINT_VALUES_RECEIVED, 30, "of them, the contact points' values (P_q, u_n - g0) other ranks evaluated") \
  X(ND_STAT_KRYLOV_ITERATIONS, 31, "Krylov iterations of the iterative solves (ND_SOLVER_PETSC_GAMG), summed") \
  X(ND_STAT_PREDICTED_STEPS, 32, "implicit steps their predictor solved to round-off (constant acceleration): no solve") \
  X(ND_STAT_LAGGED_STEPS, 33, "contact steps whose first Newton iteration kept the last step's tangent factor") \
  X(ND_STAT_FACTOR_MODIFICATIONS, 34, "rank-one updates and downdates of the Newton tangent's updated factor") \
  X(ND_STAT_FACTOR_MODIFIED_ENTRIES, 35, "their work: entries of L times the vectors that rotated them") \
  X(ND_PARTITION_KIND, 36, "the cells' partition over the ranks: 0 one rank, 1 a graph partitioner (PT-Scotch, ParMETIS), 2 slabs") \
  X(ND_MOMENTUM_X, 40, "linear momentum sum_i (M V)_i of the x components (clamped rows included)") \
  X(ND_MOMENTUM_Y, 41, "linear momentum, y components (0 below 2D)")                 \
  X(ND_MOMENTUM_Z, 42, "linear momentum, z components (0 below 3D)")                 \
  X(ND_ANGULAR_MOMENTUM_X, 43, "angular momentum sum_i x_i x (M V)_i about the origin, x (0 below 3D)") \
  X(ND_ANGULAR_MOMENTUM_Y, 44, "angular momentum about the origin, y (0 below 3D)")  \
  X(ND_ANGULAR_MOMENTUM_Z, 45, "angular momentum about the origin, z (0 in 1D)")               \
  X(ND_STAT_NORMAL_REFRESHES, 50, "contact points whose frozen normal was refreshed (curved obstacles)") \
  X(ND_DISSIPATION_FRICTION, 55, "D_f, energy the friction dissipated since t = 0 (>= 0, non-decreasing)") \
  X(ND_SLIDING_POINTS, 56, "contact points in contact and sliding at the last step (friction)") \
  X(ND_STICKING_POINTS, 57, "contact points in contact and sticking at the last step (friction)") \
  X(ND_DISSIPATION_DAMPING, 60, "dissipation of the Rayleigh damping since t = 0") \
  X(ND_WORK_PRESCRIBED, 70, "work of the prescribed motion on the body since t = 0") \
  X(ND_WORK_GEOMETRY, 71, "E_Theta change of curved obstacles' re-linearisations (gaps, refreshed normals) since t = 0") \
  X(ND_CONTACT_FORCE_TANGENTIAL_X, 75, "x of the tangential contact force's resultant the last step applied, obstacle on body") \
  X(ND_CONTACT_FORCE_TANGENTIAL_Y, 76, "y of that resultant (0 in 1D)")                \
  X(ND_CONTACT_FORCE_TANGENTIAL_Z, 77, "z of that resultant (0 below 3D)") \
  X(ND_STAT_STEPS_ACCEPTED, 80, "steps nd_step took since nd_problem_create") \
  X(ND_STAT_STEPS_REJECTED, 81, "adaptive steps tried and rejected (retried smaller) since creation") \
  X(ND_TIMESTEP_LAST, 82, "the size of the step that led to t^n (0 at t^0)") \
  X(ND_ERROR_ESTIMATE, 83, "adaptive steps: the last step's error estimate over the tolerance (<= 1)")

/* Linear solvers for nd_problem_set_linear_solver: X(name, value, description) */
#define ND_SOLVER_LIST(X)                                                              \
  X(ND_SOLVER_AUTO, 0, "choose by size and structure")                                 \
  X(ND_SOLVER_DENSE, 1, "LAPACK dense Cholesky / LU")                                  \
  X(ND_SOLVER_BANDED, 2, "LAPACK banded Cholesky / LU after reverse Cuthill-McKee")   \
  X(ND_SOLVER_CHOLMOD, 3, "SuiteSparse CHOLMOD (symmetric positive definite)")          \
  X(ND_SOLVER_UMFPACK, 4, "SuiteSparse UMFPACK (general sparse LU)")                    \
  X(ND_SOLVER_KLU, 5, "SuiteSparse KLU (general sparse LU)")                      \
  X(ND_SOLVER_PETSC_MUMPS, 6, "PETSc + MUMPS Cholesky (LDL^T) / LU (builds with ND_WITH_PETSC)") \
  X(ND_SOLVER_PETSC_GAMG, 7, "PETSc CG / GMRES + GAMG, rigid-body near-null space (ND_WITH_PETSC)")

/* Guards for nd_problem_set_guard: X(name, value, description) */
#define ND_GUARD_LIST(X)                                                                \
  X(ND_GUARD_ENERGY, 1, "factor f (a backstop): refuse a step with E > f (E^0 + max_k W^k); 0 off; default 2") \
  X(ND_GUARD_PENETRATION, 2, "refuse u_n - g0 > f eps* min(h_K, L/8), eps* the strain of the energy put in; 0 off; default 4") \
  X(ND_GUARD_CRITICAL_TIMESTEP, 3, "1: refuse explicit steps above tau_c (default); 0: allow") \
  X(ND_GUARD_UNSTABLE_SCHEME, 4, "1: refuse the theta-scheme with theta < 1/2 (default); 0: allow") \
  X(ND_GUARD_COERCIVITY, 5, "1: refuse Theta > 0 with K_Theta indefinite (default); 0: allow") \
  X(ND_GUARD_INITIAL_PENETRATION, 6, "1: refuse an initial state inside the obstacle (default); 0: allow") \
  X(ND_GUARD_ENERGY_BALANCE, 7, "tol: refuse a gain of the balance E_Theta - works + dissipations above tol times the energy in motion; 0 off; default 0.05")

/* Operators for nd_problem_get_matrix, on the free DOFs: X(name, value, description) */
#define ND_MATRIX_LIST(X)                                                              \
  X(ND_MATRIX_MASS, 1, "M, the mass the scheme uses (consistent, lumped or redistributed)") \
  X(ND_MATRIX_STIFFNESS, 2, "K, the stiffness")                                        \
  X(ND_MATRIX_NITSCHE, 3, "K_Theta - K = -Theta sum_q w_q gamma_q s_q^T s_q")           \
  X(ND_MATRIX_STEP, 4, "c M + K_Theta of the scheme and time step set (implicit schemes)") \
  X(ND_MATRIX_LUMPED_MASS, 5, "the lumped (HRZ) mass, diagonal, whatever mass the scheme uses") \
  X(ND_MATRIX_DAMPING, 6, "C = alpha M + beta K, the Rayleigh damping (zero when off)")

/* Friction laws for nd_problem_set_friction: X(name, value, parameters) */
#define ND_FRICTION_LIST(X)                                                            \
  X(ND_FRICTION_NONE, 0, "frictionless; no parameter")                                 \
  X(ND_FRICTION_TRESCA, 1, "params[0] = s >= 0, the threshold (a stress), on the whole region") \
  X(ND_FRICTION_COULOMB, 2, "params[0] = F >= 0, the friction coefficient")

/* Cell types for nd_mesh_create_cells and the generators: X(name, value, description) */
#define ND_CELL_LIST(X)                                                                \
  X(ND_CELL_SIMPLEX, 0, "intervals, triangles, tetrahedra: dim + 1 vertices; P1, P2")  \
  X(ND_CELL_QUADRILATERAL, 1, "2D, 4 vertices counter-clockwise; Q1, Q2 (9 nodes)")    \
  X(ND_CELL_HEXAHEDRON, 2, "3D, 8 vertices: the bottom face counter-clockwise, then the top; Q1, Q2 (27 nodes)")

#define ND_ENUM_ENTRY_(name, value, text) name = value,
enum nd_status { ND_STATUS_LIST(ND_ENUM_ENTRY_) };
enum nd_scheme { ND_SCHEME_LIST(ND_ENUM_ENTRY_) };
enum nd_field { ND_FIELD_LIST(ND_ENUM_ENTRY_) };
enum nd_scalar { ND_SCALAR_LIST(ND_ENUM_ENTRY_) };
enum nd_solver { ND_SOLVER_LIST(ND_ENUM_ENTRY_) };
enum nd_guard { ND_GUARD_LIST(ND_ENUM_ENTRY_) };
enum nd_matrix { ND_MATRIX_LIST(ND_ENUM_ENTRY_) };
enum nd_friction { ND_FRICTION_LIST(ND_ENUM_ENTRY_) };
enum nd_cell_type { ND_CELL_LIST(ND_ENUM_ENTRY_) };
#undef ND_ENUM_ENTRY_

typedef struct nd_mesh_s *nd_mesh;
typedef struct nd_problem_s *nd_problem;

/* Monitor: called after every accepted step; a non-zero return makes
   nd_step return ND_MONITOR_STOP (the step itself is kept). */
typedef int (*nd_monitor_fn)(nd_problem p, void *userdata);

/* ---- library ----------------------------------------------------------- */
ND_EXPORT int nd_version(int *major, int *minor, int *patch);
ND_EXPORT const char *nd_last_error(void);
ND_EXPORT const char *nd_strerror(int code);
/* BLAS threads used inside the library's calls (process-wide; default 1):
   n >= 1 limits the BLAS to n threads during each call and restores the
   caller's count on return; 0 leaves the BLAS as the caller set it. */
ND_EXPORT int nd_set_blas_threads(int threads);
ND_EXPORT int nd_get_blas_threads(int *threads);

/* ---- mesh -------------------------------------------------------------- */
/* coords node-major (n_nodes*dim); cells are simplices, dim+1 0-based vertex
   indices each; both copied. */
ND_EXPORT int nd_mesh_create(int dim, int64_t n_nodes, const double *coords,
                             int64_t n_cells, const int64_t *cells, nd_mesh *out);
ND_EXPORT int nd_mesh_create_interval(int64_t n_cells, double a, double b, nd_mesh *out);
/* nx*ny rectangles of [lo, hi], each split into 2 triangles */
ND_EXPORT int nd_mesh_create_rectangle(int64_t nx, int64_t ny, const double lo[2],
                                       const double hi[2], nd_mesh *out);
/* nx*ny*nz boxes of [lo, hi], each split into 6 tetrahedra */
ND_EXPORT int nd_mesh_create_box(int64_t nx, int64_t ny, int64_t nz, const double lo[3],
                                 const double hi[3], nd_mesh *out);
/* As nd_mesh_create with a cell type of ND_CELL_LIST: ND_CELL_SIMPLEX is
   nd_mesh_create; ND_CELL_QUADRILATERAL (dim 2) and ND_CELL_HEXAHEDRON
   (dim 3) cells have 2^dim vertices each, in the VTK and Gmsh order. */
ND_EXPORT int nd_mesh_create_cells(int dim, int cell_type, int64_t n_nodes, const double *coords,
                                   int64_t n_cells, const int64_t *cells, nd_mesh *out);
/* A mesh whose cells have their own types: cell_types[c] of ND_CELL_LIST,
   cells each cell's vertices in turn (as many as its type has). 2D mixes
   triangles and quadrilaterals; in 1D and 3D all cells have one type
   (ND_ERR_DIMENSION: a tetrahedron/hexahedron mix needs prisms or pyramids). */
ND_EXPORT int nd_mesh_create_mixed(int dim, int64_t n_nodes, const double *coords, int64_t n_cells,
                                   const int *cell_types, const int64_t *cells, nd_mesh *out);
/* The generators with a cell type: ND_CELL_SIMPLEX gives the meshes above,
   ND_CELL_QUADRILATERAL (rectangle) and ND_CELL_HEXAHEDRON (box) keep each
   rectangle or box whole. */
ND_EXPORT int nd_mesh_create_rectangle_cells(int64_t nx, int64_t ny, const double lo[2], const double hi[2],
                                             int cell_type, nd_mesh *out);
ND_EXPORT int nd_mesh_create_box_cells(int64_t nx, int64_t ny, int64_t nz, const double lo[3],
                                       const double hi[3], int cell_type, nd_mesh *out);
/* Gmsh MSH 4.1 or 2.2, ASCII: the cells of the top dimension; each physical
   group of facets becomes the region with the group's tag, each physical
   group of cells the cell region with its tag (a cell in several groups:
   the largest tag). */
ND_EXPORT int nd_mesh_read_gmsh(const char *path, nd_mesh *out);
/* Adds boundary facets (dim vertices each; a hexahedron's face: 4) to a
   region (region >= 0). */
ND_EXPORT int nd_mesh_set_region(nd_mesh m, int region, int64_t n_facets,
                                 const int64_t *facet_vertices);
/* Adds the boundary facets whose vertices all lie in the box [lo, hi]. */
ND_EXPORT int nd_mesh_mark_boundary_box(nd_mesh m, int region, const double *lo,
                                        const double *hi);
/* Puts n_cells cells (0-based indices) in cell region cell_region (>= 0),
   taking them out of the region they were in; a cell in no region is in
   region 0. Materials per cell region: nd_problem_set_material_region. */
ND_EXPORT int nd_mesh_set_cell_region(nd_mesh m, int cell_region, int64_t n_cells, const int64_t *cells);
/* Each cell's region (n_cells = the mesh's cell count values; 0: none). */
ND_EXPORT int nd_mesh_get_cell_regions(nd_mesh m, int64_t n_cells, int *region);
ND_EXPORT int nd_mesh_get_dimension(nd_mesh m, int *dim);
ND_EXPORT int nd_mesh_get_vertex_count(nd_mesh m, int64_t *n_vertices);
ND_EXPORT int nd_mesh_get_cell_count(nd_mesh m, int64_t *n_cells);
ND_EXPORT int nd_mesh_get_region_size(nd_mesh m, int region, int64_t *n_facets);
ND_EXPORT int nd_mesh_destroy(nd_mesh *m);

/* ---- problem: definition ---------------------------------------------- */
/* The problem keeps its own copy of the mesh (regions included). */
ND_EXPORT int nd_problem_create(nd_mesh m, int degree, nd_problem *out);
/* Isotropic: Young's modulus E > 0, Poisson's ratio in (-1, 1/2), density > 0.
   2D is plane strain. In 1D sigma = E u_x and `poisson` is ignored. */
ND_EXPORT int nd_problem_set_material(nd_problem p, double young, double poisson,
                                      double density);
/* The material of the cells of cell region cell_region (>= 1, with cells in
   the problem's mesh); the other cells keep nd_problem_set_material's, which
   stays required. Checked as nd_problem_set_material. */
ND_EXPORT int nd_problem_set_material_region(nd_problem p, int cell_region, double young, double poisson,
                                             double density);
ND_EXPORT int nd_problem_set_dirichlet(nd_problem p, int region);
/* Prescribed motion of a clamped region: the displacement (dim values, the
   same for every node of the region) its clamped DOFs take at t^{n+1} of the
   next step, set before each step as loads are (before the first step a
   first call gives t^0's value, a second t^1's). The nodal form sets every
   clamped DOF (n = node count, n*dim values; the free DOFs' are not read).
   Velocity and acceleration there follow the scheme. Default 0. */
ND_EXPORT int nd_problem_set_dirichlet_value(nd_problem p, int region, const double *u);
ND_EXPORT int nd_problem_set_dirichlet_nodal(nd_problem p, int64_t n, const double *u);
ND_EXPORT int nd_problem_set_body_force(nd_problem p, const double *f);
ND_EXPORT int nd_problem_set_neumann(nd_problem p, int region, const double *g);
/* normal points from the obstacle towards the body; a region's plane is
   replaced. Same normal, new point: the obstacle moves (nothing is rebuilt;
   after nd_problem_setup the point is where it is at the next step's end) */
ND_EXPORT int nd_problem_set_contact_plane(nd_problem p, int region, const double *point,
                                           const double *normal);
/* gamma = gamma0 * h_K (h_K the diameter of the cell owning the facet; times
   E / E_K with several materials, nd_problem_set_material_region);
   gamma0 = 0 chooses a safe value (half the coercivity limit; 1/50 of it with
   Theta <= 0 and the hybrid scheme; ND_GAMMA0) */
/* More rigid obstacles for a region (docs/design.md §10.1); at each contact
   point the nearest acts. inside = 1: the body is inside the shell (a bowl).
   A sphere is a circle in 2D; a cylinder (infinite, of this axis) is 3D. */
ND_EXPORT int nd_problem_add_contact_sphere(nd_problem p, int region, const double *center, double radius,
                                            int inside);
ND_EXPORT int nd_problem_add_contact_cylinder(nd_problem p, int region, const double *point, const double *axis,
                                              double radius, int inside);
/* The signed distance (positive on the body's side) and the unit normal from
   the obstacle towards the body at x and time t (dim values each); non-zero:
   the step fails with ND_ERR_CALLBACK and is not taken. */
typedef int (*nd_distance_fn)(double t, const double *x, double *distance, double *normal, void *user);
ND_EXPORT int nd_problem_add_contact_distance(nd_problem p, int region, nd_distance_fn f, void *user);
/* Contact between two bodies (docs/design.md §10.3): the contact points of
   region `slave` against the surface of region `master` (master/slave
   Nitsche, any Theta), paired anew from the current positions as they
   slide. Both regions of one mesh (its connected components are the bodies);
   a slave region has one master (set again: replaced), which may be itself:
   a body touching itself through one region (its points then skip their own
   neighbourhood and the facets not facing them). */
ND_EXPORT int nd_problem_set_contact_pair(nd_problem p, int slave, int master);
/* Places the region's obstacle `index` (0-based, in the order added; the
   plane moves with nd_problem_set_contact_plane) at x -> R x + translation
   relative to its definition (rotation: dim x dim row-major, NULL: none):
   where it is at t^{n+1} of the next step (before the first step, a first
   call gives t^0's pose, a second t^1's). */
ND_EXPORT int nd_problem_move_obstacle(nd_problem p, int region, int index, const double *translation,
                                       const double *rotation);
/* The friction law of a contact region (docs/design.md §10.2): law one of
   ND_FRICTION_LIST, params its parameters (NULL for ND_FRICTION_NONE). 2D
   and 3D; the region's obstacle its plane alone (it may move: slip is
   relative to it), or a contact pair's master surface (the region the
   pair's slave: friction between two bodies); one rank. */
ND_EXPORT int nd_problem_set_friction(nd_problem p, int region, int law, const double *params);
ND_EXPORT int nd_problem_set_nitsche(nd_problem p, double theta, double gamma0);
ND_EXPORT int nd_problem_set_scheme(nd_problem p, int scheme, const double *params);
/* Extra force per FE node (n = node count, n*dim values), e.g. from a coupled
   code; replaces the previous values (zeros remove them). A step uses the
   values set at its start as F^{n+1}. */
ND_EXPORT int nd_problem_set_nodal_forces(nd_problem p, int64_t n, const double *f);
ND_EXPORT int nd_problem_set_newton(nd_problem p, double rtol, double atol, int max_iter);
ND_EXPORT int nd_problem_set_mass_lumping(nd_problem p, int lumped);
/* Rayleigh damping C = alpha M + beta K (M the scheme's mass), alpha, beta
   >= 0 and finite; 0, 0 (the default) is off. Every scheme applies C V at
   its own point (docs/design.md §10.5); ND_DISSIPATION_DAMPING sums it. */
ND_EXPORT int nd_problem_set_damping(nd_problem p, double alpha, double beta);
/* on = 1: plane stress in 2D (lambda* = 2 lambda mu/(lambda + 2 mu));
   default 0, plane strain. In 1D and 3D only 0 is accepted. */
ND_EXPORT int nd_problem_set_plane_stress(nd_problem p, int on);
/* on = 1: the FE nodes of the contact facets get no mass, each cell touching
   them gives its mass to its other nodes keeping the total mass (and the
   first and second moments where its nodes allow); with an explicit scheme
   their DOFs are found each step from their static equilibrium. Default 0. */
ND_EXPORT int nd_problem_set_mass_redistribution(nd_problem p, int on);
ND_EXPORT int nd_problem_set_linear_solver(nd_problem p, int solver);
/* The ranks of an MPI job that step this problem together, as Fortran's
   integer handle (MPI_COMM_WORLD of `use mpi`); from C nd_problem_set_comm
   (nitschedyn_mpi.h). Every rank creates the same mesh and problem and makes
   the same calls; the PETSc solvers then distribute the matrix and the solve.
   Collective, before nd_problem_setup. Without PETSc: ND_ERR_KEY. */
ND_EXPORT int nd_problem_set_comm_f(nd_problem p, int fortran_comm);
/* on = 1: with a communicator and a PETSc solver (the rows split over the
   ranks), each rank keeps the state right on the rows its steps read only,
   and an implicit step gathers no whole solution; nd_get_field,
   nd_problem_set_state and the checkpoint calls then gather the state, and
   are collective. nd_get_field_owned, nd_get_field_gathered and
   nd_get_scalar read it as it is. Default 0 (every rank holds the whole
   state after each step). Before nd_problem_setup. */
ND_EXPORT int nd_problem_set_distributed_state(nd_problem p, int on);
ND_EXPORT int nd_problem_set_timestep(nd_problem p, double tau);
/* Adaptive time steps, off by default (tolerance 0 turns them off): each
   nd_step takes one step of a size in [tau_min, tau_max] (tau_max/2^k or
   tau_min) chosen by its error estimate (the local truncation error
   relative to the largest displacement, and the step's gain of the energy
   balance relative to the energy in motion, both below tolerance); a
   rejected or failed try is retried smaller and leaves no trace; the step
   that first makes a contact point active ends at the first touch. The
   first step tries the size of nd_problem_set_timestep (tau_max if none).
   Implicit schemes, one process. */
ND_EXPORT int nd_problem_set_adaptive_timestep(nd_problem p, double tolerance, double tau_min,
                                               double tau_max);
/* u0, v0 per FE node (n*dim values each); NULL means zero. Values at clamped
   DOFs are ignored. Resets the time, the step count and the work to 0. */
ND_EXPORT int nd_problem_set_initial_state(nd_problem p, int64_t n, const double *u0,
                                           const double *v0);
ND_EXPORT int nd_problem_set_monitor(nd_problem p, nd_monitor_fn fn, void *userdata);
/* Sets or disables (value 0) one of the checks of ND_GUARD_LIST. */
ND_EXPORT int nd_problem_set_guard(nd_problem p, int guard, double value);

/* ---- problem: queries -------------------------------------------------- */
/* FE nodes: the mesh vertices first (same numbering), then for P2 one node
   per edge midpoint. */
ND_EXPORT int nd_problem_get_node_count(nd_problem p, int64_t *n_nodes);
ND_EXPORT int nd_problem_get_node_coordinates(nd_problem p, int64_t n, double *coords);
ND_EXPORT int nd_problem_get_contact_point_count(nd_problem p, int64_t *n_points);
/* The contact quadrature points (n*dim coordinates) and their weights; either
   array may be NULL. Needs the material and Nitsche parameters (the rows of
   every point are built with the points). */
ND_EXPORT int nd_problem_get_contact_points(nd_problem p, int64_t n, double *coords,
                                            double *weights);

/* ---- time stepping ----------------------------------------------------- */
/* Assembles, factorizes and computes the initial acceleration now rather
   than in the first nd_step (which calls it when needed): to time the set-up
   apart, or to learn of an ill-posed step before stepping. */
ND_EXPORT int nd_problem_setup(nd_problem p);
/* The critical time step of an explicit scheme: limit/omega_max, omega_max
   the highest frequency with every contact point active (Lanczos), limit the
   scheme's (2 for the central difference; 2 when the scheme set is implicit). */
ND_EXPORT int nd_problem_estimate_critical_timestep(nd_problem p, double *tau_c);
ND_EXPORT int nd_step(nd_problem p);
ND_EXPORT int nd_get_field(nd_problem p, int field, int64_t n, double *out);
/* The FE nodes this rank owns (every node has one owner among the ranks of
   the problem's communicator, see nd_problem_set_comm_f; without one, or in
   a build without MPI, the process owns every node): their count, and one
   field's values at them (n_owned*dim, node-major) with their node numbers
   (n_owned, ascending); values or nodes may be NULL. Over the ranks the parts
   are disjoint and cover every node, with nd_get_field's values. */
ND_EXPORT int nd_problem_get_owned_node_count(nd_problem p, int64_t *n_owned);
ND_EXPORT int nd_get_field_owned(nd_problem p, int field, int64_t n_owned, double *values, int64_t *nodes);
/* The whole field on one rank: out (n*dim, n the node count) on rank `root`
   of the problem's communicator, each node's values from the rank that owns
   it; out and n are not read on the other ranks (out may be NULL there).
   Collective: every rank calls it with the same field and root, and a call
   refused on one rank is refused on all. Without a communicator root is 0 and
   it is nd_get_field. */
ND_EXPORT int nd_get_field_gathered(nd_problem p, int field, int root, int64_t n, double *out);
ND_EXPORT int nd_get_scalar(nd_problem p, int key, double *out);
/* A contact scalar of one contact region's points alone (a contact pair's:
   its slave region): ND_CONTACT_FORCE, ND_CONTACT_FORCE_APPLIED,
   ND_ACTIVE_POINTS, ND_MAX_PENETRATION or ND_ENERGY_NITSCHE (its part of R);
   with friction ND_DISSIPATION_FRICTION, ND_SLIDING_POINTS,
   ND_STICKING_POINTS and ND_CONTACT_FORCE_TANGENTIAL_X/Y/Z (0 without).
   The regions' values add up to nd_get_scalar's (the deepest: its max). */
ND_EXPORT int nd_get_region_scalar(nd_problem p, int region, int key, double *out);
/* Checkpoint: the whole state at t^n (t, n, U, V, A, F^n, W, Newton totals,
   the guards' reference) as a versioned, checksummed block of nbytes bytes;
   a run resumed from it is bitwise the uninterrupted one. Loading checks the
   problem's structure and changes nothing when it fails. */
ND_EXPORT int nd_problem_get_state_size(nd_problem p, int64_t *nbytes);
ND_EXPORT int nd_problem_save_state(nd_problem p, int64_t nbytes, void *buf);
ND_EXPORT int nd_problem_load_state(nd_problem p, int64_t nbytes, const void *buf);
/* The same block in a file: written atomically (a temporary file in the same
   directory, synced, renamed; an earlier file at path survives a failure);
   read with the checks of nd_problem_load_state. */
ND_EXPORT int nd_problem_save_state_file(nd_problem p, const char *path);
ND_EXPORT int nd_problem_load_state_file(nd_problem p, const char *path);
/* Overwrites u, v (per FE node, n*dim values; NULL keeps one) at the current
   time, e.g. after a coupled code's own sub-cycling: t, n and W stay, the
   acceleration is re-derived. */
ND_EXPORT int nd_problem_set_state(nd_problem p, int64_t n, const double *u, const double *v);
/* lambda_q = -[P_q]_+/gamma_q at each contact point (<= 0: compression) */
ND_EXPORT int nd_get_contact_pressure(nd_problem p, int64_t n, double *out);
/* -phi_q/gamma_q: the pressure the last step applied (its contact term phi_q:
   the hybrid's Phi_q, generalized-alpha's at the alpha_f point, the end-of-step
   [P_q]_+ for the theta-scheme and Newmark); lambda_q before the first step */
ND_EXPORT int nd_get_contact_pressure_applied(nd_problem p, int64_t n, double *out);
ND_EXPORT int nd_problem_destroy(nd_problem *p);

/* ---- operators out (nd_problem_get_matrix(3)) ------------------------- */
/* Free DOFs (the unknowns after Dirichlet elimination), CSR 0-based, rows
   ascending, columns sorted in each row. Two calls: with row_ptr, col_idx
   and values all NULL the sizes are written to *n and *nnz; then with arrays
   of n + 1, nnz and nnz entries and *n, *nnz holding those sizes. */
ND_EXPORT int nd_problem_get_matrix(nd_problem p, int which, int64_t *n, int64_t *nnz,
                                    int64_t *row_ptr, int64_t *col_idx, double *values);
/* The FE node and component (0-based) of each of the n free DOFs; either
   array may be NULL. */
ND_EXPORT int nd_problem_get_dof_map(nd_problem p, int64_t n, int64_t *node, int *component);
/* F^n on the n free DOFs: the load the state at the current time holds. */
ND_EXPORT int nd_problem_get_load(nd_problem p, int64_t n, double *f);
/* The cells as the space numbers their FE nodes (P2: vertices, then the
   edges (i,j), i<j, lexicographically; Q2: vertices, edges, faces, centre
   in VTK's order, nd_mesh_create_cells(3)): with nodes NULL the sizes, then
   *n_cells * *nodes_per_cell node indices. */
ND_EXPORT int nd_problem_get_cells(nd_problem p, int64_t *n_cells, int *nodes_per_cell, int64_t *nodes);

/* ---- contact on the host's operators (nd_problem_contact_residual(3)) --- */
/* At u on the n free DOFs, the obstacle where it is at the current time,
   the law [P]_+; the problem's state is not touched. r = N(u). */
ND_EXPORT int nd_problem_contact_residual(nd_problem p, int64_t n, const double *u, double *r);
/* N'(u), CSR on the pattern of every contact point's rows (the same at every
   u); two calls as nd_problem_get_matrix (u may be NULL in the first). */
ND_EXPORT int nd_problem_contact_tangent(nd_problem p, int64_t n, const double *u, int64_t *nnz,
                                         int64_t *row_ptr, int64_t *col_idx, double *values);
/* The step form: the law by the problem's scheme's time rule over the step
   from P_q(u_old) to P_q(u) (the hybrid scheme's Phi_q, generalized-alpha's
   shifted point, [P_q(u)]_+ for the others), u_old the host's U^n, the
   obstacle at the current time at both ends. r = sum_q (w_q/gamma_q) phi_q b_q,
   and its Jacobian in u as nd_problem_contact_tangent (u, u_old may be NULL
   in the first call). */
ND_EXPORT int nd_problem_contact_step_residual(nd_problem p, int64_t n, const double *u, const double *u_old,
                                               double *r);
ND_EXPORT int nd_problem_contact_step_tangent(nd_problem p, int64_t n, const double *u, const double *u_old,
                                              int64_t *nnz, int64_t *row_ptr, int64_t *col_idx, double *values);
/* The first nvalues (1 to 4) of: the resultant normal contact force
   sum_q w_q [P_q]_+/gamma_q, the active points, the Nitsche energy R and the
   deepest penetration max_q (u_n - g0)_+, at u. */
ND_EXPORT int nd_problem_contact_values(nd_problem p, int64_t n, const double *u, int nvalues,
                                        double *values);

/* ---- output ------------------------------------------------------------ */
/* VTK XML unstructured grid of the current state: displacement, velocity
   (per FE vertex node), the contact pressure on the contact facets, the
   Cauchy stress per cell (at its centroid) and the time and step index
   (FieldData TIME, CYCLE). */
ND_EXPORT int nd_problem_write_vtu(nd_problem p, const char *path);
/* A ParaView time series: n VTU files (paths as written in the .pvd) and times. */
ND_EXPORT int nd_write_pvd(const char *path, int64_t n, const char *const *vtu_files,
                           const double *times);

#ifdef __cplusplus
}
#endif
#endif /* NITSCHEDYN_H */
