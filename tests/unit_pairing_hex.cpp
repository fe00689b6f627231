// A contact pair's master face on a hexahedron (contact/pairing.hpp,
// docs/design.md §10.3): one Q1 and Q2 hexahedron with its top face warped
// (one corner raised, another pushed sideways: not flat). For points above
// it and beside it, the landing is no farther than the nearest point of a
// fine grid of the face (it is the nearest point), an inner landing's y - z
// lies along its normal, the master cell's reference point of the pairing
// is z (the cell's trilinear map), and a linear displacement at the paired
// point is that of z (counterpart_displacement: Q1 and Q2 hold it exactly).
// On the face's extension (on_facet), an inner landing is not beyond the
// facet and a point over a corner 0.3 outside it is.
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "common/error.hpp"  // before check.h, which defines fail
#include "contact/obstacles.hpp"
#include "contact/pairing.hpp"
#include "mesh/cell_shape.hpp"
#include "testutil.h"

#include <check.h>

namespace {

const double kEps = std::numeric_limits<double>::epsilon();

// the unit cube as one hexahedron, its top face warped; region 1 the top face
std::shared_ptr<nd::Mesh> warped_cube() {
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  auto m = std::make_shared<nd::Mesh>(nd::make_box(1, 1, 1, lo, hi, ND_CELL_HEXAHEDRON));
  for (int64_t v = 0; v < m->n_vertices; ++v) {
    double *x = &m->coords[3 * v];
    if (x[2] == 1 && x[0] == 1 && x[1] == 1) x[2] = 1.3;              // raised
    if (x[2] == 1 && x[0] == 0 && x[1] == 1) x[0] = -0.2, x[2] = 0.9;  // pushed aside and down
  }
  const double tlo[3] = {-1, -1, 0.5}, thi[3] = {2, 2, 2};
  nd::add_region_box(*m, 1, tlo, thi);
  return m;
}

// the trilinear map of the cell (its 8 vertices) at xi
void cell_point(const nd::Mesh &m, int64_t cell, const double *xi, double *out) {
  const double *x[8];
  for (int v = 0; v < 8; ++v) x[v] = m.x(m.cell(cell)[v]);
  nd::cube::to_physical(3, x, xi, out);
}

double d2(const double *a, const double *b) {
  double s = 0;
  for (int k = 0; k < 3; ++k) s += (a[k] - b[k]) * (a[k] - b[k]);
  return s;
}

START_TEST(a_warped_face_is_projected_on_exactly) {
  for (int degree = 1; degree <= 2; ++degree) {
    auto m = warped_cube();
    ck_assert_int_eq(static_cast<int>(m->regions.at(1).size()), 1);
    const int64_t b = *m->regions.at(1).begin();
    const nd::Facet &f = m->boundary[b];
    nd::Space sp(m, degree);
    nd::DofMap dofs(sp, {});
    nd::MasterSurface surface(sp, dofs, 1, nullptr);
    // U = A x + c at every node: its value at any point of the cell is A x + c
    const double A[9] = {0.3, -0.1, 0.2, 0.05, 0.4, -0.3, 0.1, 0.2, -0.2}, c[3] = {0.01, -0.02, 0.03};
    std::vector<double> U(static_cast<size_t>(sp.n_dofs()));
    for (int64_t node = 0; node < sp.n_nodes; ++node)
      for (int i = 0; i < 3; ++i) {
        double u = c[i];
        for (int k = 0; k < 3; ++k) u += A[3 * i + k] * sp.node_x(node)[k];
        U[static_cast<size_t>(dofs.free[node * 3 + i])] = u;
      }
    int inner = 0, edges = 0;
    for (int i = 0; i < 9; ++i)
      for (int j = 0; j < 9; ++j) {
        // from 0.3 beyond one edge to 0.3 beyond the other, 0.05 to 0.45 above
        const double y[3] = {-0.3 + 1.6 * i / 8, -0.3 + 1.6 * j / 8, 1.2 + 0.05 * ((i * 7 + j * 3) % 9)};
        const nd::Projection p = surface.project(y);
        ck_assert_int_eq(p.facet, b);
        ck_assert_double_eq(p.bary[2], 0);
        // z: the cell's point at the pairing's reference coordinates
        double xi[3], z[3];
        nd::facet_point_reference(*m, f, p.bary, xi);
        cell_point(*m, f.cell, xi, z);
        // (every coordinate of size 1, a few tens of roundings)
        const double tol = 64 * kEps;
        // no grid point of the face is nearer (of 201 x 201, at the same map)
        double grid = std::numeric_limits<double>::infinity();
        for (int a = 0; a <= 200; ++a)
          for (int e = 0; e <= 200; ++e) {
            const double st[2] = {a / 200.0, e / 200.0};
            double g[3], w[3];
            nd::facet_point_reference(*m, f, st, w);
            cell_point(*m, f.cell, w, g);
            grid = std::fmin(grid, d2(g, y));
          }
        ck_assert_double_le(d2(z, y), grid + tol);
        // d = (y - z).nu, nu a unit vector pointing up (out of the cell)
        double r[3], dn = 0, nn = 0;
        for (int k = 0; k < 3; ++k) r[k] = y[k] - z[k], dn += r[k] * p.nu[k], nn += p.nu[k] * p.nu[k];
        ck_assert_double_le(std::fabs(dn - p.d), tol);
        ck_assert_double_le(std::fabs(nn - 1), tol);
        ck_assert_double_gt(p.nu[2], 0);
        const bool inside = p.bary[0] > 0 && p.bary[0] < 1 && p.bary[1] > 0 && p.bary[1] < 1;
        if (inside) {  // y - z along nu: r = d nu
          ++inner;
          double along[3];
          for (int k = 0; k < 3; ++k) along[k] = p.d * p.nu[k];
          ck_assert_double_le(d2(r, along), tol * tol);
        } else {
          ++edges;
        }
        // the paired point's displacement is A z + c
        double u[3];
        nd::counterpart_displacement(sp, dofs, b, p.bary, U.data(), u);
        for (int row = 0; row < 3; ++row) {
          double expected = c[row];
          for (int k = 0; k < 3; ++k) expected += A[3 * row + k] * z[k];
          ck_assert_double_le(std::fabs(u[row] - expected), tol);
        }
        // on_facet: an inner landing's coordinates, not beyond the facet;
        // over a corner 0.3 beyond both its edges (the square's x and y
        // there: s and t about -0.3 or 1.3), beyond
        const nd::Projection held = surface.on_facet(b, y);
        if (inside) {
          ck_assert(held.bary[0] == p.bary[0] && held.bary[1] == p.bary[1]);
          ck_assert(!nd::beyond_facet(4, held.bary, nd::kPairSlack));
        }
        if ((i == 0 && j == 0) || (i == 8 && j == 8)) ck_assert(nd::beyond_facet(4, held.bary, nd::kPairSlack));
      }
    ck_assert_int_gt(inner, 0);
    ck_assert_int_gt(edges, 0);
  }
}
END_TEST

}  // namespace

int main() {
  Suite *s = suite_create("pairing_hex");
  TCase *tc = tcase_create("faces");
  tcase_add_test(tc, a_warped_face_is_projected_on_exactly);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
