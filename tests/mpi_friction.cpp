// Friction (docs/design.md §10.2) on several ranks, under mpiexec -n 2 and 3.
// With friction every rank evaluates every contact point (normal and
// tangential values) itself, from a U right at every point's DOFs, and makes
// the end-of-step return mapping (the slip reference, D_f, the sliding and
// sticking points) over every point, so the friction state is each rank's
// own, one process's bits. The scene: a block on the rigid plane under
// gravity tilted by 0.5 rad (a slope), launched onto the plane (it lands,
// sticks and slides), hybrid scheme with Theta = 1; 2D and
// 3D, Coulomb (F = 0.3) and Tresca (s = 0.2, a stress).
//  - CHOLMOD on every rank (every rank solves the whole system itself, the
//    work outside the solves split): every rank makes one process's solves
//    with one process's Newton tangent (the block tangent in 2D, the
//    sticking GMRES in 3D), so against one process every step is
//    bitwise: the displacement field, the nodal contact force, D_f, the
//    tangential force's resultant, the normal force applied, the Nitsche
//    energy, the sliding and sticking counts. Likewise the explicit central
//    difference (no tangent). (One process with the refactoring tangent,
//    printed, is off by Newton's tolerance.)
//  - MUMPS on split rows (each rank its rows of the operators, the Newton
//    passes reading the points touching them): MUMPS's parallel sums are not
//    one process's, so the histories are held to 1e-8 of one process's as
//    the frictionless ones (mpi_distributed.c), the counts equal, and the
//    ranks agree exactly.
//  - A checkpoint written on the ranks resumes in one process, and one
//    process's on the ranks, bitwise against the run that went on.
//  - A distributed state is refused with friction, on every rank.
// White-box: the one-process reference's tangent is chosen (Problem::set_tangent).
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <vector>

#include "capi/handles.hpp"  // before check.h, whose fail() macro hides nd::fail
#include "fast/tangents.hpp"
// last: check.h's fail() macro would clash with nd::fail and std::ios::fail
#include <check.h>

#include "nitschedyn_mpi.h"
#include "testutil_mpi.h"

namespace {

int g_rank = 0, g_size = 1;

double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

enum { kExplicit = 0 };  // (Scene::scheme: the central difference, lumped mass)

struct Scene {
  int dim, law;
  double parameter;
  int scheme = ND_SCHEME_HYBRID;  // an ND_SCHEME_* (its parameters: scheme_params) or kExplicit
};

// the implicit schemes' parameters (mpi_distributed.c's)
const double *scheme_params(int scheme) {
  static const double newmark[2] = {0.25, 0.5}, alpha[1] = {0.8}, theta[1] = {0.75};
  return scheme == ND_SCHEME_NEWMARK ? newmark
         : scheme == ND_SCHEME_GENERALIZED_ALPHA ? alpha
         : scheme == ND_SCHEME_THETA ? theta
                                     : nullptr;
}

enum Where { kAlone, kEveryRank, kSplitRows, kAloneRefactor };

// The block [0,2] x [0,1] (x [0,1]) 5e-3 above the plane y = 0 (z = 0),
// launched at 0.5 towards the plane (the landing's pressure makes its
// points stick, then they slide); rho = 1, g = 1
// tilted by 0.5 rad along x. kAlone: one process, its own tangent (the
// block tangent in 2D, GMRES in 3D; kAloneRefactor: the refactoring one);
// kEveryRank: CHOLMOD on every rank; kSplitRows: MUMPS over the ranks.
nd_problem block(const Scene &s, Where where) {
  nd_mesh m = nullptr;
  nd_problem p = nullptr;
  if (s.dim == 2) {
    const double lo[2] = {0, 0}, hi[2] = {2, 1}, blo[2] = {-1, -1e-9}, bhi[2] = {3, 1e-9};
    ND_OK_OR_FAIL(nd_mesh_create_rectangle(8, 4, lo, hi, &m));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  } else {
    const double lo[3] = {0, 0, 0}, hi[3] = {2, 1, 1}, blo[3] = {-1, -1, -1e-9}, bhi[3] = {3, 2, 1e-9};
    ND_OK_OR_FAIL(nd_mesh_create_box(4, 2, 2, lo, hi, &m));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  }
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1e4, 0.3, 1));
  double point[3] = {0, 0, 0}, normal[3] = {0, 0, 0}, g[3] = {std::sin(0.5), 0, 0};
  point[s.dim - 1] = -5e-3, normal[s.dim - 1] = 1, g[s.dim - 1] = -std::cos(0.5);
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, point, normal));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1, 0));
  ND_OK_OR_FAIL(nd_problem_set_friction(p, 1, s.law, &s.parameter));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  std::vector<double> v(static_cast<size_t>(s.dim * nodes), 0.0);
  for (int64_t i = 0; i < nodes; ++i) v[s.dim * i + s.dim - 1] = -0.5;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nodes, nullptr, v.data()));
  ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, where == kSplitRows ? ND_SOLVER_PETSC_MUMPS : ND_SOLVER_CHOLMOD));
  if (s.scheme == kExplicit) {
    const double central[2] = {0.0, 0.5};
    ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, central));
    ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
    double tau_c = 0;
    ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tau_c));
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.5 * tau_c));
  } else {
    ND_OK_OR_FAIL(nd_problem_set_scheme(p, s.scheme, scheme_params(s.scheme)));
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, 2e-3));
  }
  if (where == kAloneRefactor) p->problem.set_tangent(nd::TangentChoice::Refactor);
  if (where == kEveryRank || where == kSplitRows) ND_OK_OR_FAIL(nd_problem_set_comm(p, MPI_COMM_WORLD));
  return p;
}

// What a step leaves, compared: the displacement field, the nodal contact
// force (normal and tangential), D_f, the tangential resultant, the normal
// force applied, the Nitsche energy (with its tangential part), the sliding
// and sticking points
struct Record {
  std::vector<double> u, f;
  double D = 0, ft[3] = {0, 0, 0}, fn = 0, nitsche = 0, sliding = 0, sticking = 0;
};

Record record(nd_problem p) {
  Record r;
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  const int64_t dim = p->problem.space().dim;
  r.u.resize(static_cast<size_t>(dim * nodes));
  r.f.resize(r.u.size());
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nodes, r.u.data()));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_CONTACT_FORCE, nodes, r.f.data()));
  r.fn = scalar(p, ND_CONTACT_FORCE_APPLIED);
  r.nitsche = scalar(p, ND_ENERGY_NITSCHE);
  r.D = scalar(p, ND_DISSIPATION_FRICTION);
  r.ft[0] = scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X);
  r.ft[1] = scalar(p, ND_CONTACT_FORCE_TANGENTIAL_Y);
  r.ft[2] = scalar(p, ND_CONTACT_FORCE_TANGENTIAL_Z);
  r.sliding = scalar(p, ND_SLIDING_POINTS);
  r.sticking = scalar(p, ND_STICKING_POINTS);
  return r;
}

// a record's values in one array
std::vector<double> values(const Record &r) {
  std::vector<double> all = r.u;
  all.insert(all.end(), r.f.begin(), r.f.end());
  all.insert(all.end(), {r.D, r.ft[0], r.ft[1], r.ft[2], r.fn, r.nitsche, r.sliding, r.sticking});
  return all;
}

bool same(const Record &a, const Record &b) {
  const std::vector<double> x = values(a), y = values(b);
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), sizeof(double) * x.size()) == 0;
}

// every rank holds rank 0's record, bitwise
bool same_on_all_ranks(const Record &r) {
  const std::vector<double> all = values(r);
  return nd_test_same_on_all_ranks(all.data(), static_cast<int>(sizeof(double) * all.size()));
}

const char *name(const Scene &s) {
  static char text[64];
  const char *schemes[] = {"explicit", "theta", "Newmark", "hybrid", "generalized-alpha"};
  std::snprintf(text, sizeof text, "%dD %s %s", s.dim, s.law == ND_FRICTION_COULOMB ? "Coulomb" : "Tresca",
                schemes[s.scheme]);
  return text;
}

const Scene kScenes[] = {{2, ND_FRICTION_COULOMB, 0.3}, {2, ND_FRICTION_TRESCA, 0.2},
                         {3, ND_FRICTION_COULOMB, 0.3}, {3, ND_FRICTION_TRESCA, 0.2}};
constexpr int kSteps = 60;  // the landing in the fifth step (5e-3 at 0.5), then sticking and sliding points

// |x - y| over the history relative to the largest |x| (NaN-safe: a NaN fails)
struct Gap {
  double diff = 0, size = 0;
  void add(double x, double y) {
    const double d = std::fabs(x - y);
    diff = std::isnan(d) || std::isnan(diff) ? NAN : std::fmax(diff, d);
    size = std::fmax(size, std::fabs(x));
  }
  double relative() const { return diff / size; }
};

// The run on every rank (CHOLMOD) is one process's, bitwise, at every step,
// and it lands, sticks and slides: the four scenes with the hybrid scheme,
// Coulomb with the other schemes
START_TEST(every_rank_solving_is_one_process_bitwise) {
  std::vector<Scene> scenes(std::begin(kScenes), std::end(kScenes));
  scenes.push_back({2, ND_FRICTION_COULOMB, 0.3, kExplicit});
  for (int dim = 2; dim <= 3; ++dim)
    for (int scheme : {ND_SCHEME_NEWMARK, ND_SCHEME_GENERALIZED_ALPHA, ND_SCHEME_THETA})
      scenes.push_back({dim, ND_FRICTION_COULOMB, 0.3, scheme});
  for (const Scene &s : scenes) {
    nd_problem alone = block(s, kAlone), ranks = block(s, kEveryRank), own = block(s, kAloneRefactor);
    const int steps = s.scheme == kExplicit ? 4 * kSteps : kSteps;
    double slid = 0, stuck = 0;
    Gap u;  // (printed: one process with the refactoring tangent, off by Newton's tolerance)
    for (int n = 0; n < steps; ++n) {
      ND_OK_OR_FAIL(nd_step(alone));
      ND_OK_OR_FAIL(nd_step(ranks));
      ND_OK_OR_FAIL(nd_step(own));
      const Record a = record(alone), b = record(ranks), c = record(own);
      ck_assert_msg(same(a, b), "%s, step %d: the ranks' run is not one process's", name(s), n);
      ck_assert(same_on_all_ranks(b));
      slid += a.sliding, stuck += a.sticking;
      for (size_t i = 0; i < a.u.size(); ++i) u.add(a.u[i], c.u[i]);
    }
    const double D = scalar(ranks, ND_DISSIPATION_FRICTION);
    if (g_rank == 0)
      std::printf("%s, %d ranks: bitwise one process's over %d steps (point-steps sliding %g, sticking %g, D_f %.6e); "
                  "one process with the refactoring tangent: U %.2e off\n",
                  name(s), g_size, steps, slid, stuck, D, u.relative());
    ck_assert_msg(slid > 0 && D > 0, "%s: nothing slid", name(s));
    if (s.scheme != kExplicit) ck_assert_msg(stuck > 0, "%s: nothing stuck", name(s));
    ND_OK_OR_FAIL(nd_problem_destroy(&alone));
    ND_OK_OR_FAIL(nd_problem_destroy(&ranks));
    ND_OK_OR_FAIL(nd_problem_destroy(&own));
  }
}
END_TEST


// MUMPS on split rows: within 1e-8 of one process (mpi_distributed.c's
// bound for MUMPS: its sums over the ranks are in another order, each
// solve off by a few ulps times the condition number), the same sliding
// and sticking counts, every rank the same values. The four scenes with the
// hybrid scheme, and Coulomb with generalized-alpha and Newmark.
START_TEST(split_rows_follow_one_process) {
  std::vector<Scene> scenes(std::begin(kScenes), std::end(kScenes));
  scenes.push_back({2, ND_FRICTION_COULOMB, 0.3, ND_SCHEME_GENERALIZED_ALPHA});  // (right-hand sides read M A^n)
  scenes.push_back({3, ND_FRICTION_COULOMB, 0.3, ND_SCHEME_NEWMARK});
  for (const Scene &s : scenes) {
    nd_problem alone = block(s, kAlone), split = block(s, kSplitRows);
    Gap u, f, D, ft;
    int counts_differ = -1;
    for (int n = 0; n < kSteps; ++n) {
      ND_OK_OR_FAIL(nd_step(alone));
      ND_OK_OR_FAIL(nd_step(split));
      const Record a = record(alone), b = record(split);
      ck_assert(same_on_all_ranks(b));
      for (size_t i = 0; i < a.u.size(); ++i) u.add(a.u[i], b.u[i]), f.add(a.f[i], b.f[i]);
      D.add(a.D, b.D);
      for (int k = 0; k < 3; ++k) ft.add(a.ft[k], b.ft[k]);
      if (counts_differ < 0 && (a.sliding != b.sliding || a.sticking != b.sticking)) counts_differ = n;
    }
    if (g_rank == 0)
      std::printf("%s, MUMPS on %d ranks: U %.2e, contact force %.2e, D_f %.2e, f_t %.2e off one process's\n",
                  name(s), g_size, u.relative(), f.relative(), D.relative(), ft.relative());
    ck_assert_msg(counts_differ < 0, "%s: the sliding and sticking counts differ at step %d", name(s), counts_differ);
    ck_assert_msg(u.relative() <= 1e-8 && f.relative() <= 1e-8 && D.relative() <= 1e-8 && ft.relative() <= 1e-8,
                  "%s: U %.3g, contact force %.3g, D_f %.3g, f_t %.3g off one process's", name(s), u.relative(),
                  f.relative(), D.relative(), ft.relative());
    ND_OK_OR_FAIL(nd_problem_destroy(&alone));
    ND_OK_OR_FAIL(nd_problem_destroy(&split));
  }
}
END_TEST

// A checkpoint's friction section (the slip references, the applied
// tangential values, D_f) is whole on every rank: written on the ranks it
// resumes in one process, and one process's on the ranks, each bitwise the
// run that went on. (Their bytes are not compared: the energy guard's
// reference in them is an energy, which the ranks sum in another order.)
START_TEST(checkpoints_cross_the_rank_counts) {
  for (const Scene &s : {kScenes[0], kScenes[2]}) {
    nd_problem alone = block(s, kAlone), ranks = block(s, kEveryRank);
    for (int n = 0; n < kSteps / 2; ++n) {
      ND_OK_OR_FAIL(nd_step(alone));
      ND_OK_OR_FAIL(nd_step(ranks));
    }
    int64_t size_alone = 0, size_ranks = 0;
    unsigned char *from_alone = nd_test_checkpoint(alone, &size_alone);
    unsigned char *from_ranks = nd_test_checkpoint(ranks, &size_ranks);
    ck_assert(nd_test_same_on_all_ranks(from_ranks, static_cast<int>(size_ranks)));
    nd_problem to_alone = block(s, kAlone), to_ranks = block(s, kEveryRank);
    ND_OK_OR_FAIL(nd_problem_load_state(to_alone, size_ranks, from_ranks));
    ND_OK_OR_FAIL(nd_problem_load_state(to_ranks, size_alone, from_alone));
    for (int n = 0; n < kSteps / 2; ++n) {
      nd_problem all[4] = {alone, ranks, to_alone, to_ranks};
      for (nd_problem p : all) ND_OK_OR_FAIL(nd_step(p));
      const Record a = record(alone);
      ck_assert_msg(same(a, record(ranks)), "%s, step %d after: the ranks' run differs", name(s), n);
      ck_assert_msg(same(a, record(to_alone)), "%s, step %d after: the ranks' checkpoint resumed differs", name(s), n);
      ck_assert_msg(same(a, record(to_ranks)), "%s, step %d after: one process's checkpoint resumed on the ranks "
                    "differs", name(s), n);
    }
    if (g_rank == 0) std::printf("%s: checkpoints from %d ranks to one and back resume bitwise\n", name(s), g_size);
    std::free(from_alone), std::free(from_ranks);
    nd_problem all[4] = {alone, ranks, to_alone, to_ranks};
    for (nd_problem &p : all) ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

// A distributed state holds U right at the rank's own points only: refused
// with friction (ND_ERR_STATE) on every rank, nothing stepped
START_TEST(a_distributed_state_is_refused_with_friction) {
  nd_problem p = block(kScenes[0], kSplitRows);
  ND_OK_OR_FAIL(nd_problem_set_distributed_state(p, 1));
  const int code = nd_step(p);
  if (g_size > 1) {
    ck_assert_msg(nd_test_on_all_ranks(code == ND_ERR_STATE), "nd_step returned %d: %s", code, nd_last_error());
    ck_assert(std::strstr(nd_last_error(), "distributed state") != nullptr);
    ck_assert_double_eq(scalar(p, ND_TIME), 0);
  } else {
    ck_assert_int_eq(code, ND_OK);  // (one rank: nothing is distributed)
  }
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

}  // namespace

int main(int argc, char **argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  Suite *s = suite_create("mpi_friction");
  TCase *tc = tcase_create("friction");
  tcase_set_timeout(tc, 600);
  tcase_add_test(tc, a_distributed_state_is_refused_with_friction);
  tcase_add_test(tc, every_rank_solving_is_one_process_bitwise);
  tcase_add_test(tc, split_rows_follow_one_process);
  tcase_add_test(tc, checkpoints_cross_the_rank_counts);
  suite_add_tcase(s, tc);
  return nd_test_run_on_ranks(s);
}
