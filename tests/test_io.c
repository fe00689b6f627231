/* Files in and out: the Gmsh reader on the committed meshes and on malformed
 * inputs (each error names the file and line), and the VTU/PVD writers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "testutil.h"

START_TEST(reads_the_committed_meshes) {
  /* the contact boundary is the lower half circle (length pi R) or the lower
     hemisphere (area 2 pi R^2), polygonal: its measure approaches the exact
     one from below, within the chord error ~ (h/R)^2 */
  const char *names[] = {"disk_h4", "disk_h2", "disk_h1", "ball_h4", "ball_h2", "ball_h1"};
  const double R = 20, pi = 3.14159265358979;
  for (int i = 0; i < 6; ++i) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s.msh", ND_MESH_DIR, names[i]);
    nd_mesh m = NULL;
    ND_OK_OR_FAIL(nd_mesh_read_gmsh(path, &m));
    int dim = 0;
    int64_t lower = 0, upper = 0;
    ND_OK_OR_FAIL(nd_mesh_get_dimension(m, &dim));
    ND_OK_OR_FAIL(nd_mesh_get_region_size(m, 1, &lower));
    ND_OK_OR_FAIL(nd_mesh_get_region_size(m, 2, &upper));
    ck_assert_int_eq(dim, names[i][0] == 'd' ? 2 : 3);
    ck_assert_int_gt(lower, 0);
    ck_assert_int_gt(upper, 0);
    nd_problem p = NULL;
    ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
    const double origin[3] = {0, 0, 0}, up[3] = {0, dim == 2 ? 1 : 0, dim == 3 ? 1 : 0};
    ND_OK_OR_FAIL(nd_problem_set_material(p, 50, 0.25, 1));
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, origin, up));
    ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1, 1e-3));
    int64_t nq = 0;
    ND_OK_OR_FAIL(nd_problem_get_contact_point_count(p, &nq));
    double *w = malloc(sizeof(double) * (size_t)nq), *x = malloc(sizeof(double) * (size_t)(nq * dim)), sum = 0;
    ND_OK_OR_FAIL(nd_problem_get_contact_points(p, nq, x, w));
    for (int64_t q = 0; q < nq; ++q) {
      sum += w[q];
      ck_assert_double_le(x[q * dim + dim - 1], 25.0 + 1e-9); /* lower half */
    }
    const double exact = dim == 2 ? pi * R : 2 * pi * R * R, h = names[i][6] - '0';
    ck_assert_msg(sum <= exact && sum >= exact * (1 - (h / R) * (h / R)), "%s: contact measure %g, exact %g", names[i],
                  sum, exact);
    free(w);
    free(x);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
    ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  }
}
END_TEST

/* writes text to a temporary file and reads it as a mesh */
static int read_text(const char *text, nd_mesh *m, char *path, size_t size) {
  snprintf(path, size, "/tmp/nd_test_io_%d.msh", (int)getpid());
  FILE *f = fopen(path, "w");
  ck_assert_ptr_nonnull(f);
  fputs(text, f);
  fclose(f);
  const int status = nd_mesh_read_gmsh(path, m);
  remove(path);
  return status;
}

START_TEST(malformed_files_are_refused_with_file_and_line) {
  static const struct {
    const char *text, *words;
    int code;
  } cases[] = {
      {"$Nodes\n", ":1: expected '$MeshFormat'", ND_ERR_FORMAT},
      {"$MeshFormat\n3.0 0 8\n$EndMeshFormat\n", ":2: MSH version 3.0 is not supported", ND_ERR_FORMAT},
      {"$MeshFormat\n4.1 1 8\n$EndMeshFormat\n", ":2: binary MSH files are not supported", ND_ERR_FORMAT},
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 x 0 0\n$EndNodes\n",
       ":7: expected a node coordinate (a number), found 'x'", ND_ERR_FORMAT},
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n"
       "$Elements\n1\n1 3 2 0 1 1 2 3 4\n$EndElements\n",
       ":13: element type 3 is not supported", ND_ERR_FORMAT},
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n$Elements\n1\n1 1 2 0 1 1 7\n"
       "$EndElements\n",
       "node 7, which is not in $Nodes", ND_ERR_FORMAT},
      {"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n0 1 0 2\n1\n",
       ":5: the number of nodes (2) is more than the rest of the file (15 bytes) can hold", ND_ERR_FORMAT},
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n", "no line, triangle or tetrahedron",
       ND_ERR_FORMAT},
  };
  char path[256];
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    nd_mesh m = (nd_mesh)(void *)path;
    const int status = read_text(cases[i].text, &m, path, sizeof path);
    ck_assert_msg(status == cases[i].code, "case %zu: status %d (%s)", i, status, nd_last_error());
    ck_assert_ptr_null(m);
    ck_assert_msg(strstr(nd_last_error(), "nd_mesh_read_gmsh: ") == nd_last_error(), "case %zu: %s", i, nd_last_error());
    ck_assert_msg(strstr(nd_last_error(), path) != NULL, "case %zu does not name the file: %s", i, nd_last_error());
    ck_assert_msg(strstr(nd_last_error(), cases[i].words) != NULL, "case %zu: '%s' lacks '%s'", i, nd_last_error(),
                  cases[i].words);
  }
  nd_mesh m = NULL;
  ck_assert_int_eq(nd_mesh_read_gmsh("/nonexistent/dir/mesh.msh", &m), ND_ERR_IO);
  ck_assert_ptr_nonnull(strstr(nd_last_error(), "/nonexistent/dir/mesh.msh"));
}
END_TEST

/* a text file into buf, NUL-terminated; it must fit */
static void read_whole(const char *path, char *buf, size_t size) {
  FILE *f = fopen(path, "r");
  ck_assert_ptr_nonnull(f);
  const size_t len = fread(buf, 1, size - 1, f);
  buf[len] = 0;
  ck_assert_msg(fgetc(f) == EOF, "%s is larger than %zu bytes", path, size - 1);
  fclose(f);
}

START_TEST(writes_vtu_and_pvd) {
  /* a P2 strip in contact: the file lists every FE node, every cell and the
     contact facets, and the .pvd names its files */
  const double lo[2] = {0, 0}, hi[2] = {1, 0.25}, blo[2] = {-1, -1}, bhi[2] = {2, 0}, o[2] = {0, -0.01}, up[2] = {0, 1};
  const double g[2] = {0, -1};
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_rectangle(4, 1, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  ND_OK_OR_FAIL(nd_problem_create(m, 2, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 10, 0.3, 1));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1, 1e-3));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.05));
  for (int k = 0; k < 10; ++k) ND_OK_OR_FAIL(nd_step(p));
  double active = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_ACTIVE_POINTS, &active));
  ck_assert_double_gt(active, 0);
  char vtu[256], pvd[256];
  snprintf(vtu, sizeof vtu, "/tmp/nd_test_io_%d.vtu", (int)getpid());
  snprintf(pvd, sizeof pvd, "/tmp/nd_test_io_%d.pvd", (int)getpid());
  ND_OK_OR_FAIL(nd_problem_write_vtu(p, vtu));
  static char text[1 << 16];
  read_whole(vtu, text, sizeof text);
  /* 4x1 rectangles -> 8 triangles; P2: 5*3 + 5*... nodes = the library's count */
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  char expect[128];
  snprintf(expect, sizeof expect, "NumberOfPoints=\"%lld\" NumberOfCells=\"%d\"", (long long)n, 8 + 4);
  ck_assert_msg(strstr(text, expect) != NULL, "missing %s", expect);
  ck_assert_ptr_nonnull(strstr(text, "Name=\"displacement\""));
  ck_assert_ptr_nonnull(strstr(text, "Name=\"contact_pressure\""));
  ck_assert_ptr_nonnull(strstr(text, "</VTKFile>"));
  const char *files[2] = {vtu, vtu};
  const double times[2] = {0.0, 0.5};
  ND_OK_OR_FAIL(nd_write_pvd(pvd, 2, files, times));
  ck_assert_int_eq(nd_problem_write_vtu(p, "/nonexistent/dir/x.vtu"), ND_ERR_IO);
  ck_assert_int_eq(nd_write_pvd(pvd, 0, files, times), ND_ERR_SIZE);
  remove(vtu);
  remove(pvd);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* the number after the first '>' that follows `name` in text (a FieldData
   value), or the start of the values of the DataArray called `name` */
static const char *values_of(const char *text, const char *name) {
  char key[64];
  snprintf(key, sizeof key, "Name=\"%s\"", name);
  const char *at = strstr(text, key);
  ck_assert_msg(at != NULL, "no DataArray %s", name);
  at = strchr(at, '>');
  ck_assert_ptr_nonnull(at);
  return at + 1;
}

/* An affine displacement u = G x has the constant stress sigma(G) =
   lambda tr(G) I + mu (G + G^T) (2D plane strain: sigma_zz = lambda tr G;
   1D: E G): every cell's stress in the VTU (at its centroid) equals it to
   round-off, P1 and P2, 1D-3D. The FieldData holds ND_TIME and ND_STEP_INDEX
   (printed with 17 digits: read back exactly). */
START_TEST(vtu_has_time_cycle_and_stress) {
  const double E = 10, nu = 0.3, lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double Gall[9] = {0.3, -0.2, 0.1, 0.5, -0.4, 0.25, -0.15, 0.05, 0.2};
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 0.5, 0.75};
  char vtu[256];
  snprintf(vtu, sizeof vtu, "/tmp/nd_test_io_stress_%d.vtu", (int)getpid());
  for (int dim = 1; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree) {
      nd_mesh m = NULL;
      nd_problem p = NULL;
      if (dim == 1) ND_OK_OR_FAIL(nd_mesh_create_interval(5, 0, 1, &m));
      if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle(3, 2, lo, hi, &m));
      if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box(2, 2, 1, lo, hi, &m));
      int64_t n_cells = 0;
      ND_OK_OR_FAIL(nd_mesh_get_cell_count(m, &n_cells));
      ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
      ND_OK_OR_FAIL(nd_mesh_destroy(&m));
      ND_OK_OR_FAIL(nd_problem_set_material(p, E, nu, 1));
      ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
      ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.01));
      int64_t n = 0;
      ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
      double *x = malloc(sizeof(double) * (size_t)(n * dim)), *u = malloc(sizeof(double) * (size_t)(n * dim));
      ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
      double G[9] = {0}, want[9] = {0}, gmax = 0;
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) G[3 * i + j] = Gall[3 * i + j], gmax = fmax(gmax, fabs(G[3 * i + j]));
      for (int64_t a = 0; a < n; ++a)
        for (int i = 0; i < dim; ++i) {
          u[a * dim + i] = 0;
          for (int j = 0; j < dim; ++j) u[a * dim + i] += G[3 * i + j] * x[a * dim + j];
        }
      const double tr = G[0] + G[4] + G[8];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) want[3 * i + j] = mu * (G[3 * i + j] + G[3 * j + i]) + (i == j ? lambda * tr : 0);
      if (dim == 1) want[0] = E * G[0];
      /* a few steps from rest, then u = G x at the current time */
      for (int k = 0; k < 3; ++k) ND_OK_OR_FAIL(nd_step(p));
      ND_OK_OR_FAIL(nd_problem_set_state(p, n, u, NULL));
      ND_OK_OR_FAIL(nd_problem_write_vtu(p, vtu));
      static char text[1 << 20];
      read_whole(vtu, text, sizeof text);
      double t = 0, steps = 0;
      ND_OK_OR_FAIL(nd_get_scalar(p, ND_TIME, &t));
      ND_OK_OR_FAIL(nd_get_scalar(p, ND_STEP_INDEX, &steps));
      ck_assert(steps == 3);
      ck_assert_msg(strtod(values_of(text, "TIME"), NULL) == t, "TIME differs from ND_TIME");
      ck_assert_msg(strtod(values_of(text, "CYCLE"), NULL) == steps, "CYCLE differs from ND_STEP_INDEX");
      ck_assert(strstr(text, "<FieldData>") < strstr(text, "<Piece"));
      const int n_comp = dim == 1 ? 1 : 9;
      const char *at = values_of(text, "stress");
      double worst = 0;
      for (int64_t c = 0; c < n_cells; ++c)
        for (int k = 0; k < n_comp; ++k) {
          char *end = NULL;
          const double v = strtod(at, &end);
          ck_assert_msg(end != at, "cell %lld: stress component %d missing", (long long)c, k);
          at = end;
          worst = fmax(worst, fabs(v - want[k]));
        }
      /* the gradient of an interpolated affine field: sums of O(1/h) terms,
         a few hundred ulps of E |G| at most */
      ck_assert_msg(worst <= 1e-12 * E * gmax, "%dD P%d: stress off by %g", dim, degree, worst);
      free(x);
      free(u);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
  remove(vtu);
}
END_TEST

int main(void) {
  Suite *s = suite_create("io");
  TCase *tc = tcase_create("files");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, reads_the_committed_meshes);
  tcase_add_test(tc, malformed_files_are_refused_with_file_and_line);
  tcase_add_test(tc, writes_vtu_and_pvd);
  tcase_add_test(tc, vtu_has_time_cycle_and_stress);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
