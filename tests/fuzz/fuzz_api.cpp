// libFuzzer target: bytes -> a sequence of nd_* calls on up to two meshes and
// two problems, with bounded sizes (small meshes, at most 24 steps) and
// arguments drawn from ordinary and extreme values (NaN, infinities, 1e308,
// 1e-308, INT64_MAX, negative counts). Oracle, besides the sanitizers: the
// C API's contract on every call: a known status; a message that names the
// call exactly when it failed; create functions leave NULL on failure; an
// accepted nd_step leaves no message even when the monitor made a failing
// call.
#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "nitschedyn.h"

namespace {

[[noreturn]] void violated(const char *call, int status, const char *what) {
  std::fprintf(stderr, "fuzz_api: %s returned %d: %s (last error '%s')\n", call, status, what, nd_last_error());
  std::abort();
}

// The contract of one call's outcome (FUZZ_API_TRACE set: each call and
// its status on stderr, to read what a crashing input did)
int check(const char *call, int status) {
  static const bool trace = std::getenv("FUZZ_API_TRACE") != nullptr;
  if (trace) std::fprintf(stderr, "%s -> %d %s\n", call, status, nd_last_error());
  if (std::strcmp(nd_strerror(status), "unknown status code") == 0) violated(call, status, "unknown status");
  const char *msg = nd_last_error();
  if (msg == nullptr) violated(call, status, "nd_last_error() is NULL");
  if (status < 0) {
    const size_t n = std::strlen(call);
    if (std::strncmp(msg, call, n) != 0 || std::strncmp(msg + n, ": ", 2) != 0)
      violated(call, status, "the message does not start with the call's name");
    if (status == ND_ERR_INTERNAL) violated(call, status, "ND_ERR_INTERNAL");
  } else if (msg[0] != '\0') {
    violated(call, status, "a message after success");
  }
  return status;
}
#define CALL(fn, ...) check(#fn, fn(__VA_ARGS__))

// a distance callback: the plane x_0 = 0, normal +x (the fuzzer varies where it acts)
int distance(double, const double *x, double *d, double *nu, void *) {
  *d = x[0];
  nu[0] = 1, nu[1] = 0, nu[2] = 0;
  return 0;
}

double any_double(FuzzedDataProvider &in) {
  static const double special[] = {0.0, 1.0, -1.0, 0.5, 0.25, 0.3, 2.0, 10.0, 1e-3, 1e-12, 1e308, -1e308, 1e-308,
                                   DBL_MAX, DBL_MIN, std::numeric_limits<double>::denorm_min(),
                                   std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                                   std::numeric_limits<double>::quiet_NaN(), 0.49999999, -0.99999999};
  const uint8_t k = in.ConsumeIntegral<uint8_t>();
  if (k < 2 * sizeof special / sizeof special[0]) return special[k / 2];
  return in.ConsumeFloatingPointInRange<double>(-4.0, 4.0);
}

// a count: usually small, sometimes one that must be refused by arithmetic
int64_t any_count(FuzzedDataProvider &in, int64_t small_max) {
  // (each large one overflows, or exceeds what an array may hold, in every
  // size computation it enters: refused before anything is allocated)
  static const int64_t extreme[] = {0, -1, INT64_MIN, INT64_MAX, INT64_MAX / 3 + 1, int64_t(1) << 62, int64_t(1) << 61};
  const uint8_t k = in.ConsumeIntegral<uint8_t>();
  if (k < 2 * sizeof extreme / sizeof extreme[0]) return extreme[k / 2];
  return in.ConsumeIntegralInRange<int64_t>(1, small_max);
}

int monitor(nd_problem p, void *userdata) {
  double x;
  nd_get_scalar(p, 12345, &x);  // fails: nd_step must not return with its message
  return *static_cast<int *>(userdata);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  FuzzedDataProvider in(data, size);
  nd_mesh meshes[2] = {nullptr, nullptr};
  nd_problem problems[2] = {nullptr, nullptr};
  int stop_flag = 0, steps = 0;
  std::vector<double> buf, buf2;
  for (int op = 0; op < 64 && in.remaining_bytes() > 0; ++op) {
    const int which = in.ConsumeIntegral<uint8_t>() & 1;
    nd_mesh &m = meshes[which];
    nd_problem &p = problems[which];
    double lo[3], hi[3], a[3], b[3];
    for (int k = 0; k < 3; ++k) lo[k] = any_double(in), hi[k] = any_double(in);
    for (int k = 0; k < 3; ++k) a[k] = any_double(in), b[k] = any_double(in);
    int64_t nodes = 0;
    if (p) nd_problem_get_node_count(p, &nodes);
    int dim = 1;
    if (m) nd_mesh_get_dimension(m, &dim);
    switch (in.ConsumeIntegralInRange<int>(0, 65)) {
      case 0:
        nd_mesh_destroy(&m);
        if (CALL(nd_mesh_create_interval, any_count(in, 12), lo[0], hi[0], &m) != ND_OK && m) violated("interval", 0, "handle");
        break;
      case 1:
        nd_mesh_destroy(&m);
        if (CALL(nd_mesh_create_rectangle, any_count(in, 5), any_count(in, 5), lo, hi, &m) != ND_OK && m) violated("rectangle", 0, "handle");
        break;
      case 2:
        nd_mesh_destroy(&m);
        if (CALL(nd_mesh_create_box, any_count(in, 2), any_count(in, 2), any_count(in, 2), lo, hi, &m) != ND_OK && m) violated("box", 0, "handle");
        break;
      case 3: {  // a raw mesh, counts possibly lying about the arrays only when they must be refused
        const int d = in.ConsumeIntegralInRange<int>(0, 4);
        const int64_t nv = in.ConsumeIntegralInRange<int64_t>(0, 8), nc = in.ConsumeIntegralInRange<int64_t>(0, 6);
        std::vector<double> x(static_cast<size_t>(nv * 3 + 1));
        std::vector<int64_t> c(static_cast<size_t>(nc * 4 + 1));
        for (auto &v : x) v = any_double(in);
        for (auto &v : c) v = in.ConsumeIntegralInRange<int64_t>(-1, 9);
        const bool huge = in.ConsumeBool();
        nd_mesh_destroy(&m);
        CALL(nd_mesh_create, d, huge ? INT64_MAX / 3 + 1 : nv, x.data(), huge ? int64_t(1) << 62 : nc, c.data(), &m);
        break;
      }
      case 4:
        if (m) CALL(nd_mesh_mark_boundary_box, m, in.ConsumeIntegralInRange<int>(-1, 3), lo, hi);
        break;
      case 61: {  // a raw mesh of any cell type (4 or 8 vertices a cell), counts lying only where refused
        const int d = in.ConsumeIntegralInRange<int>(0, 4), type = in.ConsumeIntegralInRange<int>(-1, 3);
        const int64_t nv = in.ConsumeIntegralInRange<int64_t>(0, 12), nc = in.ConsumeIntegralInRange<int64_t>(0, 3);
        std::vector<double> x(static_cast<size_t>(nv * 3 + 1));
        std::vector<int64_t> c(static_cast<size_t>(nc * 8 + 1));
        for (auto &v : x) v = any_double(in);
        for (auto &v : c) v = in.ConsumeIntegralInRange<int64_t>(-1, 13);
        nd_mesh_destroy(&m);
        if (CALL(nd_mesh_create_cells, d, type, nv, x.data(), nc, c.data(), &m) != ND_OK && m)
          violated("cells", 0, "handle");
        break;
      }
      case 60: {  // a mixed mesh: any types a cell (the count of vertices each takes from them), any vertices
        const int d = in.ConsumeIntegralInRange<int>(0, 4);
        const int64_t nv = in.ConsumeIntegralInRange<int64_t>(0, 12), nc = in.ConsumeIntegralInRange<int64_t>(0, 4);
        std::vector<double> x(static_cast<size_t>(nv * 3 + 1));
        std::vector<int> types(static_cast<size_t>(nc + 1));
        std::vector<int64_t> c(static_cast<size_t>(nc * 8 + 1));  // (room for the largest type's count)
        for (auto &v : x) v = any_double(in);
        for (auto &t : types) t = in.ConsumeIntegralInRange<int>(-1, 3);
        for (auto &v : c) v = in.ConsumeIntegralInRange<int64_t>(-1, 13);
        nd_mesh_destroy(&m);
        if (CALL(nd_mesh_create_mixed, d, nv, x.data(), nc, types.data(), c.data(), &m) != ND_OK && m)
          violated("mixed", 0, "handle");
        break;
      }
      case 62: {  // the generators with a cell type, any type
        const int type = in.ConsumeIntegralInRange<int>(-1, 3);
        nd_mesh_destroy(&m);
        const int st = in.ConsumeBool()
                           ? CALL(nd_mesh_create_rectangle_cells, any_count(in, 4), any_count(in, 4), lo, hi, type, &m)
                           : CALL(nd_mesh_create_box_cells, any_count(in, 2), any_count(in, 2), any_count(in, 2), lo, hi,
                                  type, &m);
        if (st != ND_OK && m) violated("cells generator", 0, "handle");
        break;
      }
      case 5: {
        std::vector<int64_t> f(static_cast<size_t>(3 * 3));
        for (auto &v : f) v = in.ConsumeIntegralInRange<int64_t>(-1, 10);
        if (m) CALL(nd_mesh_set_region, m, in.ConsumeIntegralInRange<int>(-1, 3), in.ConsumeIntegralInRange<int64_t>(-1, 3), f.data());
        break;
      }
      case 6: {
        int64_t n;
        if (m) CALL(nd_mesh_get_region_size, m, in.ConsumeIntegralInRange<int>(-2, 3), &n);
        if (m) CALL(nd_mesh_get_vertex_count, m, &n);
        break;
      }
      case 7:
        nd_problem_destroy(&p);
        if (m) CALL(nd_problem_create, m, in.ConsumeIntegralInRange<int>(0, 3), &p);
        break;
      case 8:
        if (p) CALL(nd_problem_set_material, p, any_double(in), any_double(in), any_double(in));
        break;
      case 9:
        if (p) CALL(nd_problem_set_dirichlet, p, in.ConsumeIntegralInRange<int>(-1, 3));
        break;
      case 10:
        if (p) CALL(nd_problem_set_body_force, p, a);
        break;
      case 11:
        if (p) CALL(nd_problem_set_neumann, p, in.ConsumeIntegralInRange<int>(-1, 3), a);
        break;
      case 12:
        if (p) CALL(nd_problem_set_contact_plane, p, in.ConsumeIntegralInRange<int>(-1, 3), a, b);
        break;
      case 13:
        if (p) CALL(nd_problem_set_nitsche, p, any_double(in), any_double(in));
        break;
      case 14:
        if (p) CALL(nd_problem_set_scheme, p, in.ConsumeIntegralInRange<int>(0, 5), a);
        break;
      case 15:
        if (p) {
          buf.assign(static_cast<size_t>(nodes * 3 + 1), 0.0);
          for (auto &v : buf) v = any_double(in);
          CALL(nd_problem_set_nodal_forces, p, in.ConsumeBool() ? nodes : any_count(in, 4), buf.data());
        }
        break;
      case 16:
        if (p) CALL(nd_problem_set_newton, p, any_double(in), any_double(in), in.ConsumeIntegralInRange<int>(-1, 20));
        break;
      case 17:
        if (p) CALL(nd_problem_set_mass_lumping, p, in.ConsumeIntegralInRange<int>(-1, 2));
        break;
      case 18:
        if (p) CALL(nd_problem_set_linear_solver, p, in.ConsumeIntegralInRange<int>(-1, 6));
        break;
      case 19:
        if (p) CALL(nd_problem_set_timestep, p, any_double(in));
        break;
      case 20:
        if (p) {
          buf.assign(static_cast<size_t>(nodes * 3 + 1), 0.0);
          buf2.assign(buf.size(), 0.0);
          for (auto &v : buf) v = any_double(in);
          CALL(nd_problem_set_initial_state, p, nodes, in.ConsumeBool() ? buf.data() : nullptr, buf2.data());
        }
        break;
      case 21:
        if (p) CALL(nd_problem_setup, p);
        break;
      case 22:
      case 23:
        if (p && steps < 24) {
          ++steps;
          const int st = CALL(nd_step, p);
          if (st == ND_MONITOR_STOP && !stop_flag) violated("nd_step", st, "stopped without the monitor asking");
        }
        break;
      case 24:
        if (p) {
          buf.assign(static_cast<size_t>(nodes * 3 + 1), 0.0);
          CALL(nd_get_field, p, in.ConsumeIntegralInRange<int>(0, 4), nodes, buf.data());
        }
        break;
      case 25:
        if (p) {
          double x;
          CALL(nd_get_scalar, p, in.ConsumeIntegralInRange<int>(0, 13), &x);
        }
        break;
      case 26:
        if (p) {
          int64_t nq = 0;
          if (CALL(nd_problem_get_contact_point_count, p, &nq) == ND_OK && nq >= 0 && nq < 100000) {
            buf.assign(static_cast<size_t>(nq * 3 + 1), 0.0);
            buf2.assign(static_cast<size_t>(nq + 1), 0.0);
            CALL(nd_problem_get_contact_points, p, nq, buf.data(), buf2.data());
            CALL(nd_get_contact_pressure, p, nq, buf2.data());
          }
        }
        break;
      case 27:
        if (p) {
          stop_flag = in.ConsumeBool();
          CALL(nd_problem_set_monitor, p, in.ConsumeBool() ? monitor : nullptr, &stop_flag);
        }
        break;
      case 28:
        nd_mesh_destroy(&m);
        break;
      case 29:
        nd_problem_destroy(&p);
        break;
      case 30:
        if (p) {
          buf.assign(static_cast<size_t>(nodes * 3 + 1), 0.0);
          CALL(nd_problem_get_node_coordinates, p, nodes, buf.data());
        }
        break;
      case 31: {
        const char *names[2] = {"a<b&c\"d'.vtu", "tab\there.vtu"};
        double t[2] = {any_double(in), 1.0};
        char path[64];
        std::snprintf(path, sizeof path, "/proc/self/fd/%d", -1);  // never writable: ND_ERR_IO
        CALL(nd_write_pvd, path, in.ConsumeIntegralInRange<int64_t>(-1, 2), names, t);
        break;
      }
      case 32:
        (void)dim;
        CALL(nd_mesh_create_interval, any_count(in, 4), any_double(in), any_double(in), nullptr);
        break;
      case 33:  // operators out: sizes, then the arrays; the DOF map and the load
        if (p) {
          int64_t n = 0, nnz = 0;
          const int kind = in.ConsumeIntegralInRange<int>(0, 7);
          if (CALL(nd_problem_get_matrix, p, kind, &n, &nnz, nullptr, nullptr, nullptr) == ND_OK && n >= 0 &&
              n < 100000 && nnz >= 0 && nnz < 10000000) {
            std::vector<int64_t> ptr(static_cast<size_t>(n + 1)), col(static_cast<size_t>(nnz + 1));
            buf.assign(static_cast<size_t>(nnz + n + 1), 0.0);
            CALL(nd_problem_get_matrix, p, kind, &n, &nnz, ptr.data(), col.data(), buf.data());
            std::vector<int> comp(static_cast<size_t>(n + 1));
            CALL(nd_problem_get_dof_map, p, n, ptr.data(), comp.data());
            CALL(nd_problem_get_load, p, n, buf.data());
          }
        }
        break;
      case 34:  // the contact term at a fuzzed U (values possibly not finite)
        if (p) {
          int64_t n = 0, nnz = 0;
          if (CALL(nd_problem_get_matrix, p, ND_MATRIX_MASS, &n, &nnz, nullptr, nullptr, nullptr) == ND_OK &&
              n >= 0 && n < 100000) {
            buf.assign(static_cast<size_t>(n + 1), 0.0);
            // (room for the residual's n values and for the up to 5 values asked of contact_values:
            // the harness's own buffer, which a small mesh made shorter than the count it passed)
            buf2.assign(static_cast<size_t>(std::max<int64_t>(n + 1, 5)), 0.0);
            for (auto &x : buf) x = any_double(in);
            CALL(nd_problem_contact_residual, p, n, buf.data(), buf2.data());
            CALL(nd_problem_contact_values, p, n, buf.data(), in.ConsumeIntegralInRange<int>(0, 5), buf2.data());
            if (CALL(nd_problem_contact_tangent, p, n, nullptr, &nnz, nullptr, nullptr, nullptr) == ND_OK &&
                nnz >= 0 && nnz < 10000000) {
              std::vector<int64_t> ptr(static_cast<size_t>(n + 1)), col(static_cast<size_t>(nnz + 1));
              std::vector<double> val(static_cast<size_t>(nnz + 1));
              CALL(nd_problem_contact_tangent, p, n, buf.data(), &nnz, ptr.data(), col.data(), val.data());
            }
          }
        }
        break;
      case 35:
        if (p) CALL(nd_problem_add_contact_sphere, p, in.ConsumeIntegralInRange<int>(-1, 3), a, any_double(in),
                    in.ConsumeIntegralInRange<int>(-1, 2));
        break;
      case 63:  // two regions in contact (the same one, unknown ones: refused); steps then pair them
        if (p) CALL(nd_problem_set_contact_pair, p, in.ConsumeIntegralInRange<int>(-1, 3),
                    in.ConsumeIntegralInRange<int>(-1, 3));
        break;
      case 64: {  // a contact region's scalar: any region, any key
        double x = 0;
        if (p) CALL(nd_get_region_scalar, p, in.ConsumeIntegralInRange<int>(-1, 3), in.ConsumeIntegralInRange<int>(-1, 80),
                    &x);
        break;
      }
      case 65:  // adaptive steps with any values (refused, or on: the steps then choose their sizes)
        if (p) CALL(nd_problem_set_adaptive_timestep, p, in.ConsumeBool() ? 0.0 : any_double(in), any_double(in),
                    any_double(in));
        break;
      case 36:
        if (p) CALL(nd_problem_add_contact_cylinder, p, in.ConsumeIntegralInRange<int>(-1, 3), a, b, any_double(in),
                    in.ConsumeIntegralInRange<int>(-1, 2));
        break;
      case 37:
        if (p) CALL(nd_problem_add_contact_distance, p, in.ConsumeIntegralInRange<int>(-1, 3),
                    in.ConsumeBool() ? distance : nullptr, nullptr);
        break;
      case 38: {
        double R[9];
        for (auto &v : R) v = in.ConsumeBool() ? any_double(in) : 0.0;
        if (in.ConsumeBool()) R[0] = R[4] = R[8] = 1, R[3] = 0;  // (2D reads R[0], R[1], R[2], R[3])
        if (p) CALL(nd_problem_move_obstacle, p, in.ConsumeIntegralInRange<int>(-1, 3),
                    in.ConsumeIntegralInRange<int>(-1, 2), a, in.ConsumeBool() ? R : nullptr);
        break;
      }
      case 39:  // the step form at fuzzed U and U^n (values possibly not finite)
        if (p) {
          int64_t n = 0, nnz = 0;
          if (CALL(nd_problem_get_matrix, p, ND_MATRIX_MASS, &n, &nnz, nullptr, nullptr, nullptr) == ND_OK &&
              n >= 0 && n < 100000) {
            buf.assign(static_cast<size_t>(n + 1), 0.0);
            buf2.assign(static_cast<size_t>(n + 1), 0.0);
            std::vector<double> r(static_cast<size_t>(n + 1));
            for (auto &x : buf) x = any_double(in);
            for (auto &x : buf2) x = any_double(in);
            CALL(nd_problem_contact_step_residual, p, n, buf.data(), in.ConsumeBool() ? buf2.data() : nullptr,
                 r.data());
            if (CALL(nd_problem_contact_step_tangent, p, n, nullptr, nullptr, &nnz, nullptr, nullptr, nullptr) ==
                    ND_OK &&
                nnz >= 0 && nnz < 10000000) {
              std::vector<int64_t> ptr(static_cast<size_t>(n + 1)), col(static_cast<size_t>(nnz + 1));
              std::vector<double> val(static_cast<size_t>(nnz + 1));
              CALL(nd_problem_contact_step_tangent, p, n, buf.data(), buf2.data(), &nnz, ptr.data(), col.data(),
                   val.data());
            }
          }
        }
        break;
      case 45: {  // cells into a cell region: indices out of range, counts not positive (the array's length
                  // is the caller's word: a larger count with valid indices reads past it, as it would anywhere)
        std::vector<int64_t> c(4);
        for (auto &v : c) v = in.ConsumeIntegralInRange<int64_t>(-1, 30);
        if (m) CALL(nd_mesh_set_cell_region, m, in.ConsumeIntegralInRange<int>(-1, 3),
                    in.ConsumeBool() ? INT64_MIN : in.ConsumeIntegralInRange<int64_t>(-1, 4),
                    in.ConsumeBool() ? c.data() : nullptr);
        break;
      }
      case 46:
        if (m) {
          int64_t nc = 0;
          nd_mesh_get_cell_count(m, &nc);
          std::vector<int> r(static_cast<size_t>(nc + 1));
          // (a count other than nc is refused before anything is written)
          CALL(nd_mesh_get_cell_regions, m, in.ConsumeBool() ? nc : any_count(in, 8), in.ConsumeBool() ? r.data() : nullptr);
        }
        break;
      case 47:
        if (p) CALL(nd_problem_set_material_region, p, in.ConsumeIntegralInRange<int>(-1, 3), any_double(in),
                    any_double(in), any_double(in));
        break;
      case 40:  // Rayleigh damping: any values (negative, NaN, infinite refused)
        if (p) CALL(nd_problem_set_damping, p, any_double(in), any_double(in));
        break;
      case 41:  // plane stress: refused outside 2D
        if (p) CALL(nd_problem_set_plane_stress, p, in.ConsumeIntegralInRange<int>(-1, 2));
        break;
      case 42:  // the damping matrix out
        if (p) {
          int64_t n = 0, nnz = 0;
          if (CALL(nd_problem_get_matrix, p, ND_MATRIX_DAMPING, &n, &nnz, nullptr, nullptr, nullptr) == ND_OK &&
              n >= 0 && n < 100000 && nnz >= 0 && nnz < 10000000) {
            std::vector<int64_t> ptr(static_cast<size_t>(n + 1)), col(static_cast<size_t>(nnz + 1));
            buf.assign(static_cast<size_t>(nnz + 1), 0.0);
            CALL(nd_problem_get_matrix, p, ND_MATRIX_DAMPING, &n, &nnz, ptr.data(), col.data(), buf.data());
          }
        }
        break;
      case 43:  // a damped step (valid values), whatever the scheme
        if (p && CALL(nd_problem_set_damping, p, std::fabs(any_double(in)), 1e-3 * std::fabs(any_double(in))) == ND_OK &&
            steps < 24) {
          ++steps;
          CALL(nd_step, p);
        }
        break;
      case 44: {  // the damping's dissipation
        double x;
        if (p) CALL(nd_get_scalar, p, ND_DISSIPATION_DAMPING, &x);
        break;
      }
      case 48:  // a guard: any id, any value (negative, NaN, infinite refused)
        if (p) CALL(nd_problem_set_guard, p, in.ConsumeIntegralInRange<int>(-1, 9), any_double(in));
        break;
      case 49:  // the mass redistribution: any flag, then a step
        if (p) {
          CALL(nd_problem_set_mass_redistribution, p, in.ConsumeIntegralInRange<int>(-1, 2));
          if (in.ConsumeBool() && steps < 24) ++steps, CALL(nd_step, p);
        }
        break;
      case 56:  // the state overwritten between steps, counts possibly lying, values possibly not finite
        if (p) {
          buf.assign(static_cast<size_t>(3 * nodes + 1), 0.0);
          buf2.assign(buf.size(), 0.0);
          for (auto &x : buf) x = in.ConsumeBool() ? 1e-3 * any_double(in) : 0.0;
          for (auto &x : buf2) x = in.ConsumeBool() ? any_double(in) : 0.0;
          CALL(nd_problem_set_state, p, in.ConsumeBool() ? nodes : any_count(in, 40),
               in.ConsumeBool() ? buf.data() : nullptr, in.ConsumeBool() ? buf2.data() : nullptr);
        }
        break;
      case 57: {  // the critical step and the cells (sizes, then the nodes)
        if (!p) break;
        double tau_c;
        CALL(nd_problem_estimate_critical_timestep, p, &tau_c);
        int64_t n_cells = 0;
        int per = 0;
        if (CALL(nd_problem_get_cells, p, &n_cells, &per, nullptr) == ND_OK && n_cells * per < 100000) {
          std::vector<int64_t> cells(static_cast<size_t>(n_cells * per) + 1);
          CALL(nd_problem_get_cells, p, &n_cells, &per, cells.data());
        }
        break;
      }
      case 58:  // the pressure the last step applied, counts possibly lying (refused: not the points' count)
        if (p) {
          int64_t nq = 0;
          if (CALL(nd_problem_get_contact_point_count, p, &nq) != ND_OK || nq < 0 || nq >= 100000) break;
          const int64_t n = in.ConsumeBool() ? nq : any_count(in, 40);
          buf.assign(static_cast<size_t>(std::max<int64_t>(nq, 40) + 1), 0.0);
          CALL(nd_get_contact_pressure_applied, p, n, buf.data());
        }
        break;
      case 59: {  // files: a checkpoint and a VTU to a path that may be none, a directory, missing or a file
        if (!p) break;
        static std::string dir;
        if (dir.empty()) {
          char tmpl[] = "/tmp/fuzz_api.XXXXXX";
          if (!mkdtemp(tmpl)) break;
          dir = tmpl;
          std::atexit([] {  // (the one file it may leave; the atomic writes leave no other)
            std::remove((dir + "/out").c_str());
            std::remove(dir.c_str());
          });
        }
        const std::string paths[] = {"", dir, dir + "/missing/out", dir + "/out"};
        const std::string &path = paths[in.ConsumeIntegralInRange<int>(0, 3)];
        switch (in.ConsumeIntegralInRange<int>(0, 2)) {
          case 0:
            CALL(nd_problem_save_state_file, p, path.c_str());
            break;
          case 1: {  // into this problem or the other one
            nd_problem other = problems[in.ConsumeBool() ? which : 1 - which];
            if (other) CALL(nd_problem_load_state_file, other, path.c_str());
            break;
          }
          default:
            CALL(nd_problem_write_vtu, p, path.c_str());
        }
        break;
      }
      case 55:  // friction: any law id, region and coefficient, then a step
        if (p) {
          const double c = any_double(in);
          CALL(nd_problem_set_friction, p, in.ConsumeIntegralInRange<int>(-1, 3),
               in.ConsumeIntegralInRange<int>(-1, 3), in.ConsumeBool() ? &c : nullptr);
          if (in.ConsumeBool()) CALL(nd_step, p);
        }
        break;
      case 50:  // prescribed motion of a region (clamped or not), values possibly not finite
        if (p) CALL(nd_problem_set_dirichlet_value, p, in.ConsumeIntegralInRange<int>(-1, 3), in.ConsumeBool() ? a : nullptr);
        break;
      case 51:  // the nodal form, counts possibly lying about the array
        if (p) {
          buf.assign(static_cast<size_t>(3 * nodes + 1), 0.0);
          for (auto &x : buf) x = in.ConsumeBool() ? any_double(in) : 0.0;
          CALL(nd_problem_set_dirichlet_nodal, p, in.ConsumeBool() ? nodes : any_count(in, 40), buf.data());
        }
        break;
      case 52:  // a moved support, then a step with it (refused when a contact point reads it)
        if (p && steps < 24) {
          ++steps;
          const double d[3] = {0.01 * a[0], 0.01 * a[1], 0.01 * a[2]};
          CALL(nd_problem_set_dirichlet_value, p, in.ConsumeIntegralInRange<int>(0, 3), d);
          CALL(nd_step, p);
        }
        break;
      case 53:  // what the motion reports: its work, the reactions, the supports' velocity
        if (p && nodes > 0 && nodes < 100000) {
          double w;
          CALL(nd_get_scalar, p, ND_WORK_PRESCRIBED, &w);
          buf.assign(static_cast<size_t>(3 * nodes), 0.0);
          CALL(nd_get_field, p, in.ConsumeBool() ? ND_FIELD_REACTION : ND_FIELD_VELOCITY, nodes, buf.data());
        }
        break;
      case 54:  // a checkpoint with the motion, loaded into the other problem (or this one)
        if (p) {
          int64_t nb = 0;
          if (CALL(nd_problem_get_state_size, p, &nb) == ND_OK && nb > 0 && nb < (int64_t(1) << 26)) {
            std::vector<unsigned char> bytes(static_cast<size_t>(nb));
            if (CALL(nd_problem_save_state, p, nb, bytes.data()) == ND_OK) {
              nd_problem other = problems[in.ConsumeBool() ? which : 1 - which];
              if (other) CALL(nd_problem_load_state, other, nb, bytes.data());
            }
          }
        }
        break;
      default: {
        int mj, mn, pt;
        CALL(nd_version, &mj, &mn, &pt);
      }
    }
  }
  for (auto &p : problems) nd_problem_destroy(&p);
  for (auto &m : meshes) nd_mesh_destroy(&m);
  return 0;
}
