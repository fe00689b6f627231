// Benchmark (not a test): the 2D disk or 3D ball of docs/design.md §7, one
// configuration per process so that the peak memory is its own. Prints one
// CSV row (the header: disk_bench --header): the setup time (the scene and
// the state at t = 0: the mesh read, the operators assembled), the first
// step (the ordering and factorization of c M + K_Theta, the first solve), the median step of each kind (free flight:
// no contact before or after, solved; predicted: a free-flight step that is
// its predictor, no solve (fast/predictor_check.hpp); impact: the first
// step with contact; contact: contact before and after), Newton
// iterations, the physical floor of a step
// (one solve with the cached factor of c M + K_Theta, timed in the same run)
// and each median as a ratio to it, the pass a step makes over M, K and the
// contact points for its new state (compute_products: the next right-hand
// side, the energy, P_q), timed alone on the last state, nnz(L) of CHOLMOD's analysis of A
// (what the library's CHOLMOD backend computes), peak memory (RSS high-water
// mark), and the work of the tangent factor's rank-one modifications in a
// contact step (ND_STAT_FACTOR_MODIFIED_ENTRIES, median over the contact
// steps; the updated factor of 3D, none in 2D) with its cost as a ratio to the
// floor, from the time an entry takes in the same process (as many of the
// lowest contact points' columns as a contact step modifies, median, updated
// then downdated on a factor of A, 5 times, the fastest). The solved free-flight steps are those of the run and 20 more
// timed after it from the state of its first step with the predictor off
// (Problem::set_predicted_steps): what a free-flight step of a deformed body
// costs, where a rigid fall is predicted. Then the floor again, a solve
// timed right after each of 20 more such steps (median), and the free-flight
// median as a ratio to it. With HISTORY, writes t, E, contact force, Newton iterations and the
// step's time per step, to compare with another code (bench/getfem_drop.py).
//   disk_bench DIM MESH DEGREE TAU T SOLVER [SCHEME [HISTORY]]
//   SCHEME: hybrid (default) | newmark (Newmark(1/4, 1/2))
// ND_BENCH_BLAS_LIMIT=N in the environment: nd_set_blas_threads(N) first (the
// column blas_threads then reads "unlimited" for 0 without OPENBLAS_NUM_THREADS).
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <vector>

#include "capi/handles.hpp"
#include "linalg/backends.hpp"
#include "linalg/blas_threads.hpp"
#include "linalg/updatable_cholesky.hpp"
#include "solve/contact_law.hpp"
#include "monitor/energies.hpp"
#include "drop_scene.h"
#include "timing.hpp"

using ndbench::median;
using ndbench::seconds;

namespace {

const char *kHeader =
    "dim,mesh,degree,scheme,unknowns,nnz_L,steps,solver,blas_threads,setup_s,first_step_s,loop_s,floor_ms,"
    "free_steps,free_median_ms,impact_steps,impact_median_ms,contact_steps,contact_median_ms,"
    "newton_per_contact_step,contact_per_newton_ms,free_over_floor,impact_over_floor,contact_over_floor,"
    "contact_per_newton_over_floor,peak_rss_mb,pass_ms,pass_over_floor,predicted_steps,predicted_median_ms,"
    "predicted_over_floor,modified_entries_per_contact_step,modify_ns_per_entry,modify_over_floor,"
    "floor_after_step_ms,free_over_floor_after_step";

// nnz(L) of the library's CHOLMOD analysis of A's pattern (its ordering);
// 0 if the analysis fails.
long long nnz_L(const nd::Csr &A) {
  try {
    return static_cast<long long>(nd::cholmod_factor_nonzeros(A));
  } catch (const nd::Error &) {
    return 0;
  }
}

double get(nd_problem p, int key) {
  double x = 0;
  nd_get_scalar(p, key, &x);
  return x;
}

// ns per entry of a rank-one modification of a factor of A (the updated
// tangent's kernel): the k lowest (closest to the plane) contact points'
// columns p_q, each times sqrt(w_q / gamma_q), updated then
// downdated 5 times, the fastest; 0 where the factor is not CHOLMOD's
double modify_ns_per_entry(const nd::Integrator &in, const nd::ContactPoints &cp, int dim, size_t k) {
  if (cp.size() == 0 || k == 0) return 0;
  std::vector<size_t> order(cp.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return cp.x[a * dim + dim - 1] < cp.x[b * dim + dim - 1]; });
  nd::SparseColumns C;
  C.ptr.assign(1, 0);
  for (size_t j = 0; j < std::min(k, order.size()); ++j) {
    const size_t q = order[j];
    nd::append_p(cp, q, std::sqrt(cp.w[q] / cp.gamma[q]), C.idx, C.val);
    C.ptr.push_back(static_cast<int64_t>(C.idx.size()));
  }
  try {
    nd::UpdatableCholesky f(in.A, nullptr, in.A_factor.get());
    if (!f.start_from(*in.A_factor)) f.factor(in.A);
    double best = 0;
    for (int r = 0; r < 5; ++r) {
      const int64_t before = f.modified_entries();
      const double t0 = seconds();
      if (!f.modify(true, C) || !f.modify(false, C)) return 0;
      const double ns = 1e9 * (seconds() - t0) / static_cast<double>(f.modified_entries() - before);
      if (r == 0 || ns < best) best = ns;
    }
    return best;
  } catch (const nd::Error &) {
    return 0;
  }
}

}  // namespace

int main(int argc, char **argv) {
  if (argc == 2 && !std::strcmp(argv[1], "--header")) {
    std::puts(kHeader);
    return 0;
  }
  if (argc < 7 || argc > 9) {
    std::fprintf(stderr, "usage: %s DIM MESH DEGREE TAU T SOLVER [hybrid|newmark [HISTORY.csv]] | --header\n",
                 argv[0]);
    return 2;
  }
  const int dim = std::atoi(argv[1]), degree = std::atoi(argv[3]), solver = std::atoi(argv[6]);
  const double tau = std::atof(argv[4]), T = std::atof(argv[5]);
  const char *scheme_name = argc > 7 ? argv[7] : "hybrid";
  const bool newmark = !std::strcmp(scheme_name, "newmark");
  if (!newmark && std::strcmp(scheme_name, "hybrid")) {
    std::fprintf(stderr, "unknown scheme %s\n", scheme_name);
    return 2;
  }
  const double newmark_params[2] = {0.25, 0.5};
  FILE *history = nullptr;
  if (argc > 8 && !(history = std::fopen(argv[8], "w"))) {
    std::perror(argv[8]);
    return 1;
  }
  const char *limit = std::getenv("ND_BENCH_BLAS_LIMIT");
  if (limit && nd_set_blas_threads(std::atoi(limit)) != ND_OK) {
    std::fprintf(stderr, "%s\n", nd_last_error());
    return 1;
  }
  nd_problem p = nullptr;
  double t0 = seconds();
  if (drop_scene_create(dim, argv[2], degree, newmark ? ND_SCHEME_NEWMARK : ND_SCHEME_HYBRID,
                        newmark ? newmark_params : nullptr, 1.0, 1e-3, tau, solver, &p) != ND_OK) {
    std::fprintf(stderr, "%s\n", nd_last_error());
    return 1;
  }
  // the state at t = 0, which assembles the operators (M, K, the contact
  // points): part of the setup, with or without a history to write (else
  // the history's query would make it outside every timer)
  const double E0 = get(p, ND_ENERGY_MECHANICAL), force0 = get(p, ND_CONTACT_FORCE);
  const double setup = seconds() - t0;
  const int steps = static_cast<int>(T / tau + 0.5);
  std::vector<double> free_flight, predicted, impact, contact, per_newton, modified, columns;
  std::vector<unsigned char> after_first;  // the state after the first step
  double newton_contact = 0, first = 0, loop = 0;
  if (history) std::fprintf(history, "t,E,contact_force,newton,step_s\n%.10g,%.12g,%.12g,0,0\n", 0.0, E0, force0);
  double force_before = 0, entries_before = get(p, ND_STAT_FACTOR_MODIFIED_ENTRIES),
         modifications_before = get(p, ND_STAT_FACTOR_MODIFICATIONS);
  for (int k = 0; k < steps; ++k) {
    t0 = seconds();
    if (nd_step(p) != ND_OK) {
      std::fprintf(stderr, "%s\n", nd_last_error());
      return 1;
    }
    const double dt = seconds() - t0;
    loop += dt;
    const double entries = get(p, ND_STAT_FACTOR_MODIFIED_ENTRIES) - entries_before;
    const double modifications = get(p, ND_STAT_FACTOR_MODIFICATIONS) - modifications_before;
    entries_before += entries, modifications_before += modifications;
    const double it = get(p, ND_NEWTON_ITERATIONS), force = get(p, ND_CONTACT_FORCE);
    if (k == 0) {
      first = dt;  // includes the ordering and factorization of c M + K_Theta
      int64_t size = 0;
      nd_problem_get_state_size(p, &size);
      after_first.resize(static_cast<size_t>(size));
      nd_problem_save_state(p, size, after_first.data());
    } else if (force_before == 0 && force == 0) {
      (it == 0 ? predicted : free_flight).push_back(dt);
    } else if (force_before == 0) {
      impact.push_back(dt);
    } else if (force > 0) {
      contact.push_back(dt);
      modified.push_back(entries);
      columns.push_back(modifications);
      per_newton.push_back(dt / it);
      newton_contact += it;
    }  // release steps (contact before, none after) are few: not reported
    force_before = force;
    if (history)
      std::fprintf(history, "%.10g,%.12g,%.12g,%.0f,%.9f\n", get(p, ND_TIME), get(p, ND_ENERGY_MECHANICAL), force,
                   it, dt);
  }
  if (history) std::fclose(history);
  // the floor: one forward/backward solve with the cached factor
  const nd::Integrator *so = p->problem.integrator();
  // (each solve from the same right-hand side: solved again and again, x
  // would shrink by about 1e-2 a solve on disk_h1 P2, towards subnormal numbers)
  const std::vector<double> ones(static_cast<size_t>(so->A.n), 1.0);
  std::vector<double> x = ones, floor_times;
  nd::BlasThreadScope blas;  // the library's BLAS policy, as inside its calls
  for (int r = 0; r < 31; ++r) {
    x = ones;
    t0 = seconds();
    so->A_factor->solve(x.data());
    floor_times.push_back(seconds() - t0);
  }
  const double fl = median(floor_times);
  // the new state's pass (M U, M V, M A, K U, the energy's sums, P_q, u_n - g0)
  const nd::Discretization &disc = p->problem.discretization();
  nd::State state = p->problem.current_state();
  nd::Products products;
  std::vector<double> pass_times;
  for (int r = 0; r < 31; ++r) {
    t0 = seconds();
    nd::compute_products(disc, state, products);
    pass_times.push_back(seconds() - t0);
  }
  const double pass = median(pass_times);
  // 20 solved free-flight steps from the state after the first step (the
  // predictor off), after_each(its time) after each; false: a step failed
  p->problem.set_predicted_steps(false);
  auto solved_free_steps = [&](auto &&after_each) {
    if (nd_problem_load_state(p, static_cast<int64_t>(after_first.size()), after_first.data()) != ND_OK) return false;
    for (int k = 0; k < 20 && k + 1 < steps; ++k) {
      const double start = seconds();
      if (nd_step(p) != ND_OK) return false;
      const double dt = seconds() - start;
      if (get(p, ND_CONTACT_FORCE) == 0 && get(p, ND_NEWTON_ITERATIONS) >= 1) after_each(dt);
    }
    return true;
  };
  // the floor right after such a step: do the step's own passes (over M, K
  // and the contact points) leave less of the factor in cache than the
  // back-to-back solves above? (docs/performance.md, "The floor after a
  // step".) In a second series: between the timed steps it
  // would warm their solves
  std::vector<double> floor_after_step;
  const bool stepped = solved_free_steps([&](double dt) { free_flight.push_back(dt); }) &&
                       solved_free_steps([&](double) {
                         x = ones;
                         t0 = seconds();  // (the BLAS policy of the library's calls: `blas` above)
                         so->A_factor->solve(x.data());
                         floor_after_step.push_back(seconds() - t0);
                       });
  if (!stepped) {
    std::fprintf(stderr, "%s\n", nd_last_error());
    return 1;
  }
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  const double peak_mb = ru.ru_maxrss / 1024.0;  // before the analysis below allocates
  // (the modifications' time after it: their factor is a copy of A's, not the run's)
  const double entries_step = median(modified);
  const size_t columns_step = static_cast<size_t>(std::max(1.0, median(columns)));
  const double entry_ns = entries_step > 0 ? modify_ns_per_entry(*so, disc.contact, dim, columns_step) : 0;
  const char *threads = std::getenv("OPENBLAS_NUM_THREADS");
  if (!threads && limit && std::atoi(limit) == 0) threads = "unlimited";
  const char *mesh = std::strrchr(argv[2], '/') ? std::strrchr(argv[2], '/') + 1 : argv[2];
  std::printf("%d,%s,%d,%s,%lld,%lld,%d,%s,%s,%.6f,%.6f,%.6f,%.6f,%zu,%.6f,%zu,%.6f,%zu,%.6f,%.4f,%.6f,%.3f,%.3f,%.3f,"
              "%.3f,%.1f,%.6f,%.3f,%zu,%.6f,%.3f,%.0f,%.4f,%.3f,%.6f,%.3f\n",
              dim, mesh, degree, scheme_name, static_cast<long long>(so->A.n), nnz_L(so->A), steps,
              so->A_factor->name(), threads ? threads : "default", setup, first, loop, 1e3 * fl, free_flight.size(),
              1e3 * median(free_flight), impact.size(), 1e3 * median(impact), contact.size(), 1e3 * median(contact),
              contact.empty() ? 0.0 : newton_contact / static_cast<double>(contact.size()), 1e3 * median(per_newton),
              median(free_flight) / fl, median(impact) / fl, median(contact) / fl, median(per_newton) / fl, peak_mb,
              1e3 * pass, pass / fl, predicted.size(), 1e3 * median(predicted), median(predicted) / fl, entries_step,
              entry_ns, 1e-9 * entry_ns * entries_step / fl, 1e3 * median(floor_after_step),
              floor_after_step.empty() ? 0.0 : median(free_flight) / median(floor_after_step));
  nd_problem_destroy(&p);
  return 0;
}
