// libFuzzer target: arbitrary bytes loaded as a checkpoint into a small fixed
// problem (a bar of 4 P1 cells, clamped at one end, striking a plane at the
// other: every optional field of a checkpoint is present), by
// nd_problem_load_state on the buffer and nd_problem_load_state_file on the
// same bytes in a memory file (memfd, read through /proc/self/fd). Before
// the loads the bytes are RESEALED: from 40 bytes on, the header's payload
// size and the checksum are set as src/problem/checkpoint.cpp sets them
// (nd::state_checksum), so the fuzzer reaches the fields' checks behind the
// checksum, which anyone can recompute. Oracle, besides the sanitizers: a
// known status; a refused load leaves the problem's state bitwise unchanged
// (the block it saves is the one it saved before), with a status that
// describes the bytes; an accepted load gives finite fields and scalars, a
// step after it fails cleanly or succeeds; the buffer and the file accept
// the same bytes. The problem is put back to its baseline after each input.
//
// Seeds: ND_FUZZ_WRITE_SEEDS=DIR fuzz_checkpoint writes the problem's real
// checkpoints (at t = 0, in flight, in contact, after the rebound) into DIR
// and exits (tests/fuzz/corpus/fuzz_checkpoint holds them).
#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "nitschedyn.h"
#include "problem/checkpoint.hpp"

namespace {

[[noreturn]] void violated(const char *what, int status) {
  std::fprintf(stderr, "fuzz_checkpoint: contract violated: %s (status %d, last error '%s')\n", what, status,
               nd_last_error());
  std::abort();
}
void require(bool ok, const char *what, int status = 0) {
  if (!ok) violated(what, status);
}

constexpr int kCells = 4;

nd_problem make_problem() {
  nd_mesh m = nullptr;
  nd_problem p = nullptr;
  const double lo[1] = {-0.01}, hi0[1] = {0.01}, lo1[1] = {0.99}, hi1[1] = {1.01};
  const double point[1] = {1.02}, normal[1] = {-1}, nm[2] = {0.25, 0.5};
  require(nd_mesh_create_interval(kCells, 0.0, 1.0, &m) == ND_OK, "the mesh");
  require(nd_mesh_mark_boundary_box(m, 1, lo, hi0) == ND_OK && nd_mesh_mark_boundary_box(m, 2, lo1, hi1) == ND_OK,
          "the regions");
  require(nd_problem_create(m, 1, &p) == ND_OK, "the problem");
  nd_mesh_destroy(&m);
  double v0[kCells + 1];
  for (int i = 0; i <= kCells; ++i) v0[i] = 0.5 * i / kCells;  // the free end moves towards the plane
  const double f[1] = {0.01};
  require(nd_problem_set_material(p, 1.0, 0.0, 1.0) == ND_OK && nd_problem_set_dirichlet(p, 1) == ND_OK &&
              nd_problem_set_body_force(p, f) == ND_OK && nd_problem_set_contact_plane(p, 2, point, normal) == ND_OK &&
              nd_problem_set_nitsche(p, 1.0, 0.0) == ND_OK && nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm) == ND_OK &&
              nd_problem_set_timestep(p, 0.01) == ND_OK &&
              nd_problem_set_initial_state(p, kCells + 1, nullptr, v0) == ND_OK,
          "the definition");
  return p;
}

std::vector<unsigned char> saved(nd_problem p) {
  int64_t n = 0;
  require(nd_problem_get_state_size(p, &n) == ND_OK && n > 0, "the state size");
  std::vector<unsigned char> b(static_cast<size_t>(n));
  require(nd_problem_save_state(p, n, b.data()) == ND_OK, "a save");
  return b;
}

nd_problem g_problem = nullptr;
std::vector<unsigned char> g_baseline;  // its state after 8 steps (the seeds' problem)

void write_seeds(const char *dir) {
  nd_problem p = make_problem();
  const int at[] = {0, 3, 8, 12, 30};
  int done = 0;
  for (int k : at) {
    while (done < k) {
      require(nd_step(p) == ND_OK, "a step of the seeds' run");
      ++done;
    }
    const std::vector<unsigned char> b = saved(p);
    char path[512];
    std::snprintf(path, sizeof path, "%s/step%02d.ndck", dir, k);
    FILE *f = std::fopen(path, "wb");
    require(f && std::fwrite(b.data(), 1, b.size(), f) == b.size() && std::fclose(f) == 0, "writing a seed");
  }
  double force = 0;
  require(nd_get_scalar(p, ND_CONTACT_FORCE, &force) == ND_OK, "the contact force");
  nd_problem_destroy(&p);
}

// An accepted state: the values it holds read back finite (U, V; t, n, the
// works, the iteration counts), and every other query succeeds. What is
// derived from them (the energy, the acceleration from the equilibrium,
// the contact force, the reactions) is only required to be computed: a
// block may hold finite values so large (1e300 in U, in the load or in a
// gap) that their products overflow, as nd_problem_set_state and the
// setters of loads and planes may be given.
void require_finite(nd_problem p) {
  double x[kCells + 1];
  for (int field : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY, ND_FIELD_ACCELERATION, ND_FIELD_CONTACT_FORCE,
                    ND_FIELD_REACTION}) {
    const int st = nd_get_field(p, field, kCells + 1, x);
    const bool held = field == ND_FIELD_DISPLACEMENT || field == ND_FIELD_VELOCITY;
    require(held ? st == ND_OK : st != ND_ERR_INTERNAL && std::strcmp(nd_strerror(st), "unknown status code") != 0,
            "a field of an accepted state", st);
    if (held)
      for (int i = 0; i <= kCells; ++i) require(std::isfinite(x[i]), "a finite displacement and velocity");
  }
  for (int key : {ND_TIME, ND_STEP_INDEX, ND_WORK, ND_WORK_OBSTACLE, ND_NEWTON_ITERATIONS, ND_NEWTON_ITERATIONS_TOTAL,
                  ND_ENERGY_MECHANICAL, ND_CONTACT_FORCE}) {
    double v = 0;
    const int st = nd_get_scalar(p, key, &v);
    const bool held = key != ND_ENERGY_MECHANICAL && key != ND_CONTACT_FORCE;
    require(held ? st == ND_OK : st != ND_ERR_INTERNAL && std::strcmp(nd_strerror(st), "unknown status code") != 0,
            "a scalar of an accepted state", st);
    if (held) require(std::isfinite(v), "a finite time, step count, work and iteration count");
    if (key == ND_STEP_INDEX) require(v >= 0, "a step count >= 0");
  }
}

bool describes_the_bytes(int st) { return st == ND_ERR_FORMAT || st == ND_ERR_STATE || st == ND_ERR_SIZE; }

// one load of `bytes` (file: through a memory file); returns its status
int load(const std::vector<unsigned char> &bytes, bool file) {
  const std::vector<unsigned char> before = saved(g_problem);
  int st;
  if (!file) {
    static const unsigned char none = 0;  // (an empty input: a pointer, not NULL, and 0 bytes)
    st = nd_problem_load_state(g_problem, static_cast<int64_t>(bytes.size()), bytes.empty() ? &none : bytes.data());
  } else {
    const int fd = memfd_create("fuzz.ndck", 0);
    if (fd < 0) return -1000;
    size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t w = write(fd, bytes.data() + done, bytes.size() - done);
      if (w <= 0) break;
      done += static_cast<size_t>(w);
    }
    char path[64];
    std::snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    st = nd_problem_load_state_file(g_problem, path);
    close(fd);
  }
  require(std::strcmp(nd_strerror(st), "unknown status code") != 0, "a known status", st);
  if (st != ND_OK) {
    require(describes_the_bytes(st), "a refusal that describes the bytes", st);
    require(saved(g_problem) == before, "a refused load leaves the state bitwise unchanged", st);
    return st;
  }
  require_finite(g_problem);
  const int step = nd_step(g_problem);  // (the tangent's history and the rest, read by a step)
  require(std::strcmp(nd_strerror(step), "unknown status code") != 0 && step != ND_ERR_INTERNAL,
          "a step after an accepted load: a known status, no internal error", step);
  if (step == ND_OK) require_finite(g_problem);
  require(nd_problem_load_state(g_problem, static_cast<int64_t>(g_baseline.size()), g_baseline.data()) == ND_OK,
          "the baseline loads again");
  return st;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int *, char ***) {
  if (const char *dir = std::getenv("ND_FUZZ_WRITE_SEEDS")) {
    write_seeds(dir);
    std::exit(0);
  }
  g_problem = make_problem();
  for (int k = 0; k < 8; ++k) require(nd_step(g_problem) == ND_OK, "a baseline step");
  g_baseline = saved(g_problem);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  std::vector<unsigned char> bytes(data, data + size);
  // reseal: the payload size (header bytes 24..32) and the checksum (the last 8)
  if (bytes.size() >= nd::kStateHeaderSize + 8) {
    const uint64_t payload = bytes.size() - nd::kStateHeaderSize - 8;
    std::memcpy(bytes.data() + 24, &payload, sizeof payload);
    const uint64_t sum = nd::state_checksum(bytes.data(), bytes.size() - 8);
    std::memcpy(bytes.data() + bytes.size() - 8, &sum, sizeof sum);
  }
  const int in_buffer = load(bytes, false);
  const int in_file = load(bytes, true);
  if (in_file != -1000) require((in_buffer == ND_OK) == (in_file == ND_OK), "the buffer and the file agree", in_file);
  return 0;
}
