/* Meshes (issue 54, finding 8): two vertices at exactly the same position
 * are refused by nd_mesh_create and by the Gmsh reader (nodes used by
 * cells only: a file's unused duplicate nodes are dropped), naming both;
 * adding boundary facets to a region one nd_mesh_set_region call at a time
 * costs O(log n) per facet, not a pass over the boundary per call: 20,000
 * calls finish within the test's ctest TIMEOUT (tests/CMakeLists.txt), where
 * the quadratic path took minutes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "testutil.h"

static int mentions(const char *word) { return strstr(nd_last_error(), word) != NULL; }

START_TEST(duplicate_vertices_are_refused) {
  /* within one body (a connected component of the cells) a point held
     twice is a crack the mesh should not have: refused; two bodies may
     touch at a point each holds (docs/design.md §10.3) */
  nd_mesh m = NULL;
  /* 2D: two triangles that touch at a point held twice (vertices 1 and 3),
     joined into one body by a third (vertex 2 of the first, edge 4-5 of
     the second) */
  const double xy[] = {0, 0, 1, 0, 0, 1, 1, 0, 2, 0, 1, 1};
  const int64_t tri[] = {0, 1, 2, 3, 4, 5, 2, 4, 5};
  ck_assert_int_eq(nd_mesh_create(2, 6, xy, 3, tri, &m), ND_ERR_DEGENERATE);
  ck_assert_ptr_null(m);
  ck_assert_msg(mentions("vertices 1 and 3"), "%s", nd_last_error());
  /* -0 and 0 are the same position */
  const double xz[] = {0, 0, 1, 0, 0, 1, -0.0, 0, 2, 0, 1, 1};
  ck_assert_int_eq(nd_mesh_create(2, 6, xz, 3, tri, &m), ND_ERR_DEGENERATE);
  ck_assert_msg(mentions("vertices 0 and 3"), "%s", nd_last_error());
  /* the two triangles alone are two bodies touching at (1, 0): accepted */
  ND_OK_OR_FAIL(nd_mesh_create(2, 6, xy, 2, tri, &m));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  /* 3D: two tetrahedra, the last vertex of the second at the first's vertex
     2, and a third joining them (vertices 0, 4, 3 and 6: one body) */
  const double xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 5, 0, 0, 6, 0, 0, 5, 1, 0, 0, 1, 0};
  const int64_t tet[] = {0, 1, 2, 3, 4, 5, 6, 7, 0, 4, 6, 3};
  ck_assert_int_eq(nd_mesh_create(3, 8, xyz, 3, tet, &m), ND_ERR_DEGENERATE);
  ck_assert_msg(mentions("vertices 2 and 7"), "%s", nd_last_error());
  /* 1D: the bar in two pieces that meet at x = 1: two bodies, accepted; a
     third cell joining them makes one body with a point held twice */
  const double x[] = {0, 1, 1, 2};
  const int64_t seg[] = {0, 1, 2, 3, 0, 3};
  ND_OK_OR_FAIL(nd_mesh_create(1, 4, x, 2, seg, &m));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ck_assert_int_eq(nd_mesh_create(1, 4, x, 3, seg, &m), ND_ERR_DEGENERATE);
  ck_assert_msg(mentions("vertices 1 and 2"), "%s", nd_last_error());
  /* close is not equal: accepted */
  const double near[] = {0, 0, 1, 0, 0, 1, nextafter(1, 2), 0, 2, 0, 1, 1};
  ND_OK_OR_FAIL(nd_mesh_create(2, 6, near, 2, tri, &m));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
}
END_TEST

/* the Gmsh reader applies the rule to the nodes its cells use, by tag; a
   duplicate node that no cell uses is dropped with the other unused nodes */
START_TEST(gmsh_duplicate_nodes) {
  char path[] = "/tmp/nd_mesh_XXXXXX";
  const int fd = mkstemp(path);
  ck_assert_int_ge(fd, 0);
  close(fd);
  const char *head = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                     "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 0 0\n5 1 1 0\n$EndNodes\n";
  char text[512];
  nd_mesh m = NULL;
  snprintf(text, sizeof text, "%s$Elements\n2\n1 2 2 0 1 1 2 3\n2 2 2 0 1 2 5 3\n$EndElements\n", head);
  nd_test_write_file(path, text);
  ND_OK_OR_FAIL(nd_mesh_read_gmsh(path, &m)); /* node 4 repeats node 2, unused */
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_mesh_get_vertex_count(m, &n));
  ck_assert_int_eq(n, 4);
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  snprintf(text, sizeof text, "%s$Elements\n2\n1 2 2 0 1 1 2 3\n2 2 2 0 1 4 5 3\n$EndElements\n", head);
  nd_test_write_file(path, text);
  ck_assert_int_eq(nd_mesh_read_gmsh(path, &m), ND_ERR_DEGENERATE); /* used by the second triangle */
  ck_assert_ptr_null(m);
  ck_assert_msg(mentions("nodes 2 and 4") && mentions(path), "%s", nd_last_error());
  unlink(path);
}
END_TEST

/* a strip of nx x 1 squares (2 triangles each): 2 nx + 2 boundary facets.
   Vertex i is (i, 0), vertex nx + 1 + i is (i, 1). */
enum { NX = 10000 };

START_TEST(region_grows_one_facet_per_call) {
  const int64_t nv = 2 * (NX + 1);
  double *xy = malloc(sizeof(double) * (size_t)(2 * nv));
  int64_t *tri = malloc(sizeof(int64_t) * (size_t)(6 * NX));
  for (int64_t i = 0; i <= NX; ++i) {
    xy[2 * i] = (double)i, xy[2 * i + 1] = 0;
    xy[2 * (NX + 1 + i)] = (double)i, xy[2 * (NX + 1 + i) + 1] = 1;
  }
  for (int64_t i = 0; i < NX; ++i) {
    const int64_t a = i, b = i + 1, c = NX + 2 + i, d = NX + 1 + i;
    const int64_t t[6] = {a, b, c, a, c, d};
    memcpy(tri + 6 * i, t, sizeof t);
  }
  nd_mesh m = NULL;
  ND_OK_OR_FAIL(nd_mesh_create(2, nv, xy, 2 * NX, tri, &m));
  /* 20,000 facets, bottom and top, one call each (each facet twice: the second adds nothing) */
  for (int pass = 0; pass < 2; ++pass)
    for (int64_t i = 0; i < NX; ++i) {
      const int64_t bottom[2] = {i, i + 1}, top[2] = {NX + 2 + i, NX + 1 + i};
      ND_OK_OR_FAIL(nd_mesh_set_region(m, 1, 1, bottom));
      ND_OK_OR_FAIL(nd_mesh_set_region(m, 1, 1, top));
    }
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_mesh_get_region_size(m, 1, &n));
  ck_assert_int_eq(n, 2 * NX);
  /* an interior edge is still refused, the region unchanged */
  const int64_t inside[2] = {0, NX + 2};
  ck_assert_int_eq(nd_mesh_set_region(m, 1, 1, inside), ND_ERR_REGION);
  ND_OK_OR_FAIL(nd_mesh_get_region_size(m, 1, &n));
  ck_assert_int_eq(n, 2 * NX);
  /* the region is usable: a problem on it clamps the strip's two long sides */
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 1));
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  free(xy);
  free(tri);
}
END_TEST

int main(void) {
  Suite *s = suite_create("mesh");
  TCase *tc = tcase_create("mesh");
  tcase_set_timeout(tc, 0); /* (the time limit is ctest's TIMEOUT) */
  tcase_add_test(tc, duplicate_vertices_are_refused);
  tcase_add_test(tc, gmsh_duplicate_nodes);
  tcase_add_test(tc, region_grows_one_facet_per_call);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
