// The tangent's history (TangentLog, time/state.hpp): its bound, its room
// and its form, which the checkpoint checks (the updated factor,
// fast/tangent_updown.cpp, writes it).
#include <algorithm>
#include <cmath>

#include "solve/tangent_solver.hpp"

namespace nd {

namespace {
// q[0 .. m) increasing in [0, n) and c[0 .. m) finite and positive
bool increasing_points(const int64_t *q, const double *c, int64_t m, int64_t n) {
  for (int64_t j = 0; j < m; ++j) {
    if (q[j] < 0 || q[j] >= n || (j > 0 && q[j] <= q[j - 1])) return false;
    if (!(c[j] > 0) || !std::isfinite(c[j])) return false;
  }
  return true;
}
}  // namespace

bool tangent_log_well_formed(const TangentLog &log, int64_t n_points) {
  const std::vector<int64_t> &i = log.i;
  const std::vector<double> &x = log.x;
  if (i.empty()) return x.empty();
  const int64_t ni = static_cast<int64_t>(i.size()), nx = static_cast<int64_t>(x.size());
  const int64_t nb = i[0], max_updates = updown_max_updates(n_points);
  if (nb < 0 || nb > n_points || nb > ni - 1 || nb > nx) return false;
  if (!increasing_points(i.data() + 1, x.data(), nb, n_points)) return false;
  int64_t at = 1 + nb, xat = nb, updated = 0;
  while (at < ni) {
    const int64_t v = i[at++];
    if (v == 0 || v < -max_updates || v > max_updates) return false;
    const int64_t m = v > 0 ? v : -v;
    if (m > ni - at || m > nx - xat || m > max_updates - updated) return false;
    if (!increasing_points(i.data() + at, x.data() + xat, m, n_points)) return false;
    at += m, xat += m, updated += m;
  }
  return xat == nx;
}

int64_t updown_max_updates(int64_t n_points) { return std::clamp<int64_t>(4 * n_points, 256, 2048); }

void reserve_tangent_log(TangentLog &log, int64_t n_points) {
  const size_t points = static_cast<size_t>(n_points), updates = static_cast<size_t>(updown_max_updates(n_points));
  log.i.reserve(1 + points + 2 * updates);
  log.x.reserve(points + updates);
}

}  // namespace nd
