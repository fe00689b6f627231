// The semi-smooth Newton's stopping rule on one DOF touching the obstacle:
// U = 1 exactly at the solution, where P = U - 1 = 0. A tangent solver that
// returns the exact update plus an alternating disturbance +-d makes the point
// flip between active and inactive at every iteration, as round-off does
// when P_q sits at zero. At round-off (d = 2 ulp of U) the flips move nothing
// and Newton must stop; at d = 1e-6 the iterate is genuinely off and Newton
// must not claim convergence.
#include <check.h>

#include <cfloat>
#include <cmath>

#include "solve/newton.hpp"
#include "testutil.h"

namespace {

// T x = x / (A + kappa N'), plus +-d in turn (the 1x1 tangent)
class Wobbly : public nd::TangentSolver {
 public:
  Wobbly(double A, double d) : A_(A), d_(d) {}
  void solve(const nd::ContactLaw &law, double kappa, const double *U, bool any_active, double *x, const double *,
             const std::vector<double> *) override {
    double value = 0, slope = 0;
    if (any_active) law.law(0, law.P(0, U), value, slope);
    x[0] = x[0] / (A_ + kappa * law.cp->w[0] / law.cp->gamma[0] * slope) + (flips_++ % 2 ? -d_ : d_);
  }
  const char *name() const override { return "wobbly"; }

 private:
  double A_, d_;
  long flips_ = 0;
};

struct OneDof {
  nd::Csr A, M;
  nd::ContactPoints cp;
  nd::ContactLaw law;
  OneDof() {
    A = nd::csr_from_rows({{0}});
    A.val = {2.0};
    M = A;
    M.val = {1.0};
    cp.a.push_back(nd::SparseRow{{0}, {1.0}});
    cp.s.push_back(nd::SparseRow{{0}, {0.0}});
    cp.w = {1.0}, cp.gamma = {0.5}, cp.gap = {1.0};  // P = U - 1
    law.cp = &cp;
  }
};

nd::NewtonResult run(double d, double &U_out) {
  OneDof s;
  Wobbly t(2.0, d);
  nd::NewtonSystem sys{&s.A, &t, &s.M, 1.0, 1.0, &s.law};
  std::vector<double> r{2.0}, U{0.5};  // A U = r at U = 1 with N = 0: the solution sits on the kink
  const nd::NewtonResult res = nd::newton_solve(sys, r, nd::NewtonOptions{}, U);
  U_out = U[0];
  return res;
}

}  // namespace

START_TEST(flips_at_roundoff_are_converged) {
  double U = 0;
  const nd::NewtonResult res = run(2 * DBL_EPSILON, U);
  ck_assert_msg(res.converged, "not converged after %d iterations (residual %g)", res.iterations, res.residual);
  ck_assert_int_le(res.iterations, 4);
  ck_assert_double_le(std::fabs(U - 1), 4 * DBL_EPSILON);
}
END_TEST

START_TEST(flips_off_the_solution_are_not) {
  double U = 0;
  const nd::NewtonResult res = run(1e-6, U);
  ck_assert_msg(!res.converged, "converged with U - 1 = %g", U - 1);
  ck_assert_int_eq(res.iterations, nd::NewtonOptions{}.max_iter);
}
END_TEST

int main(void) {
  Suite *s = suite_create("newton");
  TCase *tc = tcase_create("stopping");
  tcase_add_test(tc, flips_at_roundoff_are_converged);
  tcase_add_test(tc, flips_off_the_solution_are_not);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
