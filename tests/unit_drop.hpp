// The body the white-box contact tests drop on a plane: a rectangle (2D) or
// a box (3D) whose bottom facets (region 1) fall, turning, onto a plane
// `gap` below them; 1D: the bar of testutil. Through the C API.
#pragma once
#include <algorithm>
#include <vector>

#include "capi/handles.hpp"  // (a read mesh scaled in place; before check.h, whose fail() hides nd::fail)
#include "testutil.h"

namespace ndtest {

struct SchemeCase {
  int scheme;
  std::vector<double> params;
  const char *name;
};

inline const SchemeCase kSchemes[] = {
    {ND_SCHEME_THETA, {0.5}, "theta 0.5"},
    {ND_SCHEME_THETA, {1.0}, "theta 1"},
    {ND_SCHEME_NEWMARK, {0.25, 0.5}, "newmark"},
    {ND_SCHEME_HYBRID, {}, "hybrid"},
    {ND_SCHEME_GENERALIZED_ALPHA, {0.8}, "generalized-alpha 0.8"},
};

// The body of the drops: the block in cells of `cell_type` (ND_CELL_LIST;
// hexahedra: 4 x 2 x 2 of them, about the nodes of the 12 tetrahedra's P2),
// or a 2D Gmsh file (its path; its region 1 the contact boundary),
// moved and scaled to the block's place: its lowest point at y = 0, its
// rightmost at x = 2, its height 1 (the disk: [1,2] x [0,1]).
// bowl: in place of the plane, a circular bowl `gap` wider than the disk of
// diameter 1 at (1.5, 0.5) (a curved obstacle; for the disk's file).
struct Body {
  int cell_type = ND_CELL_SIMPLEX;
  const char *file = nullptr;
  bool bowl = false;
  const char *name = "simplices";
};
// the bodies in quadrilaterals and hexahedra of the white-box tests
inline const Body kQuads{ND_CELL_QUADRILATERAL, nullptr, false, "quadrilaterals"};
inline const Body kHexahedra{ND_CELL_HEXAHEDRON, nullptr, false, "hexahedra"};
#ifdef ND_MESH_DIR
inline const Body kMixed{ND_CELL_SIMPLEX, ND_MESH_DIR "/mixed.msh", false, "mixed.msh"};
inline const Body kDisk{ND_CELL_SIMPLEX, ND_MESH_DIR "/disk_quad_h4.msh", false, "disk_quad_h4"};
inline const Body kDiskInBowl{ND_CELL_SIMPLEX, ND_MESH_DIR "/disk_quad_h4.msh", true, "disk_quad_h4 in a bowl"};
#endif

inline nd_mesh body_mesh(int dim, int refine, const Body &body) {
  nd_mesh m = nullptr;
  if (body.file) {
    ck_assert(dim == 2);
    ND_OK_OR_FAIL(nd_mesh_read_gmsh(body.file, &m));
    std::vector<double> &x = m->mesh.coords;
    double lo[2] = {x[0], x[1]}, hi[2] = {x[0], x[1]};
    for (size_t i = 0; i < x.size(); ++i) lo[i % 2] = std::min(lo[i % 2], x[i]), hi[i % 2] = std::max(hi[i % 2], x[i]);
    const double to[2] = {2, 0}, from[2] = {hi[0], lo[1]};
    for (size_t i = 0; i < x.size(); ++i) x[i] = to[i % 2] + (x[i] - from[i % 2]) / (hi[1] - lo[1]);
    return m;
  }
  const double lo[3] = {0, 0, 0}, hi[3] = {2, 1, 1};
  const int hex = body.cell_type == ND_CELL_HEXAHEDRON ? 2 : 1;
  if (dim == 2)
    ND_OK_OR_FAIL(nd_mesh_create_rectangle_cells(4 * refine, 2 * refine, lo, hi, body.cell_type, &m));
  else
    ND_OK_OR_FAIL(nd_mesh_create_box_cells(2 * hex, hex, hex, lo, hi, body.cell_type, &m));
  // the bottom facets (y = 0 in 2D, z = 0 in 3D)
  const double blo[3] = {-1, dim == 2 ? -0.1 : -1, -0.1}, bhi[3] = {3, dim == 2 ? 0.1 : 2, 0.1};
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  return m;
}

// The block of the drops: a rectangle [0,2]x[0,1] (2D) or box [0,2]x[0,1]^2
// (3D) (or another body), E = 10, nu = 0.3, rho = 1, its bottom facets
// (region 1) `gap` above a plane (no contact region when gap <= 0), tau =
// 0.01; with clamp_x0 its face x = 0 (region 2) clamped; refine (2D):
// 4 refine x 2 refine cells. The initial state is the caller's.
inline nd_problem block_scene(int dim, int degree, const SchemeCase &sc, double theta, double gap,
                              bool clamp_x0 = false, int refine = 1, const Body &body = {}) {
  const double *params = sc.params.empty() ? nullptr : sc.params.data();
  nd_problem p = nullptr;
  nd_mesh m = body_mesh(dim, refine, body);
  const double clo[3] = {-0.1, -1, -1}, chi[3] = {0.1, 2, 2};
  if (clamp_x0) ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, clo, chi));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  if (clamp_x0) ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 2));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 10.0, 0.3, 1.0));
  if (gap > 0 && body.bowl) {
    const double center[2] = {1.5, 0.5};
    ND_OK_OR_FAIL(nd_problem_add_contact_sphere(p, 1, center, 0.5 + gap, 1));
  } else if (gap > 0) {
    const double plane[3] = {0, dim == 2 ? -gap : 0, dim == 3 ? -gap : 0};
    const double up[3] = {0, dim == 2 ? 1.0 : 0, dim == 3 ? 1.0 : 0};
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, plane, up));
  }
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, theta, 0.0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, sc.scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.01));
  return p;
}

// speed: the downward velocity at x = 0 (it grows with x: the body turns)
inline nd_problem drop_scene(int dim, int degree, const SchemeCase &sc, double theta, double gap = 0.02,
                             double speed = 0.1, int refine = 1, const Body &body = {}) {
  const double *params = sc.params.empty() ? nullptr : sc.params.data();
  if (dim == 1) return nd_test_bar(10, degree, sc.scheme, params, theta, 0.0, 0.025);  // (gap, speed: its own)
  nd_problem p = block_scene(dim, degree, sc, theta, gap, false, refine, body);
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  const size_t len = static_cast<size_t>(nodes * dim);
  std::vector<double> x(len), v0(len, 0.0);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, nodes, x.data()));
  for (int64_t i = 0; i < nodes; ++i)  // falling and turning: the active set grows from x = 2
    v0[i * dim + dim - 1] = -speed - 0.6 * x[i * dim] + 0.1 * x[i * dim + dim - 1];
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nodes, nullptr, v0.data()));
  return p;
}

}  // namespace ndtest
