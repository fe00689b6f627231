// A step allocates no memory once the run is under way: the state before
// the last lends its vectors to the next (reuse_storage), and the solves,
// the residual checks and the Newton workspaces keep theirs
// (linalg/supernodal.hpp's SupernodalWork, Integrator::scratch,
// CondensedCache::Work, NewtonWork); contact steps below. Counted through this program's operator new, on
// every step but those shown free by the bound after one that evaluated
// the points: such a step makes the bound's reference from that state
// (problem/integrator.cpp: U, P_q and u_n copied into an immutable shared
// PointReference, which later states share). For every implicit scheme, 2D
// (CHOLMOD's supernodal factor) and 3D, P1 and P2.
// (Under valgrind, whose operator new replaces this one, nothing is counted.)
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>

#include "capi/handles.hpp"  // before check.h, whose fail() macro hides nd::fail
#include "testutil.h"
#include "unit_drop.hpp"

namespace {
long g_allocations = 0;
bool g_counting = false;
}  // namespace

// every form of the plain and array operators, so that each allocation and
// its release meet the same pair (malloc, free) under ASan
namespace {
void *counted(std::size_t n) noexcept {
  if (g_counting) ++g_allocations;
  return std::malloc(n ? n : 1);
}
void *counted_or_throw(std::size_t n) {
  if (void *p = counted(n)) return p;
  throw std::bad_alloc();
}
}  // namespace
void *operator new(std::size_t n) { return counted_or_throw(n); }
void *operator new[](std::size_t n) { return counted_or_throw(n); }
void *operator new(std::size_t n, const std::nothrow_t &) noexcept { return counted(n); }
void *operator new[](std::size_t n, const std::nothrow_t &) noexcept { return counted(n); }
void operator delete(void *p) noexcept { std::free(p); }
void operator delete[](void *p) noexcept { std::free(p); }
void operator delete(void *p, std::size_t) noexcept { std::free(p); }
void operator delete[](void *p, std::size_t) noexcept { std::free(p); }
void operator delete(void *p, const std::nothrow_t &) noexcept { std::free(p); }
void operator delete[](void *p, const std::nothrow_t &) noexcept { std::free(p); }

namespace {

double stat(nd_problem p, int which) {
  double v = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, which, &v));
  return v;
}

void free_steps_allocate_nothing(int dim, int degree, int refine) {
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes) {
    // far above the plane: free flight, deformed (the body turns and
    // stretches), so that steps are solved, not predicted
    nd_problem p = ndtest::drop_scene(dim, degree, sc, 1.0, 5.0, 0.1, refine);
    if (refine > 1) ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, ND_SOLVER_CHOLMOD));
    for (int k = 0; k < 5; ++k) ND_OK_OR_FAIL(nd_step(p));  // (the set-up, the first capacities)
    int counted = 0, solved = 0;
    bool evaluated_before = true;
    for (int k = 0; k < 30; ++k) {
      const double evaluations = stat(p, ND_STAT_CONTACT_EVALUATIONS), solves = stat(p, ND_STAT_SOLVES);
      g_allocations = 0;
      g_counting = true;
      const int status = nd_step(p);
      g_counting = false;
      ND_OK_OR_FAIL(status);
      // (the bound's new reference: a step shown free after one that evaluated)
      const bool evaluated = stat(p, ND_STAT_CONTACT_EVALUATIONS) != evaluations, skip = !evaluated && evaluated_before;
      evaluated_before = evaluated;
      if (skip) continue;
      ++counted;
      solved += stat(p, ND_STAT_SOLVES) > solves;
      ck_assert_msg(g_allocations == 0, "%dD P%d refine %d %s: step %d allocated %ld times", dim, degree, refine,
                    sc.name, k, g_allocations);
    }
    // (the counts asserted something: most steps, solved ones among them)
    ck_assert_msg(counted >= 20 && solved >= 10, "%dD P%d %s: %d steps counted, %d solved", dim, degree, sc.name,
                  counted, solved);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}

// A contact step allocates nothing once the contact has been through its
// active sets before: the points' columns of the condensed Newton (2D) are
// made when a point is first active, and the updated factor's history (3D)
// reserves twice its size when it outgrows it; Newton's vectors and the
// points' values go round between the integrator's workspaces and the
// states (NewtonWork, Integrator::at_solution). The scene falls on the
// obstacle and turns (the active set grows and changes); 20 contact steps
// are run from a saved state, then run again from it: the second run has
// the first's bits (bitwise restart) and so its active sets, and allocates
// nothing but in its first two steps (the restored state's products and
// the updated factor's replay of its history).
void contact_steps_allocate_nothing(int dim, int degree, int refine) {
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes) {
    nd_problem p = ndtest::drop_scene(dim, degree, sc, 1.0, 0.02, 0.1, refine);
    if (refine > 1) ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, ND_SOLVER_CHOLMOD));
    int k = 0;
    while (stat(p, ND_CONTACT_FORCE) == 0 && k++ < 200) ND_OK_OR_FAIL(nd_step(p));
    ck_assert_msg(stat(p, ND_CONTACT_FORCE) > 0, "%dD P%d %s: no contact in 200 steps", dim, degree, sc.name);
    int64_t size = 0;
    ND_OK_OR_FAIL(nd_problem_get_state_size(p, &size));
    // (no std::vector of this program's own: its instantiations would be
    // the library's too, with this operator new inlined, which valgrind
    // does not replace while it replaces the library's delete)
    unsigned char *saved = static_cast<unsigned char *>(std::malloc(static_cast<size_t>(size)));
    ck_assert(saved != nullptr);
    ND_OK_OR_FAIL(nd_problem_save_state(p, size, saved));
    double first_run[20];
    for (double &force : first_run) {
      ND_OK_OR_FAIL(nd_step(p));
      force = stat(p, ND_CONTACT_FORCE);
    }
    ND_OK_OR_FAIL(nd_problem_load_state(p, size, saved));
    std::free(saved);
    int counted = 0, iterations = 0;
    for (int j = 0; j < 20; ++j) {
      g_allocations = 0;
      g_counting = j >= 2;
      const int status = nd_step(p);
      g_counting = false;
      ND_OK_OR_FAIL(status);
      const double force = stat(p, ND_CONTACT_FORCE);
      ck_assert_msg(force == first_run[j], "%dD P%d %s: step %d of the second run is not the first's", dim, degree,
                    sc.name, j);
      if (j < 2 || force == 0) continue;
      ++counted;
      iterations += static_cast<int>(stat(p, ND_NEWTON_ITERATIONS));
      ck_assert_msg(g_allocations == 0, "%dD P%d refine %d %s: contact step %d allocated %ld times", dim, degree,
                    refine, sc.name, j, g_allocations);
    }
    // (contact steps counted, Newton's among them)
    ck_assert_msg(counted >= 10 && iterations >= counted, "%dD P%d %s: %d contact steps counted, %d iterations", dim,
                  degree, sc.name, counted, iterations);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}

// dimension, degree, refinement: the rectangles (refined) on CHOLMOD's
// supernodal factor, the boxes
const int kCases[][3] = {{2, 1, 4}, {2, 2, 4}, {3, 1, 1}, {3, 2, 1}};

START_TEST(free_steps) { free_steps_allocate_nothing(kCases[_i][0], kCases[_i][1], kCases[_i][2]); }
END_TEST

START_TEST(contact_steps) { contact_steps_allocate_nothing(kCases[_i][0], kCases[_i][1], kCases[_i][2]); }
END_TEST

}  // namespace

int main() {
  Suite *s = suite_create("step_memory");
  TCase *tc = tcase_create("free_flight");
  tcase_set_timeout(tc, 60);
  tcase_add_loop_test(tc, free_steps, 0, static_cast<int>(sizeof kCases / sizeof kCases[0]));
  suite_add_tcase(s, tc);
  TCase *contact = tcase_create("contact");
  tcase_set_timeout(contact, 120);
  tcase_add_loop_test(contact, contact_steps, 0, static_cast<int>(sizeof kCases / sizeof kCases[0]));
  suite_add_tcase(s, contact);
  return nd_test_run(s);
}
