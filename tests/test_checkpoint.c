/* Checkpoint and restart (docs/design.md §8): a run resumed from a saved state is
 * bitwise the uninterrupted run, for every scheme, P1/P2, 1D/2D/3D, also
 * across a process boundary; truncated, corrupted, other-version and
 * other-problem checkpoints are refused with their codes and change nothing;
 * an implicitly coupled code can save, step, restore and step again with
 * another load; nd_problem_set_state overwrites U and V at the current time.
 * The file variant (nd_problem_save_state_file) holds the same block, is
 * written atomically and is read with the same checks. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "fixtures/checkpoint_scene.h"
#include "testutil.h"

enum { N_FIELDS = 5, N_SCALARS = ND_WORK_OBSTACLE };

typedef struct {
  int64_t n;
  double *f; /* u, v, a, contact force, reaction per DOF, then the first scalars */
} snap;

static snap take(nd_problem p, int dim) {
  snap s;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &s.n));
  const int64_t len = s.n * dim;
  s.f = malloc(sizeof(double) * (size_t)(N_FIELDS * len + N_SCALARS));
  for (int k = 0; k < N_FIELDS; ++k) ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT + k, s.n, s.f + k * len));
  for (int k = 0; k < N_SCALARS; ++k) ND_OK_OR_FAIL(nd_get_scalar(p, ND_TIME + k, s.f + N_FIELDS * len + k));
  s.n = N_FIELDS * len + N_SCALARS;
  return s;
}

static int same(snap a, snap b) { return a.n == b.n && memcmp(a.f, b.f, sizeof(double) * (size_t)a.n) == 0; }

/* whether two problems' fields and first scalars are bitwise equal now */
static int same_now(nd_problem a, nd_problem b, int dim) {
  snap sa = take(a, dim), sb = take(b, dim);
  const int equal = same(sa, sb);
  free(sa.f);
  free(sb.f);
  return equal;
}

/* a block clamped at x = 0 falling on the plane below it (1D: the bar) */
static nd_problem scene(int dim, int degree, int scheme, const double *params) {
  if (dim == 1) {
    nd_problem p = nd_test_bar(20, degree, scheme, params, 1.0, 0.0, 0.025);
    if (scheme == ND_SCHEME_NEWMARK && params[0] == 0) {
      ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
      ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.25 / 20 / degree));
    }
    return p;
  }
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo[3] = {0, 0.02, 0.02}, hi[3] = {2, 1.02, 1.02}, g[3] = {0, -1, 0}, up[3] = {0, 1, 0}, o[3] = {0, 0, 0};
  const double blo[3] = {-1, -1, -1}, bhi[3] = {3, 0.02, 3};
  if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle(4, 2, lo, hi, &m));
  if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box(2, 1, 1, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 10.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.02));
  if (scheme == ND_SCHEME_NEWMARK && params[0] == 0) {
    ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.002));
  }
  return p;
}

static unsigned char *save(nd_problem p, int64_t *nbytes) {
  ND_OK_OR_FAIL(nd_problem_get_state_size(p, nbytes));
  unsigned char *buf = malloc((size_t)*nbytes);
  ND_OK_OR_FAIL(nd_problem_save_state(p, *nbytes, buf));
  return buf;
}

static const nd_test_scheme *const schemes = nd_test_schemes;
enum { N_SCHEMES = ND_TEST_N_SCHEMES };

/* one step; with `moving`, the obstacle first moves to where it is at step k */
static void step_moving(nd_problem p, int dim, int moving, int k) {
  double o[3] = {0, 0, 0}, nu[3] = {0, 0, 0};
  nu[dim == 1 ? 0 : 1] = 1;
  o[dim == 1 ? 0 : 1] = 0.004 * sin(0.3 * k);
  if (moving) ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, nu));
  ND_OK_OR_FAIL(nd_step(p));
}

/* also with a moving obstacle: its gaps at t^n and its work are in the
   checkpoint (the caller sets the point of the next step, as it sets the
   next load) */
START_TEST(resumed_runs_are_bitwise_the_uninterrupted_ones) {
  for (int dim = 1; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree)
      for (int s = 0; s < N_SCHEMES; ++s)
        for (int moving = 0; moving <= 1; ++moving) {
          const int first = 30, then = 40; /* through the impact */
          for (int at = 0; at <= first; at += first) { /* also a checkpoint at t = 0 */
            nd_problem a = scene(dim, degree, schemes[s].scheme, schemes[s].params);
            for (int k = 0; k < at; ++k) step_moving(a, dim, moving, k + 1);
            int64_t nbytes = 0;
            unsigned char *buf = save(a, &nbytes);
            for (int k = at; k < at + then; ++k) step_moving(a, dim, moving, k + 1);
            nd_problem b = scene(dim, degree, schemes[s].scheme, schemes[s].params);
            ND_OK_OR_FAIL(nd_problem_load_state(b, nbytes, buf));
            for (int k = at; k < at + then; ++k) step_moving(b, dim, moving, k + 1);
            ck_assert_msg(same_now(a, b, dim), "%dD P%d scheme %d from step %d%s: the resumed run differs", dim, degree,
                          schemes[s].scheme, at, moving ? " (moving obstacle)" : "");
            double wo = 0;
            ND_OK_OR_FAIL(nd_get_scalar(b, ND_WORK_OBSTACLE, &wo));
            const int expl = nd_test_is_explicit(&schemes[s]);
            if (moving && at > 0 && !expl) /* (the explicit run may end before the impact) */
              ck_assert_msg(wo != 0, "%dD P%d scheme %d: the obstacle did no work", dim, degree, schemes[s].scheme);
            free(buf);
            ND_OK_OR_FAIL(nd_problem_destroy(&a));
            ND_OK_OR_FAIL(nd_problem_destroy(&b));
          }
        }
}
END_TEST

/* nd_problem_get_state_size is fixed for a problem: at t = 0 (no load, no
   reaction, no applied contact term yet) as after steps in contact with a
   load and a moving obstacle, so that a caller allocates the buffer once */
START_TEST(checkpoint_size_is_fixed) {
  for (int dim = 1; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree) {
      nd_problem p = scene(dim, degree, schemes[0].scheme, schemes[0].params);
      int64_t before = 0, after = 0, at_max = 0;
      ND_OK_OR_FAIL(nd_problem_get_state_size(p, &before));
      for (int k = 0; k < 40; ++k) step_moving(p, dim, 1, k + 1);
      ND_OK_OR_FAIL(nd_problem_get_state_size(p, &after));
      ck_assert_msg(before == after, "%dD P%d: %lld bytes at t = 0, %lld after 40 steps", dim, degree,
                    (long long)before, (long long)after);
      unsigned char *buf = save(p, &at_max);
      ck_assert_int_eq(at_max, before);
      free(buf);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

/* the checkpoint crosses a process boundary: a child process runs the first
   part and writes the bytes to a file, this process resumes from them */
START_TEST(resumes_in_another_process) {
  const double nm[2] = {0.25, 0.5};
  char path[] = "/tmp/nd_checkpoint_XXXXXX";
  const int fd = mkstemp(path);
  ck_assert_int_ge(fd, 0);
  close(fd);
  const pid_t pid = fork();
  ck_assert_int_ge(pid, 0);
  if (pid == 0) {
    nd_problem p = scene(2, 2, ND_SCHEME_NEWMARK, nm);
    for (int k = 0; k < 25; ++k)
      if (nd_step(p) != ND_OK) _exit(1);
    int64_t nbytes = 0;
    if (nd_problem_get_state_size(p, &nbytes) != ND_OK) _exit(1);
    unsigned char *buf = malloc((size_t)nbytes);
    FILE *f = fopen(path, "wb");
    const int ok = f && nd_problem_save_state(p, nbytes, buf) == ND_OK &&
                   fwrite(buf, 1, (size_t)nbytes, f) == (size_t)nbytes;
    if (f) fclose(f);
    free(buf); /* the child is checked for leaks too (valgrind follows the fork) */
    nd_problem_destroy(&p);
    _exit(ok ? 0 : 1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ck_assert(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  FILE *f = fopen(path, "rb");
  ck_assert_ptr_nonnull(f);
  unsigned char buf[1 << 16];
  const size_t nbytes = fread(buf, 1, sizeof buf, f);
  fclose(f);
  unlink(path);
  nd_problem a = scene(2, 2, ND_SCHEME_NEWMARK, nm), b = scene(2, 2, ND_SCHEME_NEWMARK, nm);
  for (int k = 0; k < 50; ++k) ND_OK_OR_FAIL(nd_step(a));
  ND_OK_OR_FAIL(nd_problem_load_state(b, (int64_t)nbytes, buf));
  for (int k = 0; k < 25; ++k) ND_OK_OR_FAIL(nd_step(b));
  ck_assert(same_now(a, b, 2));
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
}
END_TEST

START_TEST(bad_checkpoints_are_refused_and_change_nothing) {
  const double nm[2] = {0.25, 0.5};
  nd_problem p = scene(2, 1, ND_SCHEME_NEWMARK, nm);
  for (int k = 0; k < 10; ++k) ND_OK_OR_FAIL(nd_step(p));
  int64_t nbytes = 0;
  unsigned char *good = save(p, &nbytes), *bad = malloc((size_t)nbytes);
  for (int k = 0; k < 5; ++k) ND_OK_OR_FAIL(nd_step(p));
  snap before = take(p, 2);
  /* truncated: every shorter length */
  for (int64_t len = 1; len < nbytes; len += 7) {
    const int st = nd_problem_load_state(p, len, good);
    ck_assert_msg(st == ND_ERR_FORMAT, "length %lld: %d", (long long)len, st);
  }
  /* corrupted: one flipped bit anywhere (the version field is reported as such) */
  for (int64_t i = 0; i < nbytes; i += 5) {
    memcpy(bad, good, (size_t)nbytes);
    bad[i] ^= 0x10;
    ck_assert_int_eq(nd_problem_load_state(p, nbytes, bad), ND_ERR_FORMAT);
  }
  memcpy(bad, good, (size_t)nbytes);
  bad[8] = 99; /* version 99 */
  ck_assert_int_eq(nd_problem_load_state(p, nbytes, bad), ND_ERR_FORMAT);
  ck_assert_ptr_nonnull(strstr(nd_last_error(), "version 99"));
  ck_assert_int_eq(nd_problem_load_state(p, nbytes + 1, good), ND_ERR_FORMAT);
  ck_assert_int_eq(nd_problem_load_state(p, 0, good), ND_ERR_SIZE);
  ck_assert_int_eq(nd_problem_load_state(p, nbytes, NULL), ND_ERR_NULL);
  ck_assert_int_eq(nd_problem_save_state(p, nbytes - 1, bad), ND_ERR_SIZE);
  /* another problem: P2 on the same mesh, and the bar */
  nd_problem q = scene(2, 2, ND_SCHEME_NEWMARK, nm), r = scene(1, 1, ND_SCHEME_NEWMARK, nm);
  ck_assert_int_eq(nd_problem_load_state(q, nbytes, good), ND_ERR_STATE);
  ck_assert_int_eq(nd_problem_load_state(r, nbytes, good), ND_ERR_STATE);
  printf("%s\n", nd_last_error());
  snap after = take(p, 2);
  ck_assert(same(before, after));
  /* and the good one still loads */
  ND_OK_OR_FAIL(nd_problem_load_state(p, nbytes, good));
  free(before.f);
  free(after.f);
  free(good);
  free(bad);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
  ND_OK_OR_FAIL(nd_problem_destroy(&r));
}
END_TEST

/* implicit coupling (the preCICE pattern): save, step with a first guess of
   the load, restore, step with the converged load: the result is that of a
   run that only ever saw the converged load. The first checkpoint holds the
   state at t^0 with its load F^0 = 0, which the other run fixes by setting
   up before its first load. */
START_TEST(coupling_iteration_restores_and_retries) {
  const double nm[2] = {0.25, 0.5};
  for (int s = 0; s < N_SCHEMES; ++s) {
    if (schemes[s].scheme == ND_SCHEME_NEWMARK && schemes[s].params[0] == 0) continue;
    (void)nm;
    nd_problem a = scene(2, 1, schemes[s].scheme, schemes[s].params);
    nd_problem b = scene(2, 1, schemes[s].scheme, schemes[s].params);
    ND_OK_OR_FAIL(nd_problem_setup(b));
    int64_t n = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(a, &n));
    double *guess = calloc((size_t)(2 * n), sizeof(double)), *load = calloc((size_t)(2 * n), sizeof(double));
    for (int k = 0; k < 20; ++k) {
      for (int64_t i = 0; i < n; ++i) guess[2 * i] = 0.1 * sin(k + i), load[2 * i] = 0.1 * cos(k + i);
      int64_t nbytes = 0;
      unsigned char *buf = save(a, &nbytes);
      ND_OK_OR_FAIL(nd_problem_set_nodal_forces(a, n, guess));
      ND_OK_OR_FAIL(nd_step(a));
      ND_OK_OR_FAIL(nd_problem_load_state(a, nbytes, buf));
      ND_OK_OR_FAIL(nd_problem_set_nodal_forces(a, n, load));
      ND_OK_OR_FAIL(nd_step(a));
      ND_OK_OR_FAIL(nd_problem_set_nodal_forces(b, n, load));
      ND_OK_OR_FAIL(nd_step(b));
      free(buf);
    }
    ck_assert_msg(same_now(a, b, 2), "scheme %d: the retried run differs", schemes[s].scheme);
    free(guess);
    free(load);
    ND_OK_OR_FAIL(nd_problem_destroy(&a));
    ND_OK_OR_FAIL(nd_problem_destroy(&b));
  }
}
END_TEST

/* nd_problem_set_state: U, V replaced at t^n; t, n and W kept; A re-derived
   from the equilibrium exactly as at t^0 */
START_TEST(set_state_keeps_time_and_work) {
  const double nm[2] = {0.25, 0.5};
  nd_problem p = scene(2, 2, ND_SCHEME_NEWMARK, nm), q = scene(2, 2, ND_SCHEME_NEWMARK, nm);
  for (int k = 0; k < 30; ++k) ND_OK_OR_FAIL(nd_step(p));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *u = malloc(sizeof(double) * (size_t)(2 * n)), *v = malloc(sizeof(double) * (size_t)(2 * n));
  double *a1 = malloc(sizeof(double) * (size_t)(2 * n)), *a2 = malloc(sizeof(double) * (size_t)(2 * n));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, n, v));
  for (int64_t i = 0; i < 2 * n; ++i) u[i] *= 0.9, v[i] *= 1.1;
  double t0, n0, w0, t1, n1, w1;
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_TIME, &t0));
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_STEP_INDEX, &n0));
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_WORK, &w0));
  ND_OK_OR_FAIL(nd_problem_set_state(p, n, u, v));
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_TIME, &t1));
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_STEP_INDEX, &n1));
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_WORK, &w1));
  ck_assert(t0 == t1 && n0 == n1 && w0 == w1);
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, n, a1));
  ND_OK_OR_FAIL(nd_problem_set_initial_state(q, n, u, v));
  ND_OK_OR_FAIL(nd_problem_setup(q));
  ND_OK_OR_FAIL(nd_get_field(q, ND_FIELD_ACCELERATION, n, a2));
  ck_assert(memcmp(a1, a2, sizeof(double) * (size_t)(2 * n)) == 0);
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, n, a1));
  for (int64_t i = 0; i < 2 * n; ++i)
    if (a1[i] != 0) ck_assert(a1[i] == v[i]); /* clamped DOFs read 0 */
  ND_OK_OR_FAIL(nd_step(p));
  free(u);
  free(v);
  free(a1);
  free(a2);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
}
END_TEST

/* a fresh directory for the file tests; removed with its files by rm_dir */
static void make_dir(char *dir) { ck_assert_ptr_nonnull(mkdtemp(dir)); }
static void rm_dir(const char *dir) {
  char cmd[256];
  snprintf(cmd, sizeof cmd, "chmod -R u+w '%s' && rm -rf '%s'", dir, dir);
  ck_assert_int_eq(system(cmd), 0);
}
static unsigned char *slurp(const char *path, int64_t *nbytes) {
  FILE *f = fopen(path, "rb");
  ck_assert_ptr_nonnull(f);
  fseek(f, 0, SEEK_END);
  *nbytes = ftell(f);
  rewind(f);
  unsigned char *buf = malloc((size_t)*nbytes + 1);
  ck_assert_uint_eq(fread(buf, 1, (size_t)*nbytes, f), (size_t)*nbytes);
  fclose(f);
  return buf;
}
static void spit(const char *path, const unsigned char *buf, int64_t nbytes) {
  FILE *f = fopen(path, "wb");
  ck_assert_ptr_nonnull(f);
  ck_assert_uint_eq(fwrite(buf, 1, (size_t)nbytes, f), (size_t)nbytes);
  fclose(f);
}

/* the file holds exactly the buffer's block, and a run resumed from it is
   bitwise the uninterrupted one (P1/P2, 2D/3D, implicit and explicit) */
START_TEST(resumes_from_a_file) {
  char dir[] = "/tmp/nd_ckfile_XXXXXX", path[64];
  make_dir(dir);
  snprintf(path, sizeof path, "%s/state.ndck", dir);
  const int picks[3] = {0, 2, 4}; /* theta = 1/2, Newmark(1/4, 1/2), hybrid: see testutil.c */
  for (int dim = 2; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree)
      for (int i = 0; i < 3; ++i) {
        const nd_test_scheme *sc = &schemes[picks[i]];
        nd_problem a = scene(dim, degree, sc->scheme, sc->params), b = scene(dim, degree, sc->scheme, sc->params);
        for (int k = 0; k < 20; ++k) ND_OK_OR_FAIL(nd_step(a));
        ND_OK_OR_FAIL(nd_problem_save_state_file(a, path));
        int64_t nbytes = 0, nfile = 0;
        unsigned char *buf = save(a, &nbytes), *file = slurp(path, &nfile);
        ck_assert(nbytes == nfile && memcmp(buf, file, (size_t)nbytes) == 0);
        for (int k = 0; k < 20; ++k) ND_OK_OR_FAIL(nd_step(a));
        ND_OK_OR_FAIL(nd_problem_load_state_file(b, path));
        for (int k = 0; k < 20; ++k) ND_OK_OR_FAIL(nd_step(b));
        ck_assert_msg(same_now(a, b, dim), "%dD P%d scheme %d: the run resumed from a file differs", dim, degree,
                      sc->scheme);
        free(buf);
        free(file);
        ND_OK_OR_FAIL(nd_problem_destroy(&a));
        ND_OK_OR_FAIL(nd_problem_destroy(&b));
      }
  rm_dir(dir);
}
END_TEST

/* a child process writes the checkpoint file, this one resumes from it */
START_TEST(resumes_from_a_file_in_another_process) {
  const double nm[2] = {0.25, 0.5};
  char dir[] = "/tmp/nd_ckfile_XXXXXX", path[64];
  make_dir(dir);
  snprintf(path, sizeof path, "%s/state.ndck", dir);
  const pid_t pid = fork();
  ck_assert_int_ge(pid, 0);
  if (pid == 0) {
    nd_problem p = scene(3, 2, ND_SCHEME_NEWMARK, nm);
    int ok = 1;
    for (int k = 0; k < 25 && ok; ++k) ok = nd_step(p) == ND_OK;
    ok = ok && nd_problem_save_state_file(p, path) == ND_OK;
    nd_problem_destroy(&p);
    _exit(ok ? 0 : 1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ck_assert(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  nd_problem a = scene(3, 2, ND_SCHEME_NEWMARK, nm), b = scene(3, 2, ND_SCHEME_NEWMARK, nm);
  for (int k = 0; k < 50; ++k) ND_OK_OR_FAIL(nd_step(a));
  ND_OK_OR_FAIL(nd_problem_load_state_file(b, path));
  for (int k = 0; k < 25; ++k) ND_OK_OR_FAIL(nd_step(b));
  ck_assert(same_now(a, b, 3));
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
  rm_dir(dir);
}
END_TEST

/* every refusal of the file path has the buffer path's code and changes
   nothing; a failed save keeps the earlier file and leaves no temporary */
START_TEST(bad_checkpoint_files_are_refused_and_change_nothing) {
  const double nm[2] = {0.25, 0.5};
  char dir[] = "/tmp/nd_ckfile_XXXXXX", path[64], bad[64], sub[64], inner[80];
  make_dir(dir);
  snprintf(path, sizeof path, "%s/good.ndck", dir);
  snprintf(bad, sizeof bad, "%s/bad.ndck", dir);
  nd_problem p = scene(2, 1, ND_SCHEME_NEWMARK, nm);
  for (int k = 0; k < 10; ++k) ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_problem_save_state_file(p, path));
  int64_t nbytes = 0;
  unsigned char *good = slurp(path, &nbytes), *b = malloc((size_t)nbytes + 64);
  for (int k = 0; k < 5; ++k) ND_OK_OR_FAIL(nd_step(p));
  snap before = take(p, 2);
  snprintf(inner, sizeof inner, "%s/missing.ndck", dir);
  ck_assert_int_eq(nd_problem_load_state_file(p, inner), ND_ERR_IO);
  ck_assert_ptr_nonnull(strstr(nd_last_error(), "missing.ndck"));
  ck_assert_int_eq(nd_problem_load_state_file(p, dir), ND_ERR_IO); /* a directory */
  ck_assert_int_eq(nd_problem_load_state_file(p, NULL), ND_ERR_NULL);
  ck_assert_int_eq(nd_problem_save_state_file(p, NULL), ND_ERR_NULL);
  spit(bad, good, 0);
  ck_assert_int_eq(nd_problem_load_state_file(p, bad), ND_ERR_FORMAT); /* empty */
  for (int64_t len = 1; len < nbytes; len += 11) {                    /* truncated */
    spit(bad, good, len);
    ck_assert_int_eq(nd_problem_load_state_file(p, bad), ND_ERR_FORMAT);
  }
  for (int64_t i = 0; i < nbytes; i += 13) { /* corrupted */
    memcpy(b, good, (size_t)nbytes);
    b[i] ^= 0x04;
    spit(bad, b, nbytes);
    ck_assert_int_eq(nd_problem_load_state_file(p, bad), ND_ERR_FORMAT);
  }
  memcpy(b, good, (size_t)nbytes);
  b[8] = 99; /* version 99 */
  spit(bad, b, nbytes);
  ck_assert_int_eq(nd_problem_load_state_file(p, bad), ND_ERR_FORMAT);
  ck_assert_ptr_nonnull(strstr(nd_last_error(), "version 99"));
  memcpy(b, good, (size_t)nbytes); /* trailing bytes: larger than any checkpoint of p */
  memset(b + nbytes, 0, 64);
  spit(bad, b, nbytes + 64);
  ck_assert_int_eq(nd_problem_load_state_file(p, bad), ND_ERR_FORMAT);
  /* another problem: P2 (a larger block, refused from its header) and the bar */
  nd_problem q = scene(2, 2, ND_SCHEME_NEWMARK, nm), r = scene(1, 1, ND_SCHEME_NEWMARK, nm);
  ck_assert_int_eq(nd_problem_load_state_file(q, path), ND_ERR_STATE);
  ck_assert_int_eq(nd_problem_load_state_file(r, path), ND_ERR_STATE);
  snprintf(inner, sizeof inner, "%s/p2.ndck", dir);
  ND_OK_OR_FAIL(nd_problem_save_state_file(q, inner));
  ck_assert_int_eq(nd_problem_load_state_file(p, inner), ND_ERR_STATE);
  /* an unwritable directory: ND_ERR_IO, the earlier file kept, no temporary left */
  snprintf(sub, sizeof sub, "%s/ro", dir);
  ck_assert_int_eq(mkdir(sub, 0700), 0);
  snprintf(inner, sizeof inner, "%s/state.ndck", sub);
  spit(inner, good, nbytes);
  ck_assert_int_eq(chmod(sub, 0500), 0);
  if (access(sub, W_OK) != 0) { /* (root writes anyway) */
    ck_assert_int_eq(nd_problem_save_state_file(p, inner), ND_ERR_IO);
    int64_t n2 = 0;
    unsigned char *kept = slurp(inner, &n2);
    ck_assert(n2 == nbytes && memcmp(kept, good, (size_t)nbytes) == 0);
    free(kept);
  }
  ck_assert_int_eq(chmod(sub, 0700), 0);
  /* a full disk (also as root): a child whose files may not exceed 100 bytes
     fails to write the temporary file; the earlier file is kept */
  const pid_t pid = fork();
  ck_assert_int_ge(pid, 0);
  if (pid == 0) {
    /* the child's output goes to /dev/null: when stdout/stderr are a regular
       file (valgrind's log under make check-valgrind), the size limit would
       hit them too */
    const int devnull = open("/dev/null", O_WRONLY);
    if (devnull >= 0) dup2(devnull, 1), dup2(devnull, 2);
    const struct rlimit small = {100, 100};
    signal(SIGXFSZ, SIG_IGN);
    const int st = setrlimit(RLIMIT_FSIZE, &small) == 0 ? nd_problem_save_state_file(p, inner) : 0;
    /* the child frees its copy of what the test holds (valgrind follows the fork) */
    free(before.f), free(good), free(b);
    nd_problem_destroy(&p), nd_problem_destroy(&q), nd_problem_destroy(&r);
    _exit(st == ND_ERR_IO ? 0 : 1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ck_assert_msg(WIFEXITED(status) && WEXITSTATUS(status) == 0, "the child ended with status %d", status);
  {
    int64_t n2 = 0;
    unsigned char *kept = slurp(inner, &n2);
    ck_assert(n2 == nbytes && memcmp(kept, good, (size_t)nbytes) == 0);
    free(kept);
  }
  /* a directory in the way: the rename fails, the directory stays */
  ck_assert_int_eq(nd_problem_save_state_file(p, sub), ND_ERR_IO);
  snprintf(inner, sizeof inner, "%s/no/such/dir/state.ndck", dir);
  ck_assert_int_eq(nd_problem_save_state_file(p, inner), ND_ERR_IO);
  snap after = take(p, 2);
  ck_assert(same(before, after));
  ND_OK_OR_FAIL(nd_problem_load_state_file(p, path)); /* and the good one still loads */
  /* only the files this test wrote are in the directory: no temporary left */
  char cmd[160];
  snprintf(cmd, sizeof cmd, "test $(ls -A '%s' | wc -l) -eq 4 && test $(ls -A '%s' | wc -l) -eq 1", dir, sub);
  ck_assert_int_eq(system(cmd), 0);
  free(before.f);
  free(after.f);
  free(good);
  free(b);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
  ND_OK_OR_FAIL(nd_problem_destroy(&r));
  rm_dir(dir);
}
END_TEST

/* max |a - b| / max |b| over a snapshot */
static double snap_diff(snap a, snap b) {
  double d = 0, m = 0;
  for (int64_t i = 0; i < a.n && i < b.n; ++i) {
    d = fmax(d, fabs(a.f[i] - b.f[i]));
    m = fmax(m, fabs(b.f[i]));
  }
  return a.n == b.n ? d / fmax(m, 1e-300) : INFINITY;
}

/* A checkpoint of version 4 (tests/fixtures/checkpoint_v4.ndck, written by
   tests/fixtures/write_checkpoint.c against the library at commit 991f709)
   is still read: its state is the state this library reaches in as many
   steps, and the run resumed from it follows this library's run. Bounded,
   not required bitwise: the updated factor's choices between updating and
   refactoring changed with version 5, and where they differ the factors
   differ by round-off (on this box they coincide: measured 0 and 0). */
START_TEST(reads_version_4_checkpoints) {
  int64_t nbytes = 0, now = 0;
  unsigned char *buf = slurp(ND_FIXTURE_DIR "/checkpoint_v4.ndck", &nbytes);
  ck_assert_int_eq(buf[8], 4); /* the version field, little-endian */
  nd_problem a = NULL, b = NULL;
  ND_OK_OR_FAIL(checkpoint_scene(&a));
  ND_OK_OR_FAIL(checkpoint_scene(&b));
  for (int k = 0; k < CHECKPOINT_SCENE_STEPS; ++k) ND_OK_OR_FAIL(nd_step(a));
  ND_OK_OR_FAIL(nd_problem_load_state(b, nbytes, buf));
  ND_OK_OR_FAIL(nd_problem_get_state_size(b, &now));
  ck_assert_int_gt(now, nbytes); /* version 5's room for the history is larger here */
  double force = 0;
  ND_OK_OR_FAIL(nd_get_scalar(b, ND_CONTACT_FORCE, &force));
  ck_assert_msg(force > 0, "the fixture is not in contact");
  /* The fixture's library solved every step with Newton from the
     predictor's tangent; this one took the box's rigid fall before the
     impact as its predictor (nd_step(3)) and may keep the last step's
     tangent for a contact step's first iteration (ND_STAT_LAGGED_STEPS):
     the totals of Newton iterations differ by those, and are checked apart.
     The fixture's: at least one per step, and counted on from there. */
  double predicted = 0;
  ND_OK_OR_FAIL(nd_get_scalar(a, ND_STAT_PREDICTED_STEPS, &predicted));
  ck_assert_double_gt(predicted, 0);
  const int total = N_SCALARS - (ND_NEWTON_ITERATIONS_TOTAL - ND_TIME); /* its place from a snapshot's end */
  snap sa = take(a, 3), sb = take(b, 3);
  double total_b = sb.f[sb.n - total];
  ck_assert_double_ge(total_b, CHECKPOINT_SCENE_STEPS);
  sa.f[sa.n - total] = sb.f[sb.n - total] = 0;
  ck_assert_msg(snap_diff(sb, sa) <= 1e-12, "restored from version 4: %g", snap_diff(sb, sa));
  free(sa.f);
  free(sb.f);
  for (int k = 0; k < 20; ++k) {
    ND_OK_OR_FAIL(nd_step(a));
    ND_OK_OR_FAIL(nd_step(b));
    double it = 0;
    ND_OK_OR_FAIL(nd_get_scalar(b, ND_NEWTON_ITERATIONS, &it));
    total_b += it;
  }
  sa = take(a, 3), sb = take(b, 3);
  ck_assert_double_eq(sb.f[sb.n - total], total_b);
  sa.f[sa.n - total] = sb.f[sb.n - total] = 0;
  ck_assert_msg(snap_diff(sb, sa) <= 1e-10, "20 steps after: %g", snap_diff(sb, sa));
  free(sa.f);
  free(sb.f);
  free(buf);
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
}
END_TEST

/* ---- every field's meaning (version 9) ----------------------------------- */

/* FNV-1a, the library's checksum: a test that changes a field reseals the
   block, as anyone can, so that the field's own check is what refuses it */
static uint64_t fnv1a(const unsigned char *p, size_t n) {
  uint64_t h = 1469598103934665603ull;
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}
static void reseal(unsigned char *buf, int64_t nbytes) {
  const uint64_t h = fnv1a(buf, (size_t)nbytes - 8);
  memcpy(buf + nbytes - 8, &h, 8);
}
static void put_double(unsigned char *buf, int64_t at, double x) { memcpy(buf + at, &x, 8); }
static void put_i64(unsigned char *buf, int64_t at, int64_t x) { memcpy(buf + at, &x, 8); }
static double get_double(const unsigned char *buf, int64_t at) {
  double x;
  memcpy(&x, buf + at, 8);
  return x;
}
static int64_t get_i64(const unsigned char *buf, int64_t at) {
  int64_t x;
  memcpy(&x, buf + at, 8);
  return x;
}

/* buf (n bytes) without its `len` bytes at `at`, as a block of `version`:
   an older layout, its payload's size and checksum made right (*n_out bytes) */
static unsigned char *older_block(const unsigned char *buf, int64_t n, int64_t at, int64_t len, int version,
                                  int64_t *n_out) {
  *n_out = n - len;
  unsigned char *out = malloc((size_t)*n_out);
  memcpy(out, buf, (size_t)at);
  memcpy(out + at, buf + at + len, (size_t)(n - at - len));
  out[8] = (unsigned char)version;
  put_i64(out, 24, get_i64(buf, 24) - len); /* the payload's size */
  reseal(out, *n_out);
  return out;
}

/* version 11's tail before the checksum: the energy-balance guard's
   balance, lowest balance, E_top, exchange (8 bytes each) and its
   in-contact byte; without adaptive steps nothing follows it */
enum { kGuardTail = 4 * 8 + 1 };
/* buf as version 10 (no guard tail) */
static unsigned char *as_version_10(const unsigned char *buf, int64_t n, int64_t *n_out);

static unsigned char *as_version_10(const unsigned char *buf, int64_t n, int64_t *n_out) {
  return older_block(buf, n, n - 8 - kGuardTail, kGuardTail, 10, n_out);
}

/* the offsets of a version 9 block's fields (src/problem/checkpoint.cpp):
   header 32 bytes, the definition's 7 fingerprints, then the state */
typedef struct {
  int64_t t, n, t_ref, tau_ref, n_ref, U, V, A, F, A_valid, W, last, total, E0, budget, F_fixed, gap, W_obstacle,
      D_damping, curved, reaction, phi, log_i;
} layout;
static layout layout_of(int64_t nf, int64_t nc, int64_t np) {
  layout l;
  l.t = 32 + 7 * 8;
  l.n = l.t + 8, l.t_ref = l.n + 8, l.tau_ref = l.t_ref + 8, l.n_ref = l.tau_ref + 8;
  l.U = l.n_ref + 8; /* each vector: its count, then its values (or its room) */
  l.V = l.U + 8 + 8 * nf, l.A = l.V + 8 + 8 * nf, l.F = l.A + 8 + 8 * nf;
  l.A_valid = l.F + 8 + 8 * nf;
  l.W = l.A_valid + 1, l.last = l.W + 8, l.total = l.last + 8, l.E0 = l.total + 8, l.budget = l.E0 + 8;
  l.F_fixed = l.budget + 8, l.gap = l.F_fixed + 8 + 8 * nc, l.W_obstacle = l.gap + 8 + 8 * np;
  l.D_damping = l.W_obstacle + 8, l.curved = l.D_damping + 8; /* (version 8) */
  l.reaction = l.curved + 1, l.phi = l.reaction + 8 + 8 * nc, l.log_i = l.phi + 8 + 8 * np;
  return l;
}

/* a refused load changes nothing: the state saved after it is bitwise the one before */
static void refused_unchanged(nd_problem p, int64_t nbytes, const unsigned char *buf, int code, const char *word,
                              const char *what) {
  int64_t n0 = 0, n1 = 0;
  unsigned char *before = save(p, &n0);
  const int st = nd_problem_load_state(p, nbytes, buf);
  ck_assert_msg(st == code, "%s: status %d, expected %d (%s)", what, st, code, nd_last_error());
  ck_assert_msg(strstr(nd_last_error(), word) != NULL, "%s: the message '%s' does not name '%s'", what,
                nd_last_error(), word);
  unsigned char *after = save(p, &n1);
  ck_assert_msg(n0 == n1 && memcmp(before, after, (size_t)n0) == 0, "%s: the refused load changed the state", what);
  free(before);
  free(after);
}

/* loads of a negative step count, a NaN time, a NaN displacement, a NaN
   energy-guard reference, ... returned ND_OK: each field is checked for
   its meaning, with a message naming it, even with a valid checksum */
START_TEST(fields_out_of_range_are_refused) {
  const double nm[2] = {0.25, 0.5};
  nd_problem p = scene(1, 1, ND_SCHEME_NEWMARK, nm); /* the bar: clamped, in contact */
  const double f[1] = {0.01};
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, f)); /* (a load, for its field) */
  for (int k = 0; k < 30; ++k) ND_OK_OR_FAIL(nd_step(p));
  int64_t nbytes = 0, nodes = 0, np = 0;
  unsigned char *good = save(p, &nbytes), *bad = malloc((size_t)nbytes);
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  ND_OK_OR_FAIL(nd_problem_get_contact_point_count(p, &np));
  ck_assert_int_eq(good[8], 12); /* the version */
  const int64_t nf = get_i64(good, layout_of(0, 0, 0).U), nc = nodes - nf;
  const layout l = layout_of(nf, nc, np);
  ck_assert_int_eq(get_i64(good, l.n), 30);
  ck_assert(nc > 0 && np > 0);
  /* the layout is the library's, and every optional field is there */
  ck_assert_int_eq(get_i64(good, l.F), nf);
  ck_assert_int_eq(get_i64(good, l.F_fixed), nc);
  ck_assert_int_eq(get_i64(good, l.gap), np);
  ck_assert_int_eq(get_i64(good, l.reaction), nc);
  ck_assert_int_eq(get_i64(good, l.phi), np);
  /* version 8's tail: the clamped DOFs' U, V, A (empty: no prescribed
     motion, in their room) and W_prescribed, then the checksum; no section
     flagged (no curved obstacle, no friction) */
  const int64_t guard = nbytes - 8 - kGuardTail, W_prescribed = guard - 8, Ac = W_prescribed - 8 - 8 * nc, Vc = Ac - 8 - 8 * nc,
                Uc = Vc - 8 - 8 * nc;
  ck_assert_int_eq(get_i64(good, Uc), 0);
  ck_assert_int_eq(get_i64(good, Ac), 0);
  ck_assert_int_eq(good[l.curved], 0);
  for (int k = 0; k < 3; ++k) ND_OK_OR_FAIL(nd_step(p));
  const double nan = NAN, inf = INFINITY;
  struct {
    int64_t at;
    int kind; /* 0: double, 1: int64, 2: byte */
    double value;
    const char *word;
  } cases[] = {
      {l.n, 1, -1, "step count"},
      {l.t, 0, nan, "time"},
      {l.t, 0, inf, "time"},
      {l.t, 0, 123.0, "t_ref + (n - n_ref) tau_ref"},
      {l.t_ref, 0, nan, "t_ref"},
      {l.tau_ref, 0, nan, "tau_ref"},
      {l.tau_ref, 0, -0.02, "tau_ref"},
      {l.tau_ref, 0, 0, "tau_ref"},
      {l.n_ref, 1, -1, "n_ref"},
      {l.n_ref, 1, 31, "n_ref"},
      {l.U + 8, 0, nan, "displacement"},
      {l.U + 8 + 8 * (nf - 1), 0, -inf, "displacement"},
      {l.V + 8 + 8, 0, nan, "velocity"},
      {l.A + 8, 0, inf, "acceleration"},
      {l.F + 8 + 8, 0, nan, "load"},
      {l.A_valid, 2, 2, "acceleration flag"},
      {l.W, 0, nan, "work of the loads"},
      {l.last, 1, -1, "Newton iteration count"},
      {l.last, 1, 1ll << 40, "Newton iteration count"},
      {l.total, 1, -3, "total of Newton"},
      {l.E0, 0, nan, "E0"}, /* NaN silently turned the energy guard off */
      {l.budget, 0, nan, "budget"},
      {l.budget, 0, -1e30, "below its initial energy"},
      {l.F_fixed + 8, 0, nan, "load on the clamped DOFs"},
      {l.gap + 8, 0, nan, "obstacle gaps"},
      {l.W_obstacle, 0, inf, "work of the obstacle"},
      {l.D_damping, 0, nan, "dissipation of the damping"},
      {l.curved, 2, 16, "section flags"}, /* (1, 2, 4 and 8 name sections) */
      {l.reaction + 8, 0, nan, "reactions"},
      {l.phi + 8, 0, nan, "applied contact term"},
      {l.log_i, 1, 1, "tangent history"}, /* one index: nb = 0 points ... */
      {12, 1, 7, "reserved"},               /* (the header's reserved word and the fingerprint's first half) */
      {Uc, 1, (double)nc, "some of U, V, A only"}, /* (U_c's zeros there, V_c and A_c empty) */
      {W_prescribed, 0, nan, "W_prescribed"},
      {guard, 0, inf, "energy balance"}, /* (NaN: not evaluated yet, a valid value) */
      {guard + 16, 0, nan, "largest mechanical energy"},
      {guard + 24, 0, inf, "contact exchange"},
      {guard + 32, 2, 2, "in-contact flag"},
  };
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    memcpy(bad, good, (size_t)nbytes);
    if (cases[c].kind == 0) put_double(bad, cases[c].at, cases[c].value);
    if (cases[c].kind == 1) put_i64(bad, cases[c].at, (int64_t)cases[c].value);
    if (cases[c].kind == 2) bad[cases[c].at] = (unsigned char)cases[c].value;
    if (cases[c].at == l.log_i) put_i64(bad, l.log_i + 8, np + 5); /* ... but naming a point past the last */
    if (cases[c].at == 12) put_i64(bad, 8, 9 | (7ll << 32));        /* (version 9 kept) */
    reseal(bad, nbytes);
    char what[64];
    snprintf(what, sizeof what, "case %zu (%s)", c, cases[c].word);
    refused_unchanged(p, nbytes, bad, ND_ERR_FORMAT, cases[c].word, what);
  }
  /* padding (the room of a shorter field) that is not zero */
  memcpy(bad, good, (size_t)nbytes);
  ck_assert_int_eq(bad[W_prescribed - 1], 0); /* (the last byte of A_c's room) */
  bad[W_prescribed - 1] = 1;
  reseal(bad, nbytes);
  refused_unchanged(p, nbytes, bad, ND_ERR_FORMAT, "padding", "padding");
  /* a resealed copy of the good block still loads, and gives its time */
  memcpy(bad, good, (size_t)nbytes);
  reseal(bad, nbytes);
  ND_OK_OR_FAIL(nd_problem_load_state(p, nbytes, bad));
  double t = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_TIME, &t));
  ck_assert(t == get_double(good, l.t));
  free(good);
  free(bad);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* a checkpoint of a problem defined otherwise (material, Nitsche
   parameters, scheme, time step, mass, a plane's normal) was accepted
   silently: now ND_ERR_STATE naming what differs, the state bitwise
   unchanged; the same definition, with other loads, another position of
   the plane and another solver, is accepted */
START_TEST(other_definitions_are_refused) {
  const double nm[2] = {0.25, 0.5}, nm2[2] = {0.3, 0.6}, th[2] = {1, 0};
  const double g2[3] = {0, -2, 0}, o2[3] = {0, -0.001, 0}, up[3] = {0, 1, 0}, tilted[3] = {0.1, 1, 0};
  nd_problem p = scene(2, 1, ND_SCHEME_NEWMARK, nm);
  for (int k = 0; k < 20; ++k) ND_OK_OR_FAIL(nd_step(p));
  int64_t nbytes = 0;
  unsigned char *buf = save(p, &nbytes);
  for (int which = 0; which < 8; ++which) {
    nd_problem q = scene(2, 1, which == 2 ? ND_SCHEME_THETA : ND_SCHEME_NEWMARK, which == 2 ? th : which == 3 ? nm2 : nm);
    const char *word = "";
    switch (which) {
      case 0:
        ND_OK_OR_FAIL(nd_problem_set_material(q, 20.0, 0.3, 1.0));
        word = "material";
        break;
      case 1:
        ND_OK_OR_FAIL(nd_problem_set_material(q, 10.0, 0.3, 1.5));
        word = "material";
        break;
      case 2:
      case 3:
        word = "scheme";
        break;
      case 4:
        ND_OK_OR_FAIL(nd_problem_set_timestep(q, 0.01));
        word = "time step";
        break;
      case 5:
        ND_OK_OR_FAIL(nd_problem_set_nitsche(q, 0.0, 0.0));
        word = "Nitsche";
        break;
      case 6:
        ND_OK_OR_FAIL(nd_problem_set_mass_lumping(q, 1));
        word = "mass";
        break;
      case 7:
        ND_OK_OR_FAIL(nd_problem_set_contact_plane(q, 1, o2, tilted));
        word = "contact planes";
        break;
    }
    for (int k = 0; k < 3; ++k) ND_OK_OR_FAIL(nd_step(q)); /* a state of its own, to be kept */
    char what[32];
    snprintf(what, sizeof what, "definition %d", which);
    refused_unchanged(q, nbytes, buf, ND_ERR_STATE, word, what);
    ND_OK_OR_FAIL(nd_problem_destroy(&q));
  }
  /* the same definition: other loads, the plane elsewhere (same normal),
     another linear solver, Newton's options: accepted, and it resumes */
  nd_problem q = scene(2, 1, ND_SCHEME_NEWMARK, nm);
  ND_OK_OR_FAIL(nd_problem_set_body_force(q, g2));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(q, 1, o2, up));
  ND_OK_OR_FAIL(nd_problem_set_linear_solver(q, ND_SOLVER_DENSE));
  ND_OK_OR_FAIL(nd_problem_load_state(q, nbytes, buf));
  ND_OK_OR_FAIL(nd_step(q));
  /* a restart may change the time step and the scheme: after the load, as between steps */
  nd_problem r = scene(2, 1, ND_SCHEME_NEWMARK, nm);
  ND_OK_OR_FAIL(nd_problem_load_state(r, nbytes, buf));
  ND_OK_OR_FAIL(nd_problem_set_timestep(r, 0.01));
  ND_OK_OR_FAIL(nd_problem_set_scheme(r, ND_SCHEME_THETA, th));
  ND_OK_OR_FAIL(nd_step(r));
  double t = 0;
  ND_OK_OR_FAIL(nd_get_scalar(r, ND_TIME, &t));
  ck_assert_double_eq_tol(t, 21 * 0.02 - 0.01, 1e-12);
  free(buf);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
  ND_OK_OR_FAIL(nd_problem_destroy(&r));
}
END_TEST

/* A checkpoint taken right after a redefinition between steps (new
   operators not made yet: fuzz_api's clang build read them before they
   were made) holds the new definition: it loads into a problem defined the same
   way and both runs go on bitwise */
START_TEST(saved_after_a_redefinition_between_steps) {
  const double nm[2] = {0.25, 0.5};
  nd_problem p = scene(2, 1, ND_SCHEME_NEWMARK, nm);
  for (int k = 0; k < 20; ++k) ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 0.5, 0.0));
  int64_t nbytes = 0;
  unsigned char *buf = save(p, &nbytes);
  nd_problem q = scene(2, 1, ND_SCHEME_NEWMARK, nm);
  ND_OK_OR_FAIL(nd_problem_set_nitsche(q, 0.5, 0.0));
  ND_OK_OR_FAIL(nd_problem_load_state(q, nbytes, buf));
  for (int k = 0; k < 10; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    ND_OK_OR_FAIL(nd_step(q));
  }
  ck_assert_msg(same_now(p, q, 2), "the run resumed from the checkpoint differs");
  free(buf);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
}
END_TEST

/* A version 8 checkpoint with curved obstacles (before W_geometry, the
   re-linearisations' energy, closed their section) still loads: the run
   goes on bitwise in its fields, W_geometry counted from 0 at the load */
START_TEST(version_8_curved_checkpoint_loads) {
  /* a circle above the scene's plane under the whole block (top at y = 0.01), so that it acts */
  const double centre[2] = {1, -100};
  nd_problem a = scene(2, 1, ND_SCHEME_HYBRID, NULL), b = scene(2, 1, ND_SCHEME_HYBRID, NULL);
  ND_OK_OR_FAIL(nd_problem_add_contact_sphere(a, 1, centre, 100.01, 0));
  ND_OK_OR_FAIL(nd_problem_add_contact_sphere(b, 1, centre, 100.01, 0));
  for (int k = 0; k < 30; ++k) ND_OK_OR_FAIL(nd_step(a));
  double Wg = 0, Wa = 0, Wb = 0;
  ND_OK_OR_FAIL(nd_get_scalar(a, ND_WORK_GEOMETRY, &Wg));
  ck_assert(Wg != 0);
  int64_t n9 = 0;
  unsigned char *v9 = save(a, &n9);
  ck_assert_int_eq(v9[8], 12);
  {  /* (version 10 without pairs, before the guard tail: version 9's layout) */
    int64_t n10 = 0;
    unsigned char *v10 = as_version_10(v9, n9, &n10);
    free(v9);
    v9 = v10, n9 = n10;
  }
  int64_t at = -1, found = 0; /* W_geometry's one place in the payload */
  for (int64_t i = 32; i + 8 <= n9 - 8; ++i)
    if (memcmp(v9 + i, &Wg, 8) == 0) at = i, ++found;
  ck_assert_int_eq(found, 1);
  int64_t n8 = 0;
  unsigned char *v8 = older_block(v9, n9, at, 8, 8, &n8);
  ND_OK_OR_FAIL(nd_problem_load_state(b, n8, v8));
  ND_OK_OR_FAIL(nd_get_scalar(b, ND_WORK_GEOMETRY, &Wb));
  ck_assert_double_eq(Wb, 0);
  for (int k = 0; k < 20; ++k) {
    ND_OK_OR_FAIL(nd_step(a));
    ND_OK_OR_FAIL(nd_step(b));
  }
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(a, &nodes));
  double *ua = malloc(sizeof(double) * (size_t)(2 * nodes)), *ub = malloc(sizeof(double) * (size_t)(2 * nodes));
  ND_OK_OR_FAIL(nd_get_field(a, ND_FIELD_DISPLACEMENT, nodes, ua));
  ND_OK_OR_FAIL(nd_get_field(b, ND_FIELD_DISPLACEMENT, nodes, ub));
  ck_assert(memcmp(ua, ub, sizeof(double) * (size_t)(2 * nodes)) == 0);
  ND_OK_OR_FAIL(nd_get_scalar(a, ND_WORK_GEOMETRY, &Wa));
  ND_OK_OR_FAIL(nd_get_scalar(b, ND_WORK_GEOMETRY, &Wb));
  /* the same 20 terms added to Wg and to 0: apart by the rounding of 20 sums */
  ck_assert_double_le(fabs(Wb - (Wa - Wg)), 20 * DBL_EPSILON * (fabs(Wa) + fabs(Wg)));
  /* and as version 9 (10 without the pairs' section is 9's layout) it loads
     with W_geometry kept, the run going on bitwise */
  int64_t n_9 = 0;
  unsigned char *as9 = older_block(v9, n9, 0, 0, 9, &n_9);
  nd_problem c = scene(2, 1, ND_SCHEME_HYBRID, NULL);
  ND_OK_OR_FAIL(nd_problem_add_contact_sphere(c, 1, centre, 100.01, 0));
  ND_OK_OR_FAIL(nd_problem_load_state(c, n_9, as9));
  double Wc = 0;
  ND_OK_OR_FAIL(nd_get_scalar(c, ND_WORK_GEOMETRY, &Wc));
  ck_assert(Wc == Wg);
  for (int k = 0; k < 20; ++k) ND_OK_OR_FAIL(nd_step(c));
  ND_OK_OR_FAIL(nd_get_field(c, ND_FIELD_DISPLACEMENT, nodes, ub));
  ck_assert(memcmp(ua, ub, sizeof(double) * (size_t)(2 * nodes)) == 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&c));
  free(as9);
  free(v9), free(v8), free(ua), free(ub);
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
}
END_TEST

/* Friction against a moving plane (docs/design.md §10.2): the friction
   section ends with the planes' points at t^n, from which the next step
   shifts the slip references; the block holds them (here, where the plane
   was at the last step), a NaN there is refused naming them, and a block
   that moves them moves the next step: a resumed run differs from the
   uninterrupted one unless they are the saved ones. Version 8 still loads. */
START_TEST(friction_section_holds_the_planes) {
  const double th[2] = {1, 0}, F = 0.3, up[2] = {0, 1};
  nd_problem p = scene(2, 1, ND_SCHEME_THETA, th);
  ND_OK_OR_FAIL(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F));
  double x = 0;
  for (int k = 1; k <= 20; ++k) {
    x = 0.01 * k;
    const double o[2] = {x, 0};
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
    ND_OK_OR_FAIL(nd_step(p));
  }
  int64_t nbytes = 0, nodes = 0, np = 0;
  unsigned char *good = save(p, &nbytes), *bad = malloc((size_t)nbytes);
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  ND_OK_OR_FAIL(nd_problem_get_contact_point_count(p, &np));
  const int64_t nf = get_i64(good, layout_of(0, 0, 0).U), nc = 2 * nodes - nf;
  /* from the end: the checksum, W_prescribed, A_c, V_c, U_c (each its count
     and room), then the planes' points: a count and 3 values per plane */
  const int64_t Uc = nbytes - 16 - kGuardTail - 3 * (8 + 8 * nc), points = Uc - 8 - 3 * 8;
  ck_assert_int_eq(good[layout_of(nf, nc, np).curved], 2); /* (the friction section alone) */
  ck_assert_int_eq(get_i64(good, points), 3);
  ck_assert(get_double(good, points + 8) == x && get_double(good, points + 16) == 0);
  memcpy(bad, good, (size_t)nbytes);
  put_double(bad, points + 8, NAN);
  reseal(bad, nbytes);
  refused_unchanged(p, nbytes, bad, ND_ERR_FORMAT, "planes' points", "a NaN plane point");
  /* resumed from the block, the next step is the uninterrupted one's; from
     a block whose plane was elsewhere, it is not (the references shift by
     the difference) */
  const double o[2] = {x + 0.01, 0};
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
  ND_OK_OR_FAIL(nd_step(p));
  const snap next = take(p, 2);
  memcpy(bad, good, (size_t)nbytes);
  put_double(bad, points + 8, x - 0.01);
  reseal(bad, nbytes);
  for (int run = 0; run < 2; ++run) {
    ND_OK_OR_FAIL(nd_problem_load_state(p, nbytes, run == 0 ? good : bad));
    ND_OK_OR_FAIL(nd_step(p));
    const snap again = take(p, 2);
    ck_assert_int_eq(same(next, again), run == 0);
    free(again.f);
  }
  free(next.f);
  /* before the planes' points, the one contact region's D_f, sliding and
     sticking points (version 12: a count and 3 values); a version 11 block
     (without them) loads, its one region's values the problem's */
  const int64_t regions = points - 32;
  ck_assert_int_eq(get_i64(good, regions), 3);
  double D = 0, D_region = -1;
  ND_OK_OR_FAIL(nd_problem_load_state(p, nbytes, good));
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_DISSIPATION_FRICTION, &D));
  ck_assert(D > 0 && get_double(good, regions + 8) == D);
  int64_t n11 = 0;
  unsigned char *v11 = older_block(good, nbytes, regions, 32, 11, &n11);
  ND_OK_OR_FAIL(nd_problem_load_state(p, n11, v11));
  ND_OK_OR_FAIL(nd_get_region_scalar(p, 1, ND_DISSIPATION_FRICTION, &D_region));
  ck_assert(D_region == D);
  free(v11);
  /* a version 8 block (its friction section without the regions' values
     and the points: friction had static planes then) still loads, the
     planes taken where they are: with the plane kept still, the run goes on
     as from the version 9 one */
  int64_t n8 = 0;
  int64_t n10 = 0;
  unsigned char *v10 = as_version_10(good, nbytes, &n10);
  unsigned char *v8 = older_block(v10, n10, regions, 64, 8, &n8);
  free(v10);
  snap from[2];
  for (int run = 0; run < 2; ++run) {
    ND_OK_OR_FAIL(run == 0 ? nd_problem_load_state(p, nbytes, good) : nd_problem_load_state(p, n8, v8));
    const double at[2] = {x, 0};
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, at, up));
    ND_OK_OR_FAIL(nd_step(p));
    from[run] = take(p, 2);
  }
  ck_assert(same(from[0], from[1]));
  free(from[0].f), free(from[1].f), free(v8);
  free(good);
  free(bad);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(void) {
  Suite *s = suite_create("checkpoint");
  TCase *tc = tcase_create("checkpoint");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, resumed_runs_are_bitwise_the_uninterrupted_ones);
  tcase_add_test(tc, checkpoint_size_is_fixed);
  tcase_add_test(tc, resumes_in_another_process);
  tcase_add_test(tc, bad_checkpoints_are_refused_and_change_nothing);
  tcase_add_test(tc, coupling_iteration_restores_and_retries);
  tcase_add_test(tc, set_state_keeps_time_and_work);
  tcase_add_test(tc, resumes_from_a_file);
  tcase_add_test(tc, resumes_from_a_file_in_another_process);
  tcase_add_test(tc, bad_checkpoint_files_are_refused_and_change_nothing);
  tcase_add_test(tc, reads_version_4_checkpoints);
  tcase_add_test(tc, fields_out_of_range_are_refused);
  tcase_add_test(tc, version_8_curved_checkpoint_loads);
  tcase_add_test(tc, other_definitions_are_refused);
  tcase_add_test(tc, saved_after_a_redefinition_between_steps);
  tcase_add_test(tc, friction_section_holds_the_planes);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
