// The obstacles' shapes (contact/obstacle.hpp), placed by a pose: the normal
// is the gradient of the signed distance (central differences), of unit
// length, and the distance of a point moved by the pose from the placed
// obstacle is the unmoved one's; the nearest of several acts; a cylinder
// ignores the position along its axis; a refresh takes every point's normal.
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "common/error.hpp"  // before check.h, which defines fail
#include "contact/obstacles.hpp"
#include "testutil.h"

#include <check.h>

namespace {

// a rotation about the unit axis (a, b, c) by angle w (Rodrigues), row-major
nd::Pose pose(double w, const double *axis, const double *t) {
  nd::Pose p;
  const double c = std::cos(w), s = std::sin(w), x = axis[0], y = axis[1], z = axis[2];
  const double R[9] = {c + x * x * (1 - c),     x * y * (1 - c) - z * s, x * z * (1 - c) + y * s,
                       y * x * (1 - c) + z * s, c + y * y * (1 - c),     y * z * (1 - c) - x * s,
                       z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)};
  for (int k = 0; k < 9; ++k) p.R[k] = R[k];
  for (int k = 0; k < 3; ++k) p.t[k] = t[k];
  return p;
}

struct Case {
  const char *name;
  int dim;
  std::shared_ptr<const nd::Shape> shape;
  double curvature;  // 1/R (0: a plane)
  bool inside;
};

std::vector<Case> cases() {
  const double c2[2] = {0.3, -0.7}, c3[3] = {0.3, -0.7, 0.2}, n3[3] = {0.0, 0.6, 0.8}, ax[3] = {1, 2, 2};
  return {
      {"plane", 3, nd::make_plane_shape(c3, n3, 3), 0, false},
      {"circle outside", 2, nd::make_sphere(c2, 2.0, false, 2), 0.5, false},
      {"circle inside", 2, nd::make_sphere(c2, 2.0, true, 2), 0.5, true},
      {"sphere outside", 3, nd::make_sphere(c3, 2.0, false, 3), 0.5, false},
      {"sphere inside", 3, nd::make_sphere(c3, 2.0, true, 3), 0.5, true},
      {"cylinder outside", 3, nd::make_cylinder(c3, ax, 1.5, false, 3), 1 / 1.5, false},
      {"cylinder inside", 3, nd::make_cylinder(c3, ax, 1.5, true, 3), 1 / 1.5, true},
  };
}

const double kAxis[3] = {0.48, 0.6, 0.64}, kZ[3] = {0, 0, 1}, kShift[3] = {0.25, -0.5, 1.0};

START_TEST(normal_is_the_gradient) {
  // central differences of step e: error <= e^2 max|d'''| / 6 + 2 eps max|d| / e;
  // d = +-(r - R), r the distance to the centre (axis), |r'''| <= 3/r^2, so
  // |d'''| <= 12 curvature^2 where r >= R/2 (the points nearer are left
  // out: d is not smooth at the centre); |d| < 10 at these points
  const double e = 1e-5, eps = std::numeric_limits<double>::epsilon();
  for (const Case &c : cases()) {
    const nd::Pose P = c.dim == 3 ? pose(0.7, kAxis, kShift) : pose(0.7, kZ, kShift);  // (2D: about z)
    const double bound = e * e * 12 * c.curvature * c.curvature / 6 + 2 * eps * 10 / e;
    for (int i = 0; i < 40; ++i) {
      const double x[3] = {std::sin(1.3 * i) * 3, std::cos(0.7 * i) * 3, std::sin(0.4 * i + 1) * 3};
      double d, nu[3] = {0, 0, 0};
      nd::obstacle_distance(*c.shape, P, c.dim, 0.0, x, d, nu);
      double len = 0;
      for (int k = 0; k < c.dim; ++k) len += nu[k] * nu[k];
      ck_assert_msg(std::fabs(len - 1) <= 8 * eps, "%s: |nu|^2 - 1 = %g", c.name, len - 1);
      if (c.curvature > 0) {  // r = R + d outside, R - d inside
        const double R = 1 / c.curvature, r = c.inside ? R - d : R + d;
        if (r < R / 2) continue;
      }
      for (int k = 0; k < c.dim; ++k) {
        double xp[3] = {x[0], x[1], x[2]}, xm[3] = {x[0], x[1], x[2]}, dp, dm, tmp[3];
        xp[k] += e, xm[k] -= e;
        nd::obstacle_distance(*c.shape, P, c.dim, 0.0, xp, dp, tmp);
        nd::obstacle_distance(*c.shape, P, c.dim, 0.0, xm, dm, tmp);
        const double fd = (dp - dm) / (2 * e);
        ck_assert_msg(std::fabs(fd - nu[k]) <= bound, "%s, point %d, component %d: d' %.15g, nu %.15g (bound %g)",
                      c.name, i, k, fd, nu[k], bound);
      }
    }
  }
}
END_TEST

START_TEST(pose_moves_the_obstacle) {
  // d of the placed obstacle at P(x) is the unmoved one's at x, and nu turns with R
  for (const Case &c : cases()) {
    const nd::Pose P2 = c.dim == 3 ? pose(1.1, kAxis, kShift) : pose(0.9, kZ, kShift);  // (2D: about z)
    for (int i = 0; i < 20; ++i) {
      const double x[3] = {std::sin(2.1 * i) * 3, std::cos(1.7 * i) * 3, c.dim == 3 ? std::sin(0.9 * i) * 3 : 0};
      double y[3] = {0, 0, 0};
      for (int r = 0; r < c.dim; ++r) {
        y[r] = P2.t[r];
        for (int k = 0; k < c.dim; ++k) y[r] += P2.R[r * 3 + k] * x[k];
      }
      double d0, n0[3] = {0, 0, 0}, d1, n1[3] = {0, 0, 0};
      nd::obstacle_distance(*c.shape, nd::Pose{}, c.dim, 0.0, x, d0, n0);
      nd::obstacle_distance(*c.shape, P2, c.dim, 0.0, y, d1, n1);
      ck_assert_msg(std::fabs(d1 - d0) <= 1e-14 * (1 + std::fabs(d0)) * 16, "%s: d %.17g vs %.17g", c.name, d1, d0);
      for (int r = 0; r < c.dim; ++r) {
        double Rn = 0;
        for (int k = 0; k < c.dim; ++k) Rn += P2.R[r * 3 + k] * n0[k];
        ck_assert_msg(std::fabs(n1[r] - Rn) <= 1e-14 * 16, "%s: nu[%d] %.17g vs R nu0 %.17g", c.name, r, n1[r], Rn);
      }
    }
  }
}
END_TEST

START_TEST(cylinder_ignores_the_axis) {
  const double p[3] = {0, 0, -20}, ax[3] = {1, 0, 0};
  auto cyl = nd::make_cylinder(p, ax, 20, false, 3);
  for (int i = 0; i < 10; ++i) {
    const double x[3] = {0.1, 3.0, 1.0}, y[3] = {0.1 + 1000.0 * i, 3.0, 1.0};
    double dx, dy, nx[3], ny[3];
    cyl->distance(0, x, dx, nx);
    cyl->distance(0, y, dy, ny);
    // the part along the axis is removed exactly: the same bits
    ck_assert(dx == dy && nx[0] == 0 && ny[0] == 0 && nx[1] == ny[1] && nx[2] == ny[2]);
  }
}
END_TEST

START_TEST(the_nearest_acts) {
  // a region with a plane y = 0 and a circle of radius 1 at (5, 3): the
  // smaller signed distance wins at each point
  const double c[2] = {5, 3};
  std::vector<nd::ContactPlane> planes{{1, {0, 0, 0}, {0, 1, 0}}};
  std::vector<nd::Obstacle> obstacles{{1, nd::make_sphere(c, 1, false, 2), nd::Pose{}}};
  const double near_plane[2] = {0, 0.5}, near_circle[2] = {5, 1.5};
  nd::Nearest a = nd::nearest(1, planes, obstacles, 2, 0, near_plane);
  nd::Nearest b = nd::nearest(1, planes, obstacles, 2, 0, near_circle);
  ck_assert_int_eq(a.which, -1);
  ck_assert_double_eq(a.d, 0.5);
  ck_assert_int_eq(b.which, 0);
  ck_assert_double_eq(b.d, 0.5);  // |(0, -1.5)| - 1, exact
  ck_assert_double_eq(b.nu[1], -1);
  ck_assert(nd::curved_region(1, obstacles) && !nd::curved_region(2, obstacles));
  ck_assert(nd::contact_regions(planes, obstacles) == std::vector<int>{1});
}
END_TEST

}  // namespace

int main() {
  Suite *s = suite_create("obstacles");
  TCase *tc = tcase_create("shapes");
  tcase_add_test(tc, normal_is_the_gradient);
  tcase_add_test(tc, pose_moves_the_obstacle);
  tcase_add_test(tc, cylinder_ignores_the_axis);
  tcase_add_test(tc, the_nearest_acts);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
