/* Files in and out: the Gmsh reader on the committed meshes and on malformed
 * inputs (each error names the file and line), and the VTU/PVD writers;
 * what a write does to what is at its path (issue 54, findings 1 and 10). */
#define _GNU_SOURCE /* O_TMPFILE */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <time.h>
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
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 0 1\n6 0 1 1\n"
       "$EndNodes\n$Elements\n1\n1 6 2 0 1 1 2 3 4 5 6\n$EndElements\n",
       ":15: element type 6 is not supported", ND_ERR_FORMAT},
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n$Elements\n1\n1 1 2 0 1 1 7\n"
       "$EndElements\n",
       "node 7, which is not in $Nodes", ND_ERR_FORMAT},
      {"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n0 1 0 2\n1\n",
       ":5: the number of nodes (2) is more than the rest of the file (15 bytes) can hold", ND_ERR_FORMAT},
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n", "no line, triangle, quadrilateral, tetrahedron or hexahedron",
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

/* a strip of nx x ny cells (P<degree>) falling on a plane under gravity,
   after `steps` hybrid steps */
static nd_problem strip_after(int nx, int ny, int degree, int steps) {
  const double lo[2] = {0, 0}, hi[2] = {1, 0.25}, blo[2] = {-1, -1}, bhi[2] = {2, 0}, o[2] = {0, -0.01}, up[2] = {0, 1};
  const double g[2] = {0, -1};
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_rectangle(nx, ny, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 10, 0.3, 1));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1, 1e-3));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.05));
  for (int k = 0; k < steps; ++k) ND_OK_OR_FAIL(nd_step(p));
  return p;
}

START_TEST(writes_vtu_and_pvd) {
  /* a P2 strip in contact: the file lists every FE node, every cell and the
     contact facets, and the .pvd names its files */
  nd_problem p = strip_after(4, 1, 2, 10);
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
    for (int type = 0; type <= (dim > 1 ? dim - 1 : 0); type += dim > 1 ? dim - 1 : 1) /* simplices, Q cells */
    for (int degree = 1; degree <= 2; ++degree) {
      nd_mesh m = NULL;
      nd_problem p = NULL;
      if (dim == 1) ND_OK_OR_FAIL(nd_mesh_create_interval(5, 0, 1, &m));
      if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle_cells(3, 2, lo, hi, type, &m));
      if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box_cells(2, 2, 1, lo, hi, type, &m));
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
      ck_assert_msg(worst <= 1e-12 * E * gmax, "%dD P%d cell type %d: stress off by %g", dim, degree, type, worst);
      if (type) { /* VTK_QUAD 9, VTK_HEXAHEDRON 12, VTK_BIQUADRATIC_QUAD 28, VTK_TRIQUADRATIC_HEXAHEDRON 29 */
        const long vtk = strtol(values_of(text, "types"), NULL, 10);
        ck_assert_int_eq(vtk, degree == 1 ? (dim == 2 ? 9 : 12) : (dim == 2 ? 28 : 29));
      }
      free(x);
      free(u);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
  remove(vtu);
}
END_TEST

/* ---- what a write does to what is at the path (issue 54, findings 1, 10) ---- */

/* a strip of nx x ny cells after a few steps, and its checkpoint block */
static nd_problem stepped_strip(int nx, int ny, unsigned char **block, int64_t *nbytes) {
  nd_problem p = strip_after(nx, ny, 1, 3);
  ND_OK_OR_FAIL(nd_problem_get_state_size(p, nbytes));
  *block = malloc((size_t)*nbytes);
  ND_OK_OR_FAIL(nd_problem_save_state(p, *nbytes, *block));
  return p;
}
static nd_problem stepped(unsigned char **block, int64_t *nbytes) { return stepped_strip(4, 1, block, nbytes); }

static void make_dir(char *dir) { ck_assert_ptr_nonnull(mkdtemp(dir)); }
static void rm_dir(const char *dir) {
  char cmd[256];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  ck_assert_int_eq(system(cmd), 0);
}

/* the whole file (or FIFO) at path; its size in *n */
static unsigned char *slurp(const char *path, int64_t *n) {
  const int fd = open(path, O_RDONLY);
  ck_assert_msg(fd >= 0, "cannot open %s: %s", path, strerror(errno));
  size_t cap = 1 << 16, len = 0;
  unsigned char *buf = malloc(cap);
  for (;;) {
    if (len == cap) buf = realloc(buf, cap *= 2);
    const ssize_t k = read(fd, buf + len, cap - len);
    if (k < 0 && errno == EINTR) continue;
    ck_assert_int_ge(k, 0);
    if (k == 0) break;
    len += (size_t)k;
  }
  close(fd);
  *n = (int64_t)len;
  return buf;
}

static int holds(const char *path, const unsigned char *block, int64_t nbytes) {
  int64_t n = 0;
  unsigned char *got = slurp(path, &n);
  const int same = n == nbytes && memcmp(got, block, (size_t)n) == 0;
  free(got);
  return same;
}

/* the names in dir, sorted, "a b c" (dot files too, . and .. not) */
static void listing(const char *dir, char *out, size_t size) {
  char cmd[256];
  snprintf(cmd, sizeof cmd, "ls -A '%s' | tr '\\n' ' '", dir);
  FILE *f = popen(cmd, "r");
  ck_assert_ptr_nonnull(f);
  const size_t n = fread(out, 1, size - 1, f);
  out[n] = 0;
  pclose(f);
}

static mode_t type_of(const char *path) {
  struct stat st;
  ck_assert_int_eq(lstat(path, &st), 0);
  return st.st_mode & S_IFMT;
}

/* A FIFO: with no reader the write fails at once with ND_ERR_IO (no wait,
   nothing replaced); with a reader (a child) the reader gets the checkpoint,
   the VTU and the PVD, and the FIFO stays a FIFO. The old writer renamed a
   regular file over it. */
START_TEST(a_fifo_is_written_in_place) {
  char dir[] = "/tmp/nd_test_write_XXXXXX", fifo[64], copy[64];
  make_dir(dir);
  snprintf(fifo, sizeof fifo, "%s/fifo", dir);
  ck_assert_int_eq(mkfifo(fifo, 0600), 0);
  int64_t nbytes = 0, n2 = 0;
  unsigned char *block = NULL, *block2 = NULL;
  nd_problem p = stepped(&block, &nbytes);
  const int lonely = nd_problem_save_state_file(p, fifo);
  ck_assert_int_eq(type_of(fifo), S_IFIFO);
  ck_assert_msg(lonely == ND_ERR_IO, "%d %s", lonely, nd_last_error());
  ck_assert_msg(strstr(nd_last_error(), "no process reads") && strstr(nd_last_error(), fifo), "%s", nd_last_error());
  for (int what = 0; what < 3; ++what) {
    snprintf(copy, sizeof copy, "%s/copy%d", dir, what);
    const pid_t pid = fork();
    ck_assert_int_ge(pid, 0);
    if (pid == 0) { /* the reader: the FIFO's bytes into a regular file */
      const int in = open(fifo, O_RDONLY), out = open(copy, O_WRONLY | O_CREAT | O_TRUNC, 0600);
      char buf[4096];
      ssize_t k;
      while (in >= 0 && out >= 0 && (k = read(in, buf, sizeof buf)) > 0)
        if (write(out, buf, (size_t)k) != k) _exit(2);
      _exit(in >= 0 && out >= 0 ? 0 : 1);
    }
    /* until the child has opened the FIFO: "no process reads" */
    const char *files[1] = {"a.vtu"};
    const double t[1] = {0};
    int st = ND_ERR_IO;
    for (int tries = 0; tries < 2000; ++tries) {
      st = what == 0 ? nd_problem_save_state_file(p, fifo)
           : what == 1 ? nd_problem_write_vtu(p, fifo)
                       : nd_write_pvd(fifo, 1, files, t);
      if (st != ND_ERR_IO || !strstr(nd_last_error(), "no process reads")) break;
      nanosleep(&(struct timespec){0, 5000000}, NULL);
    }
    ck_assert_msg(st == ND_OK, "%d %s", st, nd_last_error());
    int status = 0;
    waitpid(pid, &status, 0);
    ck_assert(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    ck_assert_int_eq(type_of(fifo), S_IFIFO);
    int64_t n = 0;
    unsigned char *got = slurp(copy, &n);
    if (what == 0) ck_assert(n == nbytes && memcmp(got, block, (size_t)n) == 0);
    if (what > 0) {
      got = realloc(got, (size_t)n + 1);
      got[n] = 0;
      ck_assert_ptr_nonnull(strstr((char *)got, "</VTKFile>"));
    }
    free(got);
  }
  /* a reader that goes away after one byte: ND_ERR_IO, and this process is
     not killed by SIGPIPE (a VTU larger than the pipe's buffer) */
  nd_problem big = stepped_strip(60, 15, &block2, &n2);
  const pid_t quitter = fork();
  ck_assert_int_ge(quitter, 0);
  if (quitter == 0) {
    char c;
    const int in = open(fifo, O_RDONLY);
    _exit(in >= 0 && read(in, &c, 1) == 1 ? 0 : 1);
  }
  int st = ND_ERR_IO;
  for (int tries = 0; tries < 2000; ++tries) {
    st = nd_problem_write_vtu(big, fifo);
    if (st != ND_ERR_IO || !strstr(nd_last_error(), "no process reads")) break;
    nanosleep(&(struct timespec){0, 5000000}, NULL);
  }
  ck_assert_msg(st == ND_ERR_IO && strstr(nd_last_error(), fifo), "%d %s", st, nd_last_error());
  free(block2);
  ND_OK_OR_FAIL(nd_problem_destroy(&big));
  int status = 0;
  waitpid(quitter, &status, 0);
  ck_assert(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  /* a checkpoint is read from a FIFO too; one no process writes to is empty:
     a format error at once, not a wait */
  ck_assert_int_eq(nd_problem_load_state_file(p, fifo), ND_ERR_FORMAT);
  const pid_t writer = fork();
  ck_assert_int_ge(writer, 0);
  if (writer == 0) {
    const int out = open(fifo, O_WRONLY);
    _exit(out >= 0 && write(out, block, (size_t)nbytes) == (ssize_t)nbytes ? 0 : 1);
  }
  /* (the writer's open waits for this reader: a load before it gets there
     reads nothing) */
  for (int tries = 0; tries < 2000 && (st = nd_problem_load_state_file(p, fifo)) == ND_ERR_FORMAT; ++tries)
    nanosleep(&(struct timespec){0, 5000000}, NULL);
  ck_assert_msg(st == ND_OK, "%d %s", st, nd_last_error());
  waitpid(writer, &status, 0);
  ck_assert_int_eq(type_of(fifo), S_IFIFO);
  free(block);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  rm_dir(dir);
}
END_TEST

/* A symbolic link stays a link and its target is written (a relative link,
   a chain of two, and a dangling link, whose target is created). The old
   writer replaced the link by a regular file. */
START_TEST(a_symlink_is_followed) {
  char dir[] = "/tmp/nd_test_write_XXXXXX", real[64], link1[64], link2[64], dangling[64], made[64], vtu[64], text[64];
  make_dir(dir);
  snprintf(real, sizeof real, "%s/real.ndck", dir);
  snprintf(link1, sizeof link1, "%s/link1", dir);
  snprintf(link2, sizeof link2, "%s/link2", dir);
  snprintf(dangling, sizeof dangling, "%s/dangling", dir);
  snprintf(made, sizeof made, "%s/made.ndck", dir);
  snprintf(vtu, sizeof vtu, "%s/out.vtu", dir);
  int64_t nbytes = 0;
  unsigned char *block = NULL;
  nd_problem p = stepped(&block, &nbytes);
  FILE *f = fopen(real, "w");
  fputs("old", f);
  fclose(f);
  ck_assert_int_eq(chmod(real, 0640), 0);
  const int root = geteuid() == 0; /* root gives the new file the old one's owner */
  if (root) ck_assert_int_eq(chown(real, 4321, 4322), 0);
  ck_assert_int_eq(symlink("real.ndck", link1), 0);
  ck_assert_int_eq(symlink(link1, link2), 0);
  ck_assert_int_eq(symlink("made.ndck", dangling), 0);
  ND_OK_OR_FAIL(nd_problem_save_state_file(p, link2));
  ck_assert_int_eq(type_of(link1), S_IFLNK);
  ck_assert_int_eq(type_of(link2), S_IFLNK);
  ck_assert_int_eq(type_of(real), S_IFREG);
  ck_assert(holds(real, block, nbytes));
  struct stat st;
  ck_assert_int_eq(stat(real, &st), 0);
  ck_assert_int_eq(st.st_mode & 07777, 0640); /* the target's mode kept */
  if (root) ck_assert(st.st_uid == 4321 && st.st_gid == 4322);
  ck_assert_int_eq((int)readlink(link2, text, sizeof text), (int)strlen(link1));
  ND_OK_OR_FAIL(nd_problem_save_state_file(p, dangling));
  ck_assert_int_eq(type_of(dangling), S_IFLNK);
  ck_assert(holds(made, block, nbytes));
  ND_OK_OR_FAIL(nd_problem_load_state_file(p, link2)); /* and read through it */
  /* the VTU writer too */
  ck_assert_int_eq(unlink(link1), 0);
  ck_assert_int_eq(symlink("out.vtu", link1), 0);
  ND_OK_OR_FAIL(nd_problem_write_vtu(p, link1));
  ck_assert_int_eq(type_of(link1), S_IFLNK);
  ck_assert_int_eq(type_of(vtu), S_IFREG);
  free(block);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  rm_dir(dir);
}
END_TEST

/* A file with two hard links keeps them: both names see the new checkpoint
   (cut to its length, from a longer old text). The old writer split them. */
START_TEST(hard_links_are_kept) {
  char dir[] = "/tmp/nd_test_write_XXXXXX", a[64], b[64];
  make_dir(dir);
  snprintf(a, sizeof a, "%s/a.ndck", dir);
  snprintf(b, sizeof b, "%s/b.ndck", dir);
  int64_t nbytes = 0;
  unsigned char *block = NULL;
  nd_problem p = stepped(&block, &nbytes);
  FILE *f = fopen(a, "w");
  for (int64_t i = 0; i < 2 * nbytes + 100; ++i) fputc('x', f);
  fclose(f);
  ck_assert_int_eq(link(a, b), 0);
  ND_OK_OR_FAIL(nd_problem_save_state_file(p, a));
  struct stat sa, sb;
  ck_assert_int_eq(stat(a, &sa), 0);
  ck_assert_int_eq(stat(b, &sb), 0);
  ck_assert_int_eq((int)sa.st_nlink, 2);
  ck_assert(sa.st_ino == sb.st_ino);
  ck_assert(holds(b, block, nbytes));
  ND_OK_OR_FAIL(nd_problem_load_state_file(p, b));
  ND_OK_OR_FAIL(nd_problem_write_vtu(p, b));
  ck_assert_int_eq(stat(a, &sa), 0);
  ck_assert_int_eq((int)sa.st_nlink, 2);
  free(block);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  rm_dir(dir);
}
END_TEST

/* A character device is written in place. First a twin of /dev/null made
   here (as root: mknod), so that a broken writer replaces only the twin;
   the real /dev/null only after the twin survived, or as another user (who
   cannot replace it). Loading /dev/null is a format error (it is empty), and
   changes nothing. /dev/stdout of a child whose output is a pipe works too.
   Sockets and directories are refused and stay. */
START_TEST(devices_are_written_in_place) {
  char dir[] = "/tmp/nd_test_write_XXXXXX", twin[64], sock[64];
  make_dir(dir);
  snprintf(twin, sizeof twin, "%s/null", dir);
  snprintf(sock, sizeof sock, "%s/sock", dir);
  int64_t nbytes = 0;
  unsigned char *block = NULL;
  nd_problem p = stepped(&block, &nbytes);
  const char *files[1] = {"a.vtu"};
  const double t[1] = {0};
  struct stat st;
  const int real_null = stat("/dev/null", &st) == 0 && S_ISCHR(st.st_mode);
  int trust = geteuid() != 0; /* another user cannot replace /dev/null */
  if (real_null && mknod(twin, S_IFCHR | 0666, st.st_rdev) == 0) {
    ND_OK_OR_FAIL(nd_problem_save_state_file(p, twin));
    ck_assert_int_eq(type_of(twin), S_IFCHR);
    ND_OK_OR_FAIL(nd_problem_write_vtu(p, twin));
    ND_OK_OR_FAIL(nd_write_pvd(twin, 1, files, t));
    ck_assert_int_eq(type_of(twin), S_IFCHR);
    trust = 1;
  }
  if (real_null && trust) {
    ND_OK_OR_FAIL(nd_problem_save_state_file(p, "/dev/null"));
    ND_OK_OR_FAIL(nd_problem_write_vtu(p, "/dev/null"));
    ND_OK_OR_FAIL(nd_write_pvd("/dev/null", 1, files, t));
    ck_assert_int_eq(stat("/dev/null", &st), 0);
    ck_assert(S_ISCHR(st.st_mode));
    ck_assert_int_eq(nd_problem_load_state_file(p, "/dev/null"), ND_ERR_FORMAT);
    ck_assert_int_eq(nd_problem_load_state_file(p, "/dev/zero"), ND_ERR_FORMAT); /* endless: read no further */
    int64_t n = nbytes;
    unsigned char *after = malloc((size_t)n);
    ND_OK_OR_FAIL(nd_problem_save_state(p, n, after));
    ck_assert(memcmp(after, block, (size_t)n) == 0);
    free(after);
  }
  /* /dev/stdout of a child, its output a pipe read here (a symbolic link to
     /proc/self/fd/1, whose text is "pipe:[...]"; also after the twin only) */
  ck_assert(trust);
  int fds[2];
  ck_assert_int_eq(pipe(fds), 0);
  const pid_t pid = fork();
  ck_assert_int_ge(pid, 0);
  if (pid == 0) {
    close(fds[0]);
    dup2(fds[1], 1);
    close(fds[1]);
    _exit(nd_problem_save_state_file(p, "/dev/stdout") == ND_OK ? 0 : 1);
  }
  close(fds[1]);
  unsigned char *got = malloc((size_t)nbytes + 1);
  int64_t n = 0;
  ssize_t k;
  while (n <= nbytes && (k = read(fds[0], got + n, (size_t)(nbytes + 1 - n))) > 0) n += k;
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  ck_assert_msg(WIFEXITED(status) && WEXITSTATUS(status) == 0, "status %d", status);
  ck_assert(n == nbytes && memcmp(got, block, (size_t)n) == 0);
  free(got);
  /* a socket and a directory: refused, left as they were */
  const int s = socket(AF_UNIX, SOCK_STREAM, 0);
  struct sockaddr_un addr = {.sun_family = AF_UNIX};
  snprintf(addr.sun_path, sizeof addr.sun_path, "%s", sock);
  ck_assert_int_eq(bind(s, (struct sockaddr *)&addr, sizeof addr), 0);
  ck_assert_int_eq(nd_problem_save_state_file(p, sock), ND_ERR_IO);
  ck_assert_ptr_nonnull(strstr(nd_last_error(), "socket"));
  ck_assert_int_eq(type_of(sock), S_IFSOCK);
  ck_assert_int_eq(nd_problem_write_vtu(p, dir), ND_ERR_IO);
  ck_assert_int_eq(type_of(dir), S_IFDIR);
  close(s);
  free(block);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  rm_dir(dir);
}
END_TEST

/* File names of up to NAME_MAX (255) bytes are written (the old temporary
   name added 11 bytes), and no temporary is left in the directory. */
START_TEST(long_names_and_no_temporaries) {
  char dir[] = "/tmp/nd_test_write_XXXXXX", path[3][320], expect[1024] = "", got[1024];
  make_dir(dir);
  const char *ext[3] = {".ndck", ".vtu", ".pvd"};
  const int len[3] = {250, 255, 245};
  for (int i = 0; i < 3; ++i) {
    char name[256];
    memset(name, 'a' + i, (size_t)len[i]);
    memcpy(name + len[i] - strlen(ext[i]), ext[i], strlen(ext[i]) + 1);
    snprintf(path[i], sizeof path[i], "%s/%s", dir, name);
    strcat(expect, name);
    strcat(expect, " ");
  }
  int64_t nbytes = 0;
  unsigned char *block = NULL;
  nd_problem p = stepped(&block, &nbytes);
  const char *files[1] = {"a.vtu"};
  const double t[1] = {0};
  for (int again = 0; again < 2; ++again) { /* new files, then replaced ones */
    ND_OK_OR_FAIL(nd_problem_save_state_file(p, path[0]));
    ND_OK_OR_FAIL(nd_problem_write_vtu(p, path[1]));
    ND_OK_OR_FAIL(nd_write_pvd(path[2], 1, files, t));
  }
  ck_assert(holds(path[0], block, nbytes));
  ND_OK_OR_FAIL(nd_problem_load_state_file(p, path[0]));
  listing(dir, got, sizeof got);
  ck_assert_str_eq(got, expect);
  free(block);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  rm_dir(dir);
}
END_TEST

/* A writer killed in the middle of writing (here by SIGXFSZ: its files may
   not exceed 100 bytes) leaves no temporary file, where the file system has
   O_TMPFILE, and the earlier checkpoint whole. */
START_TEST(a_killed_writer_leaves_no_temporary) {
  char dir[] = "/tmp/nd_test_write_XXXXXX", path[64], fresh[64], got[256], expect[64];
  make_dir(dir);
  const int probe = open(dir, O_TMPFILE | O_WRONLY, 0600);
  if (probe < 0) { /* no O_TMPFILE here: a killed writer's ".nd.*.tmp" stays (documented) */
    rm_dir(dir);
    return;
  }
  close(probe);
  snprintf(path, sizeof path, "%s/state.ndck", dir);
  snprintf(fresh, sizeof fresh, "%s/fresh.ndck", dir);
  int64_t nbytes = 0;
  unsigned char *block = NULL;
  nd_problem p = stepped(&block, &nbytes);
  ND_OK_OR_FAIL(nd_problem_save_state_file(p, path));
  for (int which = 0; which < 3; ++which) {
    const pid_t pid = fork();
    ck_assert_int_ge(pid, 0);
    if (pid == 0) {
      const struct rlimit small = {100, 100}, none = {0, 0};
      setrlimit(RLIMIT_CORE, &none);
      signal(SIGXFSZ, SIG_DFL);
      if (setrlimit(RLIMIT_FSIZE, &small) == 0) {
        if (which == 0) nd_problem_save_state_file(p, path);
        if (which == 1) nd_problem_save_state_file(p, fresh);
        if (which == 2) nd_problem_write_vtu(p, path);
      }
      _exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    ck_assert_msg(WIFSIGNALED(status) && WTERMSIG(status) == SIGXFSZ, "status %d", status);
  }
  ck_assert(holds(path, block, nbytes));
  listing(dir, got, sizeof got);
  snprintf(expect, sizeof expect, "state.ndck ");
  ck_assert_str_eq(got, expect);
  free(block);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  rm_dir(dir);
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
  TCase *tw = tcase_create("writing");
  tcase_set_timeout(tw, 60);
  tcase_add_test(tw, a_fifo_is_written_in_place);
  tcase_add_test(tw, a_symlink_is_followed);
  tcase_add_test(tw, hard_links_are_kept);
  tcase_add_test(tw, devices_are_written_in_place);
  tcase_add_test(tw, long_names_and_no_temporaries);
  tcase_add_test(tw, a_killed_writer_leaves_no_temporary);
  suite_add_tcase(s, tw);
  return nd_test_run(s);
}
