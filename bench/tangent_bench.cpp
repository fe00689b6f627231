// Benchmark (not a test): the Newton tangent solvers of docs/design.md §4 on the disk
// or ball dropped on a plane (hybrid scheme, Theta = 1, gamma0 = 1e-3, tau = 0.05).
//
//   tangent_bench run DIM MESH DEGREE [T]
//     the whole bounce (T = 32) once with each path (refactor, lowrank with
//     no rank limit, condensed, updown: the updated factor, auto); per path one CSV row: floor (one solve with the
//     cached factor of A, timed in the same run), median contact step and
//     median cost per Newton iteration of a contact step, both as ratios to
//     the floor, the slowest contact step (the impact: new columns), columns.
//
//   tangent_bench crossover DIM MESH DEGREE
//     one solve with k active points (the first k contact points made active
//     through the gap) for k = 1 .. all: the refactorization against the
//     low-rank update (warm: columns and G cached, what a Newton iteration
//     in persistent contact pays; new set: G rebuilt; and the columns' cost
//     per point). The rank above which the refactorization wins is the rule
//     of lowrank_rank_limit. The warm solve is timed right after a
//     refactorization (cold caches, as after a residual evaluation), the
//     one-point change back to back: the latter can read lower at small k.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "capi/handles.hpp"
#include "drop_scene.h"

namespace {
double seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
const char *threads() {
  const char *t = std::getenv("OPENBLAS_NUM_THREADS");
  return t ? t : "default";
}

// ND_BENCH_SOLVER=N in the environment: the ND_SOLVER_* value N instead of the library's choice
int solver() {
  const char *s = std::getenv("ND_BENCH_SOLVER");
  return s ? std::atoi(s) : ND_SOLVER_AUTO;
}

nd_problem make(int dim, const char *mesh, int degree) {
  nd_problem p = nullptr;
  if (drop_scene_create(dim, mesh, degree, ND_SCHEME_HYBRID, nullptr, 1.0, 1e-3, 0.05, solver(), &p) != ND_OK) {
    std::fprintf(stderr, "%s\n", nd_last_error());
    std::exit(1);
  }
  return p;
}

double floor_solve(const nd::Integrator &in) {
  std::vector<double> x(static_cast<size_t>(in.A.n), 1.0), t;
  for (int r = 0; r < 31; ++r) {
    const double t0 = seconds();
    in.A_factor->solve(x.data());
    t.push_back(seconds() - t0);
  }
  return median(t);
}

int run(int dim, const char *mesh, int degree, double T) {
  const char *names[] = {"refactor", "lowrank", "condensed", "updown", "auto"};
  const nd::TangentChoice choices[] = {nd::TangentChoice::Refactor, nd::TangentChoice::LowRank,
                                       nd::TangentChoice::Condensed, nd::TangentChoice::Updown,
                                       nd::TangentChoice::Auto};
  const int steps = static_cast<int>(T / 0.05 + 0.5);
  for (int c = 0; c < 5; ++c) {
    nd_problem p = make(dim, mesh, degree);
    p->problem.set_tangent(choices[c]);
    std::vector<double> contact, per_iteration, free_flight;
    double newton = 0, slowest = 0;
    for (int k = 0; k < steps; ++k) {
      const double t0 = seconds();
      if (nd_step(p) != ND_OK) {
        std::fprintf(stderr, "%s\n", nd_last_error());
        return 1;
      }
      const double dt = seconds() - t0;
      if (k == 0) continue;  // assembly and factorization
      double it = 0, force = 0;
      nd_get_scalar(p, ND_NEWTON_ITERATIONS, &it);
      nd_get_scalar(p, ND_CONTACT_FORCE, &force);
      if (force > 0) {  // a step that ends in contact
        contact.push_back(dt);
        per_iteration.push_back(dt / it);
        newton += it;
        slowest = std::max(slowest, dt);
      } else {
        free_flight.push_back(dt);
      }
    }
    const nd::Integrator &in = *p->problem.integrator();
    const double fl = floor_solve(in);
    const nd::TangentStats &st = in.tangent->stats;
    std::printf("%d,%s,%d,%lld,%lld,%s,%s,%.6f,%zu,%.3f,%.2f,%.2f,%.2f,%.2f,%.1f,%lld,%lld,%lld\n", dim,
                std::strrchr(mesh, '/') ? std::strrchr(mesh, '/') + 1 : mesh, degree,
                static_cast<long long>(in.A.n), static_cast<long long>(p->problem.discretization().contact.size()),
                names[c], threads(), 1e3 * fl, contact.size(),
                contact.empty() ? 0 : newton / static_cast<double>(contact.size()), median(free_flight) / fl,
                median(contact) / fl, median(per_iteration) / fl, median(contact) * 1e3, slowest / fl,
                static_cast<long long>(st.columns), static_cast<long long>(st.max_rank),
                static_cast<long long>(st.refactorizations));
    std::fflush(stdout);
    nd_problem_destroy(&p);
  }
  return 0;
}

int crossover(int dim, const char *mesh, int degree) {
  nd_problem p = make(dim, mesh, degree);
  if (nd_step(p) != ND_OK) return 1;
  const nd::Integrator &in = *p->problem.integrator();
  nd::ContactPoints cp = p->problem.discretization().contact;  // a copy whose gaps choose the active set
  const size_t Q = cp.size();
  const int64_t n = in.A.n;
  const double fl = floor_solve(in);
  std::vector<double> U(static_cast<size_t>(n), 0.0), x;
  const double kappa = in.coef.kappa;
  auto refactor = nd::make_refactoring_tangent(in.A, *in.A_factor, ND_SOLVER_AUTO,
                                               nd::Structure::SymmetricPositiveDefinite);
  std::vector<size_t> ks;
  for (size_t k = 1; k <= Q; k = std::max(k + 1, k * 5 / 4)) ks.push_back(k);
  if (ks.back() != Q) ks.push_back(Q);
  for (size_t k : ks) {
    for (size_t q = 0; q < Q; ++q) cp.gap[q] = q < k ? -1.0 : 1.0;  // P_q(0) = -gap
    nd::ContactLaw law{&cp, 1.0, nullptr, nullptr};
    auto lowrank = nd::make_lowrank_tangent(in.A, *in.A_factor, ND_SOLVER_AUTO,
                                            nd::Structure::SymmetricPositiveDefinite, -1);
    const int reps = k > 400 ? 3 : 9;
    std::vector<double> t_ref, t_warm;
    x.assign(static_cast<size_t>(n), 1.0);
    double t0 = seconds();
    lowrank->solve(law, kappa, U.data(), true, x.data());  // columns and G
    const double t_first = seconds() - t0;
    for (int r = 0; r < reps; ++r) {
      x.assign(static_cast<size_t>(n), 1.0);
      t0 = seconds();
      refactor->solve(law, kappa, U.data(), true, x.data());
      t_ref.push_back(seconds() - t0);
      x.assign(static_cast<size_t>(n), 1.0);
      t0 = seconds();
      lowrank->solve(law, kappa, U.data(), true, x.data());
      t_warm.push_back(seconds() - t0);
    }
    // a new active set over cached columns, as when one point comes or goes
    // in a Newton iteration: point 0 leaves and point k joins (G rebuilt,
    // the entries of the k - 1 others kept)
    std::vector<double> t_new;
    {
      const std::vector<double> saved = cp.gap;
      for (int r = 0; r < reps; ++r) {
        cp.gap[0] = r % 2 ? -1.0 : 1.0;
        if (k < Q) cp.gap[k] = r % 2 ? 1.0 : -1.0;
        x.assign(static_cast<size_t>(n), 1.0);
        t0 = seconds();
        lowrank->solve(law, kappa, U.data(), true, x.data());
        t_new.push_back(seconds() - t0);
      }
      cp.gap = saved;
    }
    // the two-solve variant (x = A^{-1}(x - B w)), columns cached, same set, back to back
    auto two = nd::make_lowrank_tangent(in.A, *in.A_factor, ND_SOLVER_AUTO,
                                        nd::Structure::SymmetricPositiveDefinite, -1, 0);
    std::vector<double> t_two, t_one;
    x.assign(static_cast<size_t>(n), 1.0);
    two->solve(law, kappa, U.data(), true, x.data());
    for (int r = 0; r < reps; ++r) {
      x.assign(static_cast<size_t>(n), 1.0);
      t0 = seconds();
      two->solve(law, kappa, U.data(), true, x.data());
      t_two.push_back(seconds() - t0);
      x.assign(static_cast<size_t>(n), 1.0);
      t0 = seconds();
      lowrank->solve(law, kappa, U.data(), true, x.data());
      t_one.push_back(seconds() - t0);
    }
    const double columns_cost = std::max(0.0, t_first - median(t_warm));
    std::printf("%d,%s,%d,%lld,%zu,%s,%zu,%.6f,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f\n", dim,
                std::strrchr(mesh, '/') ? std::strrchr(mesh, '/') + 1 : mesh, degree, static_cast<long long>(n), Q,
                threads(), k, 1e3 * fl, median(t_ref) / fl, median(t_warm) / fl, median(t_new) / fl,
                columns_cost / fl / static_cast<double>(k), median(t_one) / fl, median(t_two) / fl);
    std::fflush(stdout);
  }
  nd_problem_destroy(&p);
  return 0;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc >= 5 && !std::strcmp(argv[1], "run"))
    return run(std::atoi(argv[2]), argv[3], std::atoi(argv[4]), argc > 5 ? std::atof(argv[5]) : 32.0);
  if (argc == 5 && !std::strcmp(argv[1], "crossover"))
    return crossover(std::atoi(argv[2]), argv[3], std::atoi(argv[4]));
  std::fprintf(stderr, "usage: %s run DIM MESH DEGREE [T] | crossover DIM MESH DEGREE\n", argv[0]);
  return 2;
}
