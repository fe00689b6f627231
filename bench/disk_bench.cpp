// Benchmark (not a test): the 2D disk or 3D ball of DESIGN §7, one
// configuration per process so that the peak memory is its own. Prints one
// CSV row: the setup time, the first step (assembly and factorization), the
// median and mean time per step, Newton iterations per step, the cost of the
// physical floor of a step (one solve with the cached factor of c M + K_Theta,
// timed in the same run) and the median step as a ratio to it, peak memory.
//   disk_bench DIM MESH DEGREE TAU T SOLVER
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "capi/handles.hpp"
#include "drop_scene.h"
#include "timing.hpp"

using ndbench::median;
using ndbench::seconds;

int main(int argc, char **argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: %s DIM MESH DEGREE TAU T SOLVER\n", argv[0]);
    return 2;
  }
  const int dim = std::atoi(argv[1]), degree = std::atoi(argv[3]), solver = std::atoi(argv[6]);
  const double tau = std::atof(argv[4]), T = std::atof(argv[5]);
  nd_problem p = nullptr;
  double t0 = seconds();
  if (drop_scene_create(dim, argv[2], degree, ND_SCHEME_HYBRID, nullptr, 1.0, 1e-3, tau, solver, &p) != ND_OK) {
    std::fprintf(stderr, "%s\n", nd_last_error());
    return 1;
  }
  const double setup = seconds() - t0;
  const int steps = static_cast<int>(T / tau + 0.5);
  std::vector<double> times;
  double newton = 0, first = 0;
  for (int k = 0; k < steps; ++k) {
    t0 = seconds();
    if (nd_step(p) != ND_OK) {
      std::fprintf(stderr, "%s\n", nd_last_error());
      return 1;
    }
    const double dt = seconds() - t0;
    if (k == 0)
      first = dt;  // includes assembly and the factorization of c M + K_Theta
    else
      times.push_back(dt);
    double it = 0;
    nd_get_scalar(p, ND_NEWTON_ITERATIONS, &it);
    newton += it;
  }
  // the floor: one forward/backward solve with the cached factor
  const nd::Integrator *so = p->problem.integrator();
  std::vector<double> x(static_cast<size_t>(so->A.n), 1.0), floor_times;
  for (int r = 0; r < 21; ++r) {
    t0 = seconds();
    so->A_factor->solve(x.data());
    floor_times.push_back(seconds() - t0);
  }
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  int64_t nodes = 0;
  nd_problem_get_node_count(p, &nodes);
  const double med = median(times), mean = [&] {
    double s = 0;
    for (double v : times) s += v;
    return times.empty() ? 0 : s / static_cast<double>(times.size());
  }();
  std::printf("%d,%s,%d,%lld,%d,%s,%.6f,%.6f,%.6f,%.6f,%.4f,%.6f,%.2f,%.1f\n", dim, argv[2], degree,
              static_cast<long long>(nodes * dim), steps, so->A_factor->name(), setup, first, 1e3 * med, 1e3 * mean,
              newton / steps, 1e3 * median(floor_times), med / median(floor_times), ru.ru_maxrss / 1024.0);
  nd_problem_destroy(&p);
  return 0;
}
