// The allocation-failure harness (issue 14): this program replaces the global
// operator new/delete and SuiteSparse's allocator hooks with ones that fail
// on request. For every k along a representative run (the 1D bar for 20
// steps; a 2D plate dropping on an obstacle, with CHOLMOD and with UMFPACK;
// a Gmsh file read), allocation k fails — once ("transient") or from k on
// until the call returns ("persistent": memory stays exhausted) — and the
// harness asserts:
//  - the call returns ND_OK (the failure was absorbed) or ND_ERR_NOMEM with a
//    message, never another code, a crash or an abort;
//  - a create function that failed left its handle NULL;
//  - once memory is back the same call succeeds (the problem is still usable)
//    and the whole run ends bitwise equal to an uninterrupted one.
// Covered: every C++ allocation (the library's, the standard library's) and
// SuiteSparse's (CHOLMOD, UMFPACK, KLU allocate through SuiteSparse_config).
// Not covered: malloc calls of LAPACK/OpenBLAS (its buffers are allocated
// when the library loads; dense and banded factorizations of the sizes here
// allocate nothing in LAPACK itself), of METIS (its failure is its return
// code, which linalg/nested_dissection.cpp turns into ND_ERR_NOMEM) and of
// libc (stdio, locale).
#include <SuiteSparse_config.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <unistd.h>
#include <vector>

#include "testutil.h"

namespace {

struct Injector {
  bool armed = false;       // counting allocations
  bool persistent = false;  // after the first failure, fail until disarmed
  long fail_at = 0;         // the allocation (1-based, since arming) that fails
  long count = 0;           // allocations since arming
  bool failing = false;     // the failure has happened
  bool inside = false;      // in a library call (the harness's own allocations never fail)
};
Injector g;

bool should_fail() {
  if (!g.armed || !g.inside) return false;
  if (g.failing) return g.persistent;
  if (++g.count == g.fail_at) {
    g.failing = true;
    return true;
  }
  return false;
}

void *hooked_malloc(size_t n) { return should_fail() ? nullptr : std::malloc(n); }
void *hooked_calloc(size_t n, size_t s) { return should_fail() ? nullptr : std::calloc(n, s); }
void *hooked_realloc(void *p, size_t n) { return should_fail() ? nullptr : std::realloc(p, n); }

}  // namespace

// ---- the replaceable global allocation functions ------------------------------
// (GCC sees free() of what its own operator new returned: this is that pair)
// (never inlined: under valgrind, which substitutes these symbols, every new
// and delete must go through the symbols so that they stay paired)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#define ND_REPLACED __attribute__((noinline))
ND_REPLACED void *operator new(size_t n) {
  if (should_fail()) throw std::bad_alloc();
  if (void *p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
ND_REPLACED void *operator new[](size_t n) { return operator new(n); }
ND_REPLACED void *operator new(size_t n, const std::nothrow_t &) noexcept {
  if (should_fail()) return nullptr;
  return std::malloc(n ? n : 1);
}
ND_REPLACED void *operator new[](size_t n, const std::nothrow_t &t) noexcept { return operator new(n, t); }
ND_REPLACED void operator delete(void *p) noexcept { std::free(p); }
ND_REPLACED void operator delete[](void *p) noexcept { std::free(p); }
ND_REPLACED void operator delete(void *p, size_t) noexcept { std::free(p); }
ND_REPLACED void operator delete[](void *p, size_t) noexcept { std::free(p); }
ND_REPLACED void operator delete(void *p, const std::nothrow_t &) noexcept { std::free(p); }
ND_REPLACED void operator delete[](void *p, const std::nothrow_t &) noexcept { std::free(p); }

namespace {

// Whether the replacement is in force (valgrind substitutes its own
// operator new: the harness then has nothing to test and says so).
bool hook_active() {
  g = Injector{};
  g.armed = true;
  g.inside = true;
  g.fail_at = 1;
  bool threw = false;
  try {
    volatile char *p = new char[16];
    delete[] p;
  } catch (const std::bad_alloc &) {
    threw = true;
  }
  g = Injector{};
  return threw;
}

// One run of a scenario: its calls go through call(), its results into out.
struct Run {
  std::vector<double> out;  // every field and scalar read, in order
  int failures = 0;         // calls that returned ND_ERR_NOMEM
  int absorbed = 0;         // calls that met an injected failure and returned ND_OK
  std::string where;        // the scenario and k, for messages

  // Calls f; when an injected failure hit it, checks the outcome, gives the
  // memory back and calls it again. handle: the out-parameter of a create call.
  template <class F>
  void call(const char *what, F &&f, void **handle = nullptr) {
    const bool before = g.failing;
    g.inside = true;
    int st = f();
    g.inside = false;
    const bool hit = g.failing && !before;
    if (hit) {
      g.armed = false;  // memory is back for the rest of the run
      ck_assert_msg(st == ND_OK || st == ND_ERR_NOMEM, "%s: %s returned %d (%s) on an allocation failure",
                    where.c_str(), what, st, nd_last_error());
      if (st == ND_ERR_NOMEM) {
        ++failures;
        ck_assert_msg(std::strstr(nd_last_error(), ": ") != nullptr, "%s: %s: no message: '%s'", where.c_str(), what,
                      nd_last_error());
        if (handle) ck_assert_msg(*handle == nullptr, "%s: %s left a handle after failing", where.c_str(), what);
        st = f();
      } else {
        ++absorbed;
      }
    }
    ck_assert_msg(st == ND_OK, "%s: %s returned %d: %s", where.c_str(), what, st, nd_last_error());
  }
  void read_fields(nd_problem p, int dim) {
    int64_t n = 0;
    call("node count", [&] { return nd_problem_get_node_count(p, &n); });
    std::vector<double> v(static_cast<size_t>(n * dim));
    for (int field : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY, ND_FIELD_ACCELERATION}) {
      call("nd_get_field", [&] { return nd_get_field(p, field, n, v.data()); });
      out.insert(out.end(), v.begin(), v.end());
    }
    for (int key : {ND_TIME, ND_ENERGY_AUGMENTED, ND_CONTACT_FORCE, ND_NEWTON_ITERATIONS_TOTAL}) {
      double x = 0;
      call("nd_get_scalar", [&] { return nd_get_scalar(p, key, &x); });
      out.push_back(x);
    }
  }
};

using Scenario = void (*)(Run &);

// The 1D bar of docs/design.md §7 (AUTO solver: dense), 20 steps, contact at x = 0.
void bar(Run &r) {
  nd_mesh m = nullptr;
  nd_problem p = nullptr;
  const double up = 1, plane = 0, lo0 = -0.5, hi0 = 0.5, lo1 = 0.5, hi1 = 1.5;
  r.call("interval", [&] { return nd_mesh_create_interval(10, 0.0, 1.0, &m); }, reinterpret_cast<void **>(&m));
  r.call("mark", [&] { return nd_mesh_mark_boundary_box(m, 1, &lo0, &hi0); });
  r.call("mark", [&] { return nd_mesh_mark_boundary_box(m, 2, &lo1, &hi1); });
  r.call("create", [&] { return nd_problem_create(m, 1, &p); }, reinterpret_cast<void **>(&p));
  nd_mesh_destroy(&m);
  r.call("material", [&] { return nd_problem_set_material(p, 1.0, 0.0, 1.0); });
  r.call("dirichlet", [&] { return nd_problem_set_dirichlet(p, 2); });
  r.call("contact", [&] { return nd_problem_set_contact_plane(p, 1, &plane, &up); });
  r.call("nitsche", [&] { return nd_problem_set_nitsche(p, 1.0, 0.1); });
  const double nm[2] = {0.25, 0.5};
  r.call("scheme", [&] { return nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm); });
  r.call("timestep", [&] { return nd_problem_set_timestep(p, 0.05); });
  int64_t n = 0;
  r.call("nodes", [&] { return nd_problem_get_node_count(p, &n); });
  std::vector<double> x(static_cast<size_t>(n)), u0(x.size());
  r.call("coords", [&] { return nd_problem_get_node_coordinates(p, n, x.data()); });
  for (size_t i = 0; i < x.size(); ++i) u0[i] = 0.5 * (1 - x[i]);
  r.call("initial", [&] { return nd_problem_set_initial_state(p, n, u0.data(), nullptr); });
  for (int s = 0; s < 20; ++s) {
    r.call("nd_step", [&] { return nd_step(p); });
    r.read_fields(p, 1);
  }
  nd_problem_destroy(&p);
}

// A 2D plate falling onto a plane (contact becomes active), with a solver.
void plate(Run &r, int solver, double theta, int steps) {
  nd_mesh m = nullptr;
  nd_problem p = nullptr;
  const double lo[2] = {0, 0.01}, hi[2] = {1, 0.26}, blo[2] = {-1, -1}, bhi[2] = {2, 0.02};
  const double o[2] = {0, 0}, upn[2] = {0, 1}, grav[2] = {0, -4};
  r.call("rectangle", [&] { return nd_mesh_create_rectangle(8, 2, lo, hi, &m); }, reinterpret_cast<void **>(&m));
  r.call("mark", [&] { return nd_mesh_mark_boundary_box(m, 1, blo, bhi); });
  r.call("create", [&] { return nd_problem_create(m, 1, &p); }, reinterpret_cast<void **>(&p));
  nd_mesh_destroy(&m);
  r.call("material", [&] { return nd_problem_set_material(p, 10, 0.3, 1); });
  r.call("body force", [&] { return nd_problem_set_body_force(p, grav); });
  r.call("contact", [&] { return nd_problem_set_contact_plane(p, 1, o, upn); });
  r.call("nitsche", [&] { return nd_problem_set_nitsche(p, theta, 1e-2); });
  r.call("scheme", [&] { return nd_problem_set_scheme(p, ND_SCHEME_HYBRID, nullptr); });
  r.call("solver", [&] { return nd_problem_set_linear_solver(p, solver); });
  r.call("timestep", [&] { return nd_problem_set_timestep(p, 0.05); });
  for (int s = 0; s < steps; ++s) {
    r.call("nd_step", [&] { return nd_step(p); });
    r.read_fields(p, 2);
  }
  nd_problem_destroy(&p);
}
void plate_cholmod(Run &r) { plate(r, ND_SOLVER_CHOLMOD, 1.0, 8); }
void plate_umfpack_klu(Run &r) { plate(r, ND_SOLVER_KLU, 0.0, 6); }  // Theta = 0: a general tangent
void plate_dense(Run &r) { plate(r, ND_SOLVER_AUTO, -1.0, 6); }     // AUTO: banded/dense

// A small Gmsh file read, then its regions.
std::string msh_path;
void gmsh(Run &r) {
  nd_mesh m = nullptr;
  r.call("read", [&] { return nd_mesh_read_gmsh(msh_path.c_str(), &m); }, reinterpret_cast<void **>(&m));
  int64_t n = 0;
  r.call("region", [&] { return nd_mesh_get_region_size(m, 1, &n); });
  r.out.push_back(static_cast<double>(n));
  r.call("vertices", [&] { return nd_mesh_get_vertex_count(m, &n); });
  r.out.push_back(static_cast<double>(n));
  nd_mesh_destroy(&m);
}

// Runs the scenario once uninterrupted (counting its allocations), then
// once for every k with allocation k failing.
void sweep(const char *name, Scenario scenario, bool persistent) {
  Run ref;
  ref.where = std::string(name) + " (reference)";
  g = Injector{};
  g.armed = true;
  g.fail_at = -1;  // count only
  scenario(ref);
  const long total = g.count;
  g = Injector{};
  ck_assert_int_gt(total, 0);
  long failed_calls = 0, absorbed = 0;
  for (long k = 1; k <= total; ++k) {
    Run r;
    r.where = std::string(name) + (persistent ? " persistent" : " transient") + ", allocation " + std::to_string(k) +
              " of " + std::to_string(total);
    g = Injector{};
    g.armed = true;
    g.persistent = persistent;
    g.fail_at = k;
    scenario(r);
    g = Injector{};
    ck_assert_msg(r.out.size() == ref.out.size() &&
                      std::memcmp(r.out.data(), ref.out.data(), sizeof(double) * ref.out.size()) == 0,
                  "%s: the run differs from the uninterrupted one (%d failed calls, %d absorbed)", r.where.c_str(),
                  r.failures, r.absorbed);
    failed_calls += r.failures;
    absorbed += r.absorbed;
  }
  std::printf("alloc-failure %-18s %-10s: %ld allocations, each failed once: %ld calls returned ND_ERR_NOMEM, "
              "%ld absorbed the failure (ND_OK); all runs bitwise equal to the uninterrupted one\n",
              name, persistent ? "persistent" : "transient", total, failed_calls, absorbed);
}

#define ND_SWEEP_TEST(test, name, scenario)                                         \
  START_TEST(test) {                                                                \
    if (!hook_active()) {                                                           \
      std::printf("alloc-failure: operator new is not replaceable here (valgrind?): skipped\n"); \
      return;                                                                       \
    }                                                                               \
    sweep(name, scenario, false);                                                   \
    sweep(name, scenario, true);                                                    \
  }                                                                                 \
  END_TEST

ND_SWEEP_TEST(bar_survives_every_allocation_failure, "bar", bar)
ND_SWEEP_TEST(plate_cholmod_survives_every_allocation_failure, "plate cholmod", plate_cholmod)
ND_SWEEP_TEST(plate_klu_survives_every_allocation_failure, "plate umfpack/klu", plate_umfpack_klu)
ND_SWEEP_TEST(plate_dense_survives_every_allocation_failure, "plate dense", plate_dense)
ND_SWEEP_TEST(gmsh_survives_every_allocation_failure, "gmsh", gmsh)

}  // namespace

int main() {
  // SuiteSparse (CHOLMOD, UMFPACK, KLU) allocates through these hooks
  SuiteSparse_config.malloc_func = hooked_malloc;
  SuiteSparse_config.calloc_func = hooked_calloc;
  SuiteSparse_config.realloc_func = hooked_realloc;
  msh_path = "/tmp/nd_unit_alloc_failure_" + std::to_string(getpid()) + ".msh";
  if (FILE *f = std::fopen(msh_path.c_str(), "w")) {
    std::fputs("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 1 1 0\n1 0 0 0 1 0 0 1 7 0\n"
               "1 0 0 0 1 1 0 0 0\n$EndEntities\n$Nodes\n2 4 1 4\n1 1 0 2\n1\n2\n1 0 0\n0 0 0\n2 1 0 2\n3\n4\n"
               "1 1 0\n0 1 0\n$EndNodes\n$Elements\n2 3 1 3\n1 1 1 1\n1 2 1\n2 1 2 2\n2 1 2 3\n3 4 3 1\n"
               "$EndElements\n",
               f);
    std::fclose(f);
  }
  Suite *s = suite_create("alloc_failure");
  TCase *tc = tcase_create("every allocation");
  tcase_set_timeout(tc, 600);
  tcase_add_test(tc, bar_survives_every_allocation_failure);
  tcase_add_test(tc, plate_cholmod_survives_every_allocation_failure);
  tcase_add_test(tc, plate_klu_survives_every_allocation_failure);
  tcase_add_test(tc, plate_dense_survives_every_allocation_failure);
  tcase_add_test(tc, gmsh_survives_every_allocation_failure);
  suite_add_tcase(s, tc);
  const int status = nd_test_run(s);
  std::remove(msh_path.c_str());
  return status;
}
