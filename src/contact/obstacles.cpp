#include "contact/obstacles.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "common/error.hpp"

namespace nd {

double length(const double *v, int dim) {
  double big = 0;
  for (int k = 0; k < dim; ++k) big = std::max(big, std::fabs(v[k]));
  if (!(big > 0)) return big;
  double s = 0;
  for (int k = 0; k < dim; ++k) s += (v[k] / big) * (v[k] / big);
  return big * std::sqrt(s);
}

void obstacle_distance(const Shape &s, const Pose &pose, int dim, double t, const double *x, double &d, double *nu) {
  // R is dim x dim in the upper-left block of the 3x3
  double local[3] = {0, 0, 0}, nl[3] = {0, 0, 0};
  for (int i = 0; i < dim; ++i)
    for (int k = 0; k < dim; ++k) local[i] += pose.R[k * 3 + i] * (x[k] - pose.t[k]);
  s.distance(t, local, d, nl);
  for (int i = 0; i < dim; ++i) {
    nu[i] = 0;
    for (int k = 0; k < dim; ++k) nu[i] += pose.R[i * 3 + k] * nl[k];
  }
}

std::vector<int> contact_regions(const std::vector<ContactPlane> &planes, const std::vector<Obstacle> &obstacles,
                                 const std::vector<ContactPair> &pairs) {
  std::vector<int> r;
  for (const ContactPlane &pl : planes) r.push_back(pl.region);
  for (const Obstacle &o : obstacles)
    if (std::find(r.begin(), r.end(), o.region) == r.end()) r.push_back(o.region);
  for (const ContactPair &p : pairs)
    if (std::find(r.begin(), r.end(), p.slave) == r.end()) r.push_back(p.slave);
  return r;
}

std::vector<int> contact_node_regions(const std::vector<ContactPlane> &planes, const std::vector<Obstacle> &obstacles,
                                      const std::vector<ContactPair> &pairs) {
  std::vector<int> r = contact_regions(planes, obstacles, pairs);
  for (const ContactPair &p : pairs)
    if (std::find(r.begin(), r.end(), p.master) == r.end()) r.push_back(p.master);
  return r;
}

int pair_of(int region, const std::vector<ContactPair> &pairs) {
  for (size_t i = 0; i < pairs.size(); ++i)
    if (pairs[i].slave == region) return static_cast<int>(i);
  return -1;
}

bool curved_region(int region, const std::vector<Obstacle> &obstacles) {
  return std::any_of(obstacles.begin(), obstacles.end(), [&](const Obstacle &o) { return o.region == region; });
}

std::vector<double> positions(const std::vector<ContactPlane> &planes, const std::vector<Obstacle> &obstacles) {
  std::vector<double> at;
  for (const ContactPlane &pl : planes) at.insert(at.end(), pl.point, pl.point + 3);
  for (const Obstacle &o : obstacles) {
    at.insert(at.end(), o.pose.R, o.pose.R + 9);
    at.insert(at.end(), o.pose.t, o.pose.t + 3);
  }
  return at;
}

void place(std::vector<ContactPlane> &planes, std::vector<Obstacle> &obstacles, const std::vector<double> &at) {
  if (at.size() != 3 * planes.size() + Pose::kValues * obstacles.size())
    fail(ND_ERR_INTERNAL, "the obstacles' positions do not match the obstacles");
  size_t k = 0;
  for (ContactPlane &pl : planes)
    for (double &x : pl.point) x = at[k++];
  for (Obstacle &o : obstacles) {
    for (double &x : o.pose.R) x = at[k++];
    for (double &x : o.pose.t) x = at[k++];
  }
}

namespace {
// the region's obstacle `which` (-1: its plane) at y
void distance_of(int which, int region, const std::vector<ContactPlane> &planes, const std::vector<Obstacle> &obstacles,
                 int dim, double t, const double *y, double &d, double *nu) {
  if (which < 0) {
    for (const ContactPlane &pl : planes)
      if (pl.region == region) return plane_distance(pl.point, pl.normal, dim, y, d, nu);
    fail(ND_ERR_INTERNAL, "a contact point's plane is missing");
  }
  const Obstacle &o = obstacles[static_cast<size_t>(which)];
  obstacle_distance(*o.shape, o.pose, dim, t, y, d, nu);
}
}  // namespace

Nearest nearest(int region, const std::vector<ContactPlane> &planes, const std::vector<Obstacle> &obstacles, int dim,
                double t, const double *y) {
  Nearest best;
  bool any = false;
  for (const ContactPlane &pl : planes)
    if (pl.region == region) {
      distance_of(-1, region, planes, obstacles, dim, t, y, best.d, best.nu);
      any = true;
    }
  for (size_t i = 0; i < obstacles.size(); ++i) {
    if (obstacles[i].region != region) continue;
    Nearest n;
    n.which = static_cast<int>(i);
    distance_of(n.which, region, planes, obstacles, dim, t, y, n.d, n.nu);
    // the smallest signed distance acts (the first of equals)
    if (!any || n.d < best.d) best = n;
    any = true;
  }
  if (!any) fail(ND_ERR_INTERNAL, "a contact region without an obstacle");
  return best;
}

void displacement_at(const Space &sp, const DofMap &dofs, const ContactPoints &cp, size_t q, const double *U,
                     double *u) {
  const int64_t cell = sp.mesh->boundary[cp.facet[q]].cell;
  const int d = sp.dim, nb = sp.basis_of(cell).n, stride = sp.stride;  // (cp.phi: stride values a point)
  const int64_t *nodes = sp.nodes_of(cell);
  for (int c = 0; c < d; ++c) u[c] = 0;
  for (int i = 0; i < nb; ++i)
    for (int c = 0; c < d; ++c) {
      const int64_t r = dofs.free[nodes[i] * d + c];
      if (r >= 0) u[c] += cp.phi[q * stride + i] * U[r];
    }
}

StepGeometry step_geometry(const Space &sp, const DofMap &dofs, const ContactPoints &cp, const StepPlaces &now,
                           const StepPlaces &before, const std::vector<double> &U, const std::vector<double> &frozen,
                           const std::vector<double> &plane_gap, const std::vector<double> &plane_gap_old,
                           bool may_refresh) {
  const int d = sp.dim;
  const double cos_turn = std::cos(kNormalTurn), cos_pair_turn = std::cos(kPairTurn);
  StepGeometry g;
  g.gap = plane_gap;
  g.gap_old = plane_gap_old.empty() ? plane_gap : plane_gap_old;
  g.normal = frozen;
  const std::vector<ContactPair> none;
  const std::vector<ContactPair> &pairs = now.pairs ? *now.pairs : none;
  if (!pairs.empty()) {
    if (!now.pairing || now.pairing->size() != kPairingValues * cp.size())
      fail(ND_ERR_INTERNAL, "a pair's points without their pairings");
    g.pairing = *now.pairing;
  }
  // each pair's master surface where U^n places it (built when first needed)
  std::vector<std::unique_ptr<MasterSurface>> surfaces(pairs.size());
  struct Seen {
    Nearest n;
    Projection p;  // a pair's point: where it lands on the master surface
    double u[3], y[3], c;
    bool near;
    bool pair = false, far = false;  // a pair's point; beyond the search's reach (kPairReach)
  };
  std::vector<Seen> seen(cp.size());
  bool turned = false;  // a near point's normal turned past delta (or a pair's point slid off its facet)
  for (size_t q = 0; q < cp.size(); ++q) {
    if (cp.plane[q] >= 0) continue;  // a plane region's point: its closed form
    Seen &e = seen[q];
    displacement_at(sp, dofs, cp, q, U.data(), e.u);
    for (int k = 0; k < 3; ++k) e.y[k] = k < d ? cp.x[q * d + k] + e.u[k] : 0;
    const int pair = pairs.empty() ? -1 : pair_of(cp.region[q], pairs);
    double c_held = 1;  // a pair's point: its paired facet's normal now against the frozen one
    bool slid = false;
    if (pair >= 0) {
      auto &surface = surfaces[static_cast<size_t>(pair)];
      if (!surface) surface = std::make_unique<MasterSurface>(sp, dofs, pairs[pair].master, U.data());
      e.pair = true;
      const double reach = kPairReach * surface->bucket();
      const int64_t held_facet = static_cast<int64_t>(g.pairing[q * kPairingValues]);
      const OwnFacet own{cp.facet[q], cp.h[q]};
      e.p = surface->project(e.y, reach, held_facet, pairs[pair].slave == pairs[pair].master ? &own : nullptr);
      e.far = e.p.facet < 0;
      if (e.far) {  // nothing within reach: the gap's lower bound, along the frozen normal
        e.n.d = reach;
        std::copy_n(&g.normal[q * 3], 3, e.n.nu);
      } else {
        e.n.d = e.p.d;
        std::copy_n(e.p.nu, 3, e.n.nu);
      }
      // (the paired facet, not the nearest: a point over an edge between two
      // facets would otherwise see the edge's angle as a turn at every step)
      if (held_facet < 0) {
        slid = !e.far;  // a region's own point not paired yet (pairing.hpp, OwnFacet), with a facet in reach now
      } else {
        const Projection held = surface->on_facet(held_facet, e.y);
        slid = beyond_facet(sp.mesh->facet_size(), held.bary, kPairSlack);
        c_held = 0;
        for (int k = 0; k < d; ++k) c_held += held.nu[k] * g.normal[q * 3 + k];
      }
    } else {
      e.n = nearest(cp.region[q], now.planes, now.obstacles, d, now.t, e.y);
    }
    e.c = 0;
    for (int k = 0; k < d; ++k) e.c += e.n.nu[k] * g.normal[q * 3 + k];
    // near: within kNearCells cells of the owning cell's size (a measure of
    // the relative position alone: a Galilean change of frame keeps it)
    e.near = e.n.d <= kNearCells * cp.h[q];
    const bool turning = pair >= 0 ? !(c_held >= cos_pair_turn) : !(e.c >= cos_turn);
    if (e.near && (turning || slid)) turned = true;
  }
  for (size_t q = 0; q < cp.size(); ++q) {
    if (cp.plane[q] >= 0) continue;
    Seen &e = seen[q];
    double *nf = &g.normal[q * 3];
    const bool paired = e.pair;
    double *pq = paired ? &g.pairing[q * kPairingValues] : nullptr;
    const bool moved = paired && !e.far &&
                       (pq[0] != static_cast<double>(e.p.facet) || !std::equal(pq + 1, pq + kPairingValues, e.p.bary));
    // once the operators are made again, every point takes its normal now
    // (not only the near ones past delta): the next refresh is then as far
    // off as it can be (a pair's point out of reach keeps its own)
    if (may_refresh && turned && !e.far && (!std::equal(nf, nf + d, e.n.nu) || moved)) {
      for (int k = 0; k < d; ++k) nf[k] = e.n.nu[k];
      if (paired) {
        pq[0] = static_cast<double>(e.p.facet);
        std::copy_n(e.p.bary, kPairingValues - 1, pq + 1);
      }
      e.c = 1;
      ++g.refreshed;
    }
    // a far point's normal may have turned more: its gap is then measured
    // along nu as if within delta (<= the distance along n_q: conservative)
    const double cc = std::max(e.c, paired ? cos_pair_turn : cos_turn);
    double un = 0;  // n_q.u_q = -nu_f.u_q (a pair's: of the slave's motion relative to the paired point's)
    double rel[3] = {e.u[0], e.u[1], e.u[2]};
    if (paired && pq[0] >= 0) {  // (not paired yet: its rows have no master side)
      double um[3];
      counterpart_displacement(sp, dofs, static_cast<int64_t>(pq[0]), pq + 1, U.data(), um);
      for (int k = 0; k < d; ++k) rel[k] -= um[k];
    }
    for (int k = 0; k < d; ++k) un -= nf[k] * rel[k];
    g.gap[q] = e.n.d / cc + un;
    if (paired) {
      g.gap_old[q] = g.gap[q];  // the master moves with U alone
      continue;
    }
    double d_old = 0, nu_old[3];
    distance_of(e.n.which, cp.region[q], before.planes, before.obstacles, d, before.t, e.y, d_old, nu_old);
    g.gap_old[q] = d_old / cc + un;
  }
  return g;
}

}  // namespace nd
