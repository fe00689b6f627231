// Benchmark (not a test): what the guards of docs/design.md §3b cost a free-flight
// step of the disk (hybrid, Theta = 1, gamma0 = 1e-3, tau = 0.05, the 160
// steps before the impact at t = 10). Two copies of the problem step in
// turn, one with the default guards, one with the energy, energy-balance and penetration
// guards off, so that both see the same machine; prints one CSV row: median
// step with and without, their relative difference, and the cost of one
// energy evaluation (what the energy guard would cost if it ran every step)
// as a fraction of the median step.
//   guard_cost MESH DEGREE
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "capi/handles.hpp"
#include "drop_scene.h"
#include "timing.hpp"
#include "monitor/energies.hpp"

using ndbench::median;
using ndbench::seconds;

int main(int argc, char **argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s MESH DEGREE\n", argv[0]);
    return 2;
  }
  const int degree = std::atoi(argv[2]);
  nd_problem p[2] = {nullptr, nullptr};
  for (int k = 0; k < 2; ++k)
    if (drop_scene_create(2, argv[1], degree, ND_SCHEME_HYBRID, nullptr, 1.0, 1e-3, 0.05, ND_SOLVER_AUTO, &p[k]) !=
            ND_OK ||
        nd_problem_setup(p[k]) != ND_OK) {
      std::fprintf(stderr, "%s\n", nd_last_error());
      return 1;
    }
  nd_problem_set_guard(p[1], ND_GUARD_ENERGY, 0);
  nd_problem_set_guard(p[1], ND_GUARD_PENETRATION, 0);
  nd_problem_set_guard(p[1], ND_GUARD_ENERGY_BALANCE, 0);
  std::vector<double> t[2];
  for (int step = 0; step < 160; ++step)
    for (int k = 0; k < 2; ++k) {
      const double t0 = seconds();
      if (nd_step(p[k]) != ND_OK) {
        std::fprintf(stderr, "%s\n", nd_last_error());
        return 1;
      }
      t[k].push_back(seconds() - t0);
    }
  const nd::Discretization &d = p[0]->problem.discretization();
  std::vector<double> te;
  double sink = 0;
  nd::State s;  // the current state, read through the public API
  int64_t n = 0;
  nd_problem_get_node_count(p[0], &n);
  std::vector<double> full(static_cast<size_t>(2 * n));
  s.U.resize(static_cast<size_t>(d.dofs.n_free));
  s.V.resize(s.U.size());
  nd_get_field(p[0], ND_FIELD_DISPLACEMENT, n, full.data());
  d.dofs.restrict_to_free(full.data(), s.U.data());
  nd_get_field(p[0], ND_FIELD_VELOCITY, n, full.data());
  d.dofs.restrict_to_free(full.data(), s.V.data());
  for (int r = 0; r < 21; ++r) {
    const double t0 = seconds();
    sink += nd::mechanical_energy(d, s, nd::Products{});
    te.push_back(seconds() - t0);
  }
  const double with = median(t[0]), without = median(t[1]);
  std::printf("%d,%lld,%.4f,%.4f,%.4f,%.4f%s\n", degree, static_cast<long long>(d.dofs.n_free), 1e3 * with,
              1e3 * without, (with - without) / without, median(te) / without, sink == 0 ? " " : "");
  nd_problem_destroy(&p[0]);
  nd_problem_destroy(&p[1]);
  return 0;
}
