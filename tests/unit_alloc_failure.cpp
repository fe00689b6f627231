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
// Not covered in these: malloc calls of LAPACK/OpenBLAS (its buffers are
// allocated when the library loads; dense and banded factorizations of the
// sizes here allocate nothing in LAPACK itself), of METIS (its failure is
// its return code, which linalg/nested_dissection.cpp turns into
// ND_ERR_NOMEM) and of libc (stdio, locale): the contact-step sweep below
// covers them in its steps.
//
// The contact-step sweep (issue 54): a 2D and a 3D body resting on a plane
// (contact from the first step), for every linear solver and every scheme;
// only the allocations of its nd_step calls are counted and failed (the
// first, which sets up the problem and makes the contact columns, and two
// later contact steps), and there every allocation is: operator new and
// malloc/calloc/realloc/memalign of the whole process (this program
// replaces them: the library's, the standard library's, SuiteSparse's,
// LAPACKE's and glibc's own, such as the calloc that registers a
// thread_local's destructor, which aborts when it fails). A failed nd_step
// must return ND_ERR_NOMEM and leave the problem bitwise unchanged.
#include <SuiteSparse_config.h>
#include <malloc.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <new>
#include <string>
#include <thread>
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
  // libc: every malloc/calloc/realloc/memalign of the process counts (the
  // contact-step sweep); else operator new and SuiteSparse's hooks only
  bool libc = false;
};
Injector g;
// in a library call on this thread (the harness's own allocations, and
// other threads', never fail)
thread_local bool inside = false;

bool should_fail() {
  if (!g.armed || !inside) return false;
  if (g.failing) return g.persistent;
  if (++g.count == g.fail_at) {
    g.failing = true;
    return true;
  }
  return false;
}
bool should_fail_new() { return !g.libc && should_fail(); }
[[maybe_unused]] bool should_fail_libc() { return g.libc && should_fail(); }  // (unused under ASan)

void *hooked_malloc(size_t n) { return should_fail_new() ? nullptr : std::malloc(n); }
void *hooked_calloc(size_t n, size_t s) { return should_fail_new() ? nullptr : std::calloc(n, s); }
void *hooked_realloc(void *p, size_t n) { return should_fail_new() ? nullptr : std::realloc(p, n); }

}  // namespace

// ---- libc's allocator, interposed (glibc: its own calls come here too) ------
// Not under AddressSanitizer, whose allocator this would bypass: there the
// contact-step sweep counts operator new and SuiteSparse's allocations only.
#if defined(__SANITIZE_ADDRESS__)
#define ND_LIBC_HOOKS 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ND_LIBC_HOOKS 0
#endif
#endif
#ifndef ND_LIBC_HOOKS
#define ND_LIBC_HOOKS 1
#endif
#if ND_LIBC_HOOKS
extern "C" {
void *__libc_malloc(size_t);
void *__libc_calloc(size_t, size_t);
void *__libc_realloc(void *, size_t);
void *__libc_memalign(size_t, size_t);
void *malloc(size_t n) {
  if (should_fail_libc()) return errno = ENOMEM, nullptr;
  return __libc_malloc(n);
}
void *calloc(size_t n, size_t s) {
  if (should_fail_libc()) return errno = ENOMEM, nullptr;
  return __libc_calloc(n, s);
}
void *realloc(void *p, size_t n) {
  if (n && should_fail_libc()) return errno = ENOMEM, nullptr;
  return __libc_realloc(p, n);
}
void *memalign(size_t a, size_t n) {
  if (should_fail_libc()) return errno = ENOMEM, nullptr;
  return __libc_memalign(a, n);
}
void *aligned_alloc(size_t a, size_t n) { return memalign(a, n); }
int posix_memalign(void **out, size_t a, size_t n) {
  if (should_fail_libc()) return ENOMEM;
  void *q = __libc_memalign(a, n);
  if (!q) return ENOMEM;
  *out = q;
  return 0;
}
}
#endif

// ---- the replaceable global allocation functions ------------------------------
// (GCC sees free() of what its own operator new returned: this is that pair)
// (never inlined: under valgrind, which substitutes these symbols, every new
// and delete must go through the symbols so that they stay paired)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#define ND_REPLACED __attribute__((noinline))
ND_REPLACED void *operator new(size_t n) {
  if (should_fail_new()) throw std::bad_alloc();
  if (void *p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
ND_REPLACED void *operator new[](size_t n) { return operator new(n); }
ND_REPLACED void *operator new(size_t n, const std::nothrow_t &) noexcept {
  if (should_fail_new()) return nullptr;
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
  inside = true;
  g.fail_at = 1;
  bool threw = false;
  try {
    void *(*volatile alloc)(size_t) = ::operator new;  // (a new-delete pair would be elided)
    ::operator delete(alloc(16));
  } catch (const std::bad_alloc &) {
    threw = true;
  }
  inside = false;
  g = Injector{};
  return threw;
}
// Whether libc's allocator is interposed (not under valgrind or ASan)
bool libc_hook_active() {
  g = Injector{};
  g.armed = true;
  g.libc = true;
  inside = true;
  g.fail_at = 1;
  void *(*volatile alloc)(size_t) = std::malloc;  // (not elided)
  void *p = alloc(16);
  inside = false;
  g = Injector{};
  std::free(p);
  return p == nullptr;
}

// One run of a scenario: its calls go through call(), its results into out.
struct Run {
  std::vector<double> out;  // every field and scalar read, in order
  int failures = 0;         // calls that returned ND_ERR_NOMEM
  int absorbed = 0;         // calls that met an injected failure and returned ND_OK
  std::string where;        // the scenario and k, for messages
  bool sweep_all = true;    // every call's allocations are counted; else only while `swept`
  bool swept = false;
  std::function<void()> on_failure;  // after a call returned ND_ERR_NOMEM, before the retry
  double tangents = 0;                // the contact sweep: ND_STAT_TANGENT_UPDATES at the end

  // Calls f; when an injected failure hit it, checks the outcome, gives the
  // memory back and calls it again. handle: the out-parameter of a create call.
  template <class F>
  void call(const char *what, F &&f, void **handle = nullptr) {
    const bool before = g.failing;
    inside = sweep_all || swept;
    int st = f();
    inside = false;
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
        if (on_failure) on_failure();
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

// ---- the contact-step sweep ---------------------------------------------------
struct ContactConfig {
  int dim, solver, scheme;
};
ContactConfig contact_config;
bool contact_probe = false;           // contact_body reads the initial state, takes no step
std::vector<double> contact_initial;  // what it read
const int contact_steps = 3;  // swept: the first (setup, contact columns) and two later contact steps

// The fields and time of p, read outside the sweep
std::vector<double> snapshot(nd_problem p, int dim) {
  int64_t n = 0;
  ck_assert_int_eq(nd_problem_get_node_count(p, &n), ND_OK);
  std::vector<double> v(static_cast<size_t>(n * dim)), out;
  for (int field : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY, ND_FIELD_ACCELERATION}) {
    ck_assert_int_eq(nd_get_field(p, field, n, v.data()), ND_OK);
    out.insert(out.end(), v.begin(), v.end());
  }
  double t = 0;
  ck_assert_int_eq(nd_get_scalar(p, ND_TIME, &t), ND_OK);
  out.push_back(t);
  return out;
}

// A 2D rectangle or 3D box resting on a plane under gravity (contact from
// the first step): its nd_step calls swept, the setup not
void contact_body(Run &r) {
  const ContactConfig c = contact_config;
  const int d = c.dim;
  nd_mesh m = nullptr;
  nd_problem p = nullptr;
  r.sweep_all = false;
  if (d == 2) {
    const double lo[2] = {0, 0}, hi[2] = {1, 0.25};
    r.call("rectangle", [&] { return nd_mesh_create_rectangle(4, 2, lo, hi, &m); }, reinterpret_cast<void **>(&m));
  } else {
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 0.25};
    r.call("box", [&] { return nd_mesh_create_box(2, 2, 1, lo, hi, &m); }, reinterpret_cast<void **>(&m));
  }
  const double blo[3] = {-1, -1, -1}, bhi2[2] = {2, 0.01}, bhi3[3] = {2, 2, 0.01};
  r.call("mark", [&] { return nd_mesh_mark_boundary_box(m, 1, blo, d == 2 ? bhi2 : bhi3); });
  r.call("create", [&] { return nd_problem_create(m, 1, &p); }, reinterpret_cast<void **>(&p));
  nd_mesh_destroy(&m);
  const double o[3] = {0, 0, 0}, up2[2] = {0, 1}, up3[3] = {0, 0, 1}, grav2[2] = {0, -4}, grav3[3] = {0, 0, -4};
  r.call("material", [&] { return nd_problem_set_material(p, 10, 0.3, 1); });
  r.call("body force", [&] { return nd_problem_set_body_force(p, d == 2 ? grav2 : grav3); });
  r.call("contact", [&] { return nd_problem_set_contact_plane(p, 1, o, d == 2 ? up2 : up3); });
  // Theta = 0 (a general tangent) with the LU solvers, 1 (symmetric) with the others
  const bool lu = c.solver == ND_SOLVER_UMFPACK || c.solver == ND_SOLVER_KLU;
  r.call("nitsche", [&] { return nd_problem_set_nitsche(p, lu ? 0.0 : 1.0, d == 2 ? 1e-2 : 1e-3); });
  const double theta[1] = {0.5}, newmark[2] = {0.25, 0.5}, alpha[1] = {0.8}, explicit_nm[2] = {0.0, 0.5};
  const bool expl = c.scheme == 0;
  const int scheme = expl ? ND_SCHEME_NEWMARK : c.scheme;
  const double *params = expl ? explicit_nm
                         : c.scheme == ND_SCHEME_THETA           ? theta
                         : c.scheme == ND_SCHEME_NEWMARK         ? newmark
                         : c.scheme == ND_SCHEME_GENERALIZED_ALPHA ? alpha
                                                                 : nullptr;
  r.call("scheme", [&] { return nd_problem_set_scheme(p, scheme, params); });
  if (expl) r.call("mass", [&] { return nd_problem_set_mass_lumping(p, 0); });  // the solver solves M
  r.call("solver", [&] { return nd_problem_set_linear_solver(p, c.solver); });
  r.call("timestep", [&] { return nd_problem_set_timestep(p, expl ? 1e-4 : 0.05); });
  if (contact_probe) {  // the state before the first step, read on a problem of its own
    contact_initial = snapshot(p, d);
    nd_problem_destroy(&p);
    return;
  }
  for (int s = 0; s < contact_steps; ++s) {
    // (not read before the first step: that would set the problem up, the
    // first nd_step's work, outside the sweep)
    const std::vector<double> before = s == 0 ? contact_initial : snapshot(p, d);
    r.on_failure = [&] {
      const std::vector<double> after = snapshot(p, d);
      ck_assert_msg(after.size() == before.size() &&
                        std::memcmp(after.data(), before.data(), sizeof(double) * before.size()) == 0,
                    "%s: the failed nd_step changed the problem", r.where.c_str());
    };
    r.swept = true;
    r.call("nd_step", [&] { return nd_step(p); });
    r.swept = false;
    r.on_failure = nullptr;
    r.read_fields(p, d);
    double active = 0;
    r.call("active points", [&] { return nd_get_scalar(p, ND_ACTIVE_POINTS, &active); });
    ck_assert_msg(active > 0, "%s: no active contact point after step %d", r.where.c_str(), s + 1);
    r.out.push_back(active);
  }
  double tangents = 0;
  r.call("tangent updates", [&] { return nd_get_scalar(p, ND_STAT_TANGENT_UPDATES, &tangents); });
  r.tangents = tangents;  // (not compared: the counters count a failed step's work too)
  double contact = 0;
  r.call("contact force", [&] { return nd_get_scalar(p, ND_CONTACT_FORCE, &contact); });
  ck_assert_msg(contact != 0, "%s: no contact", r.where.c_str());
  nd_problem_destroy(&p);
}

// Each run of a configuration on a thread of its own: there the library's
// first use of anything per-thread happens inside the sweep, as in a
// program's thread (a thread_local with a destructor registers it with
// glibc, which callocs, and aborts if that fails)
void contact_body_fresh_thread(Run &r) { std::thread([&r] { contact_body(r); }).join(); }

const char *solver_name(int s) {
  static const char *names[] = {"AUTO", "DENSE", "BANDED", "CHOLMOD", "UMFPACK", "KLU"};
  return names[s];
}
const char *scheme_name(int s) {
  static const char *names[] = {"explicit", "theta", "Newmark", "hybrid", "gen-alpha"};
  return names[s];
}

// The sweep of one configuration: every allocation of its nd_step calls
// fails once (transient), and with persistent, every `stride`-th one from
// there on until the call returns; returns the count swept
long contact_sweep(int dim, int solver, int scheme, bool persistent, long stride, long first) {
  contact_config = ContactConfig{dim, solver, scheme};
  {
    Run probe;
    contact_probe = true;
    contact_body_fresh_thread(probe);
    contact_probe = false;
  }
  Run ref;
  ref.where = std::string(dim == 2 ? "2D " : "3D ") + solver_name(solver) + " " + scheme_name(scheme);
  g = Injector{};
  g.libc = true;
  g.armed = true;
  g.fail_at = -1;  // count only
  contact_body_fresh_thread(ref);
  const long total = g.count;
  g = Injector{};
  ck_assert_int_gt(total, 0);
  long failed = 0, absorbed = 0, runs = 0;
  for (long k = first; k <= total; k += stride) {
    Run r;
    r.where = ref.where + (persistent ? " persistent" : " transient") + ", allocation " + std::to_string(k) + " of " +
              std::to_string(total);
    g = Injector{};
    g.libc = true;
    g.armed = true;
    g.persistent = persistent;
    g.fail_at = k;
    contact_body_fresh_thread(r);
    g = Injector{};
    ck_assert_msg(r.out.size() == ref.out.size() &&
                      std::memcmp(r.out.data(), ref.out.data(), sizeof(double) * ref.out.size()) == 0,
                  "%s: the run differs from the uninterrupted one (%d failed calls, %d absorbed)", r.where.c_str(),
                  r.failures, r.absorbed);
    failed += r.failures;
    absorbed += r.absorbed;
    ++runs;
  }
  std::printf("alloc-failure contact %-20s %-10s: %ld allocations in %d contact steps (%g tangent updates), %ld "
              "failed (every %ld from %ld): %ld returned ND_ERR_NOMEM, %ld absorbed (ND_OK); all bitwise equal to "
              "the uninterrupted run\n",
              ref.where.c_str(), persistent ? "persistent" : "transient", total, contact_steps, ref.tangents, runs,
              stride, first, failed, absorbed);
  return total;
}

void contact_sweeps(int dim) {
  if (!hook_active() || !libc_hook_active()) {
    std::printf("alloc-failure: malloc is not replaceable here (valgrind? ASan?): contact sweep %dD skipped\n", dim);
    return;
  }
  const int solvers[] = {ND_SOLVER_AUTO, ND_SOLVER_DENSE, ND_SOLVER_BANDED, ND_SOLVER_CHOLMOD, ND_SOLVER_UMFPACK,
                         ND_SOLVER_KLU};
  const int schemes[] = {ND_SCHEME_THETA, ND_SCHEME_NEWMARK, ND_SCHEME_HYBRID, ND_SCHEME_GENERALIZED_ALPHA, 0};
  // 2D: every allocation (transient); 3D (four times as many, most of
  // them the setup's, which the schemes share): every 5th, from an offset
  // that rotates with the scheme, so that the five schemes of a solver
  // together fail each allocation index once. Persistent: every 7th (2D)
  // or 31st (3D), rotating too. ND_ALLOC_SWEEP=full: every allocation of
  // every configuration, both ways (some minutes).
  const bool full = std::getenv("ND_ALLOC_SWEEP") && std::strcmp(std::getenv("ND_ALLOC_SWEEP"), "full") == 0;
  const long transient_stride = full || dim == 2 ? 1 : 5, persistent_stride = full ? 1 : dim == 2 ? 7 : 31;
  for (int solver : solvers)
    for (int i = 0; i < 5; ++i) {
      contact_sweep(dim, solver, schemes[i], false, transient_stride, 1 + i % transient_stride);
      contact_sweep(dim, solver, schemes[i], true, persistent_stride, 1 + i % persistent_stride);
    }
}

START_TEST(contact_2d_survives_every_allocation_failure) { contact_sweeps(2); }
END_TEST
START_TEST(contact_3d_survives_every_allocation_failure) { contact_sweeps(3); }
END_TEST

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
  tcase_add_test(tc, contact_2d_survives_every_allocation_failure);
  tcase_add_test(tc, contact_3d_survives_every_allocation_failure);
  suite_add_tcase(s, tc);
  const int status = nd_test_run(s);
  std::remove(msh_path.c_str());
  return status;
}
