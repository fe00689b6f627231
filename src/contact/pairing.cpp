#include "contact/pairing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "contact/obstacle.hpp"
#include "contact/obstacles.hpp"
#include "mesh/cell_shape.hpp"

namespace nd {
namespace {

double dot(const double *a, const double *b, int d) {
  double s = 0;
  for (int k = 0; k < d; ++k) s += a[k] * b[k];
  return s;
}

// where vertex v is: x + u (u the free DOFs' values; clamped: 0)
void moved(const Space &sp, const DofMap &dofs, int64_t v, const double *U, double *x) {
  const int d = sp.dim;
  for (int c = 0; c < d; ++c) {
    x[c] = sp.mesh->x(v)[c];
    const int64_t r = U ? dofs.free[v * d + c] : -1;  // (a vertex is node v)
    if (r >= 0) x[c] += U[r];
  }
}

// the parameter of y's projection on the line a + s (b - a), |b - a| > 0
double along(const double *a, const double *b, const double *y, int d) {
  double t[3], w[3];
  for (int k = 0; k < d; ++k) t[k] = b[k] - a[k], w[k] = y[k] - a[k];
  const double tt = dot(t, t, d);
  return tt > 0 ? dot(w, t, d) / tt : 0.0;
}

// z = the facet's point of coordinates c (its n vertices x, d values each)
void facet_point(const double (&x)[4][3], int n, const double *c, int d, double *z) {
  double w[4];
  facet_weights(n, c, w);
  for (int k = 0; k < d; ++k) {
    double zk = 0;
    for (int i = 0; i < n; ++i) zk += w[i] * x[i][k];
    z[k] = zk;
  }
}

// |y - z|^2, z the facet's point of coordinates c
double squared_distance(const double (&x)[4][3], int n, const double *c, const double *y, int d) {
  double z[3], z2 = 0;
  facet_point(x, n, c, d, z);
  for (int k = 0; k < d; ++k) z2 += (y[k] - z[k]) * (y[k] - z[k]);
  return z2;
}

// x_s and x_t of a quadrilateral face's bilinear map at (s, t)
void face_tangents(const double (&x)[4][3], double s, double t, double *xs, double *xt) {
  for (int k = 0; k < 3; ++k) {
    xs[k] = (1 - t) * (x[1][k] - x[0][k]) + t * (x[2][k] - x[3][k]);
    xt[k] = (1 - s) * (x[3][k] - x[0][k]) + s * (x[2][k] - x[1][k]);
  }
}

// The stationary point (s, t) of |x(s, t) - y|^2 on a quadrilateral face's
// bilinear extension: Newton from the centre (Gauss-Newton where the
// Hessian is not positive definite: far from a warped face). A flat face's
// (x_st in its plane, normal to y - x at the answer) converges
// quadratically, a parallelogram's in one step. The iterates stay within
// one facet beyond each edge (farther is slid off anyway: kPairSlack);
// false when it did not converge.
bool face_parameters(const double (&x)[4][3], const double *y, double &s, double &t) {
  double xst[3];
  for (int k = 0; k < 3; ++k) xst[k] = x[0][k] - x[1][k] + x[2][k] - x[3][k];
  s = t = 0.5;
  for (int it = 0; it < 32; ++it) {
    double z[3], xs[3], xt[3], r[3];
    const double c[2] = {s, t};
    facet_point(x, 4, c, 3, z);
    face_tangents(x, s, t, xs, xt);
    for (int k = 0; k < 3; ++k) r[k] = z[k] - y[k];
    const double g1 = dot(xs, r, 3), g2 = dot(xt, r, 3), h11 = dot(xs, xs, 3), h22 = dot(xt, xt, 3);
    double h12 = dot(xs, xt, 3) + dot(xst, r, 3), det = h11 * h22 - h12 * h12;
    if (!(det > 0)) h12 = dot(xs, xt, 3), det = h11 * h22 - h12 * h12;
    if (!(det > 0) || !std::isfinite(det)) return false;
    const double ds = -(h22 * g1 - h12 * g2) / det, dt = -(h11 * g2 - h12 * g1) / det;
    if (!std::isfinite(ds) || !std::isfinite(dt)) return false;  // (y not finite: s and t stay finite)
    s = std::clamp(s + ds, -1.0, 2.0), t = std::clamp(t + dt, -1.0, 2.0);
    // (quadratic convergence: the error is then below round-off)
    if (std::abs(ds) + std::abs(dt) <= 1e-10) return true;
  }
  return false;
}

}  // namespace

void facet_weights(int n, const double *c, double *w) {
  if (n == 4) {  // a hexahedron's face: bilinear in (s, t), its vertices turning
    const double s = c[0], t = c[1];
    w[0] = (1 - s) * (1 - t), w[1] = s * (1 - t), w[2] = s * t, w[3] = (1 - s) * t;
    return;
  }
  for (int i = 0; i < n; ++i) w[i] = c[i];
}

bool beyond_facet(int n, const double *c, double slack) {
  if (n == 4) return c[0] < -slack || c[0] > 1 + slack || c[1] < -slack || c[1] > 1 + slack;
  bool beyond = false;
  for (int k = 0; k < n; ++k) beyond = beyond || c[k] < -slack;
  return beyond;
}

bool facet_normal(const Space &sp, const DofMap &dofs, int64_t b, const double *U, double *nu) {
  const Mesh &m = *sp.mesh;
  const int d = sp.dim;
  const Facet &facet = m.boundary[b];
  const std::array<int64_t, 4> v = m.facet_vertices(facet);
  double x[4][3] = {};
  for (int i = 0; i < m.facet_size(); ++i) moved(sp, dofs, v[i], U, x[i]);
  // across the facet, away from the cell's centre
  double centre[3] = {0, 0, 0}, c[3];
  const int nv = m.cell_vertices(facet.cell);
  for (int i = 0; i < nv; ++i) {
    moved(sp, dofs, m.cell(facet.cell)[i], U, c);
    for (int k = 0; k < d; ++k) centre[k] += c[k] / nv;
  }
  double n[3] = {0, 0, 0};
  if (d == 1) {
    n[0] = 1;
  } else if (d == 2) {
    n[0] = x[1][1] - x[0][1], n[1] = -(x[1][0] - x[0][0]);
  } else {
    // (a hexahedron's face: across its diagonals, its bilinear normal at
    // the centre, the same whichever vertex comes first)
    const bool face = m.facet_size() == 4;
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k)
      e1[k] = face ? x[2][k] - x[0][k] : x[1][k] - x[0][k], e2[k] = face ? x[3][k] - x[1][k] : x[2][k] - x[0][k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  }
  const double len = length(n, d);
  if (!(len > 0) || !std::isfinite(len)) return false;
  double out[3];
  for (int k = 0; k < d; ++k) out[k] = x[0][k] - centre[k];
  const double sign = dot(out, n, d) < 0 ? -1.0 : 1.0;
  for (int k = 0; k < 3; ++k) nu[k] = k < d ? sign * n[k] / len : 0.0;
  return true;
}

MasterSurface::MasterSurface(const Space &sp, const DofMap &dofs, int region, const double *U) : dim_(sp.dim) {
  const Mesh &m = *sp.mesh;
  const int d = dim_;
  auto it = m.regions.find(region);
  if (it == m.regions.end() || it->second.empty())
    fail(ND_ERR_REGION, "the contact pair's master region " + std::to_string(region) + " has no facet");
  where_.assign(m.boundary.size(), -1);
  double lo[3], hi[3], extent = 0, cells = 0;  // (cells: the largest master cell's diameter)
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = 0;
  for (int64_t b : it->second) {
    Moved f{};
    f.facet = b;
    const Facet &facet = m.boundary[b];
    const std::array<int64_t, 4> v = m.facet_vertices(facet);
    f.n = m.facet_size();
    for (int i = 0; i < f.n; ++i) moved(sp, dofs, v[i], U, f.x[i]);
    if (!facet_normal(sp, dofs, b, U, f.nu))
      fail(ND_ERR_DEGENERATE, "a facet of the contact pair's master region " + std::to_string(region) +
                                  " has collapsed (cell " + std::to_string(facet.cell) + ")");
    for (int k = 0; k < d; ++k) {
      f.lo[k] = f.hi[k] = f.x[0][k];
      for (int i = 1; i < f.n; ++i) f.lo[k] = std::min(f.lo[k], f.x[i][k]), f.hi[k] = std::max(f.hi[k], f.x[i][k]);
      extent = std::max(extent, f.hi[k] - f.lo[k]);
      lo[k] = facets_.empty() ? f.lo[k] : std::min(lo[k], f.lo[k]);
      hi[k] = facets_.empty() ? f.hi[k] : std::max(hi[k], f.hi[k]);
    }
    cells = std::max(cells, m.cell_diameter(facet.cell));
    where_[b] = static_cast<int64_t>(facets_.size());
    facets_.push_back(f);
    vertices_.push_back(v);
  }
  // buckets the size of the largest facet (a 1D region's points: of the
  // largest master cell), at most 8 per facet and at least one
  const int64_t n = static_cast<int64_t>(facets_.size());
  cell_ = extent > 0 ? extent : cells;
  for (;;) {
    double total = 1;
    for (int k = 0; k < d; ++k) total *= std::floor((hi[k] - lo[k]) / cell_) + 1;
    if (total <= 8.0 * static_cast<double>(n) + 8) break;
    cell_ *= 2;
  }
  std::copy_n(lo, 3, lo_), std::copy_n(hi, 3, hi_);
  int64_t buckets = 1;
  for (int k = 0; k < 3; ++k) {
    origin_[k] = k < d ? lo[k] : 0;
    counts_[k] = k < d ? static_cast<int64_t>(std::floor((hi[k] - lo[k]) / cell_)) + 1 : 1;
    buckets *= counts_[k];
  }
  // counting sort of (bucket, facet) over the buckets each facet's box meets
  auto range = [&](const Moved &f, int k, int64_t &a, int64_t &b) {
    a = k < d ? std::clamp<int64_t>(static_cast<int64_t>(std::floor((f.lo[k] - origin_[k]) / cell_)), 0, counts_[k] - 1) : 0;
    b = k < d ? std::clamp<int64_t>(static_cast<int64_t>(std::floor((f.hi[k] - origin_[k]) / cell_)), 0, counts_[k] - 1) : 0;
  };
  start_.assign(static_cast<size_t>(buckets + 1), 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int64_t> fill;
    if (pass == 1) {
      for (int64_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
      members_.assign(static_cast<size_t>(start_[buckets]), 0);
      fill.assign(start_.begin(), start_.end() - 1);
    }
    for (int64_t i = 0; i < n; ++i) {
      int64_t a[3], b[3];
      for (int k = 0; k < 3; ++k) range(facets_[i], k, a[k], b[k]);
      for (int64_t z = a[2]; z <= b[2]; ++z)
        for (int64_t y = a[1]; y <= b[1]; ++y)
          for (int64_t x = a[0]; x <= b[0]; ++x) {
            const int64_t bucket = (z * counts_[1] + y) * counts_[0] + x;
            if (pass == 0) ++start_[bucket + 1];
            else members_[fill[bucket]++] = i;
          }
    }
  }
}

Projection MasterSurface::land(const Moved &f, const double *y, bool clamp) const {
  if (f.n == 4) return land_face(f, y, clamp);
  const int d = dim_;
  Projection p;
  p.facet = f.facet;
  for (int k = 0; k < d; ++k) p.nu[k] = f.nu[k];
  double w[3];
  for (int k = 0; k < d; ++k) w[k] = y[k] - f.x[0][k];
  p.d = dot(w, f.nu, d);  // every point of the facet lies in its plane
  if (f.n == 1) {
    p.bary[0] = 1;
  } else if (f.n == 2) {
    double s = along(f.x[0], f.x[1], y, d);
    if (clamp) s = std::clamp(s, 0.0, 1.0);
    p.bary[0] = 1 - s, p.bary[1] = s;
  } else {
    // barycentric coordinates of y's projection on the plane
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) e1[k] = f.x[1][k] - f.x[0][k], e2[k] = f.x[2][k] - f.x[0][k];
    const double a11 = dot(e1, e1, 3), a12 = dot(e1, e2, 3), a22 = dot(e2, e2, 3);
    const double r1 = dot(w, e1, 3), r2 = dot(w, e2, 3), det = a11 * a22 - a12 * a12;
    const double l1 = (a22 * r1 - a12 * r2) / det, l2 = (a11 * r2 - a12 * r1) / det;
    p.bary[0] = 1 - l1 - l2, p.bary[1] = l1, p.bary[2] = l2;
    if (clamp && std::min({p.bary[0], p.bary[1], p.bary[2]}) < 0) {
      // outside: the nearest point is on an edge, the nearest edge's
      double best = std::numeric_limits<double>::infinity();
      for (int e = 0; e < 3; ++e) {
        const int i = e, j = (e + 1) % 3;
        const double s = std::clamp(along(f.x[i], f.x[j], y, 3), 0.0, 1.0);
        double z2 = 0;
        for (int k = 0; k < 3; ++k) {
          const double z = f.x[i][k] + s * (f.x[j][k] - f.x[i][k]) - y[k];
          z2 += z * z;
        }
        if (z2 < best) {
          best = z2;
          p.bary[0] = p.bary[1] = p.bary[2] = 0;
          p.bary[i] = 1 - s, p.bary[j] = s;
        }
      }
    }
  }
  return p;
}

Projection MasterSurface::land_face(const Moved &f, const double *y, bool clamp) const {
  Projection p;
  p.facet = f.facet;
  double s = 0.5, t = 0.5;
  const bool inside = face_parameters(f.x, y, s, t) && s >= 0 && s <= 1 && t >= 0 && t <= 1;
  if (clamp && !inside) {
    // the nearest point is on an edge (straight: a segment), the nearest
    // edge's; (s, t) along edge e from vertex e to e + 1 (or, on a face
    // too warped for the iteration to converge, its last iterate clamped)
    s = std::clamp(s, 0.0, 1.0), t = std::clamp(t, 0.0, 1.0);
    const double last[2] = {s, t};
    double best = squared_distance(f.x, 4, last, y, 3);
    for (int e = 0; e < 4; ++e) {
      const double a = std::clamp(along(f.x[e], f.x[(e + 1) % 4], y, 3), 0.0, 1.0);
      const double c[2] = {e == 0 ? a : e == 1 ? 1 : e == 2 ? 1 - a : 0, e == 0 ? 0 : e == 1 ? a : e == 2 ? 1 : 1 - a};
      const double z2 = squared_distance(f.x, 4, c, y, 3);
      if (z2 < best) best = z2, s = c[0], t = c[1];
    }
  }
  p.bary[0] = s, p.bary[1] = t;
  // the face's normal at z, on the facet normal's side (docs/design.md
  // §10.3: y - z is along it at an inner landing, d the distance)
  double xs[3], xt[3], z[3], n[3];
  face_tangents(f.x, s, t, xs, xt);
  n[0] = xs[1] * xt[2] - xs[2] * xt[1];
  n[1] = xs[2] * xt[0] - xs[0] * xt[2];
  n[2] = xs[0] * xt[1] - xs[1] * xt[0];
  const double len = length(n, 3);
  const double scale = !(len > 0) || !std::isfinite(len) ? 0.0 : dot(n, f.nu, 3) < 0 ? -1 / len : 1 / len;
  for (int k = 0; k < 3; ++k) p.nu[k] = scale != 0 ? scale * n[k] : f.nu[k];  // (a collapsed corner: the facet's)
  facet_point(f.x, 4, p.bary, 3, z);
  for (int k = 0; k < 3; ++k) n[k] = y[k] - z[k];
  p.d = dot(n, p.nu, 3);
  return p;
}

Projection MasterSurface::on_facet(int64_t facet, const double *y) const {
  const int64_t i = facet >= 0 && facet < static_cast<int64_t>(where_.size()) ? where_[facet] : -1;
  if (i < 0) fail(ND_ERR_INTERNAL, "a pairing's facet is not on the master surface");
  return land(facets_[i], y, false);
}

namespace {
// |y - box|^2 (0 inside it)
double box_distance2(const double *lo, const double *hi, const double *y, int d) {
  double s = 0;
  for (int k = 0; k < d; ++k) {
    const double out = std::max({lo[k] - y[k], y[k] - hi[k], 0.0});
    s += out * out;
  }
  return s;
}
}  // namespace

bool MasterSurface::admits(const OwnFacet &own, int64_t i, const Projection &p, const double *y) const {
  const int64_t at = own.facet >= 0 && own.facet < static_cast<int64_t>(where_.size()) ? where_[own.facet] : -1;
  if (at < 0) fail(ND_ERR_INTERNAL, "a point of a region paired with itself is not on its surface");
  const Moved &mine = facets_[at], &f = facets_[i];
  for (int a = 0; a < mine.n; ++a)
    for (int b = 0; b < f.n; ++b)
      if (vertices_[at][a] == vertices_[i][b]) return false;  // its own neighbourhood (its own facet too)
  // facing it: nu_f . (-n_q) >= cos(kSelfFacing), n_q its own facet's outward normal
  static const double cos_facing = std::cos(kSelfFacing);
  if (!(-dot(f.nu, mine.nu, dim_) >= cos_facing && p.d >= -kSelfDepth * own.h)) return false;
  // over the facet (to the slid-off slack): beyond the edge of a side its
  // plane is no surface of the body, and a gap measured to it would push
  // the point's own side at the other's edge
  return !beyond_facet(f.n, land(f, y, false).bary, kPairSlack);
}

Projection MasterSurface::project(const double *y, double within, int64_t hint, const OwnFacet *own) const {
  const int d = dim_;
  // farther than `within` from the facets' box: from every facet
  if (box_distance2(lo_, hi_, y, d) > within * within) return Projection{};
  int64_t at[3] = {0, 0, 0};
  // y's bucket (of y clamped into the grid, which is no farther from any
  // facet), and how far the clamped y is from that bucket's walls
  double wall = std::numeric_limits<double>::infinity();
  for (int k = 0; k < d; ++k) {
    at[k] = static_cast<int64_t>(std::clamp(std::floor((y[k] - origin_[k]) / cell_), 0.0,
                                            static_cast<double>(counts_[k] - 1)));
    const double yc = std::clamp(y[k], origin_[k], origin_[k] + static_cast<double>(counts_[k]) * cell_);
    const double low = origin_[k] + static_cast<double>(at[k]) * cell_;
    wall = std::min({wall, yc - low, low + cell_ - yc});
  }
  wall = std::max(wall, 0.0);
  Projection best;
  double best2 = std::numeric_limits<double>::infinity();
  if (hint >= 0 && hint < static_cast<int64_t>(where_.size()) && where_[hint] >= 0) {
    const Moved &f = facets_[where_[hint]];
    best = land(f, y, true);
    best2 = squared_distance(f.x, f.n, best.bary, y, d);
    if (own && !admits(*own, where_[hint], best, y)) best = Projection{}, best2 = std::numeric_limits<double>::infinity();
  }
  const int64_t most = std::max({counts_[0], counts_[1], counts_[2]});
  // rings of buckets about y's: after ring r every facet not seen is at
  // least r buckets and y's distance to its bucket's walls away
  for (int64_t r = 0; r <= most; ++r) {
    int64_t a[3], b[3];
    for (int k = 0; k < 3; ++k) a[k] = std::max<int64_t>(at[k] - r, 0), b[k] = std::min(at[k] + r, counts_[k] - 1);
    for (int64_t z = a[2]; z <= b[2]; ++z)
      for (int64_t yy = a[1]; yy <= b[1]; ++yy)
        for (int64_t x = a[0]; x <= b[0]; ++x) {
          const int64_t ring = std::max({std::abs(x - at[0]), std::abs(yy - at[1]), std::abs(z - at[2])});
          if (ring != r) continue;
          const int64_t bucket = (z * counts_[1] + yy) * counts_[0] + x;
          for (int64_t e = start_[bucket]; e < start_[bucket + 1]; ++e) {
            const Moved &f = facets_[members_[e]];
            // (no nearer than its box: a facet seen in another bucket, or
            // farther than the nearest so far, costs no projection)
            if (box_distance2(f.lo, f.hi, y, d) > best2) continue;
            const Projection p = land(f, y, true);
            if (own && !admits(*own, members_[e], p, y)) continue;
            const double z2 = squared_distance(f.x, f.n, p.bary, y, d);
            // the first of equals in the facets' order: the same answer
            // whatever order the buckets are visited in
            if (z2 < best2 || (z2 == best2 && p.facet < best.facet)) best = p, best2 = z2;
          }
        }
    // every facet not seen is at least this far: beyond the block of
    // buckets within r of y's
    const double seen = static_cast<double>(r) * cell_ + wall;
    if (best.facet >= 0 && std::sqrt(best2) <= seen) break;
    if (seen >= within) break;
  }
  if (best.facet >= 0 && !(std::sqrt(best2) <= within)) best = Projection{};
  if (best.facet < 0 && !own && !(within < std::numeric_limits<double>::infinity()))
    fail(ND_ERR_INTERNAL, "no facet found on the master surface");
  return best;
}

void facet_point_reference(const Mesh &m, const Facet &f, const double *bary, double *xi) {
  const int d = m.dim;
  for (int k = 0; k < d; ++k) xi[k] = 0;
  if (m.simplicial(f.cell)) {
    // barycentric in the cell: the facet's vertices are the cell's local
    // vertices but f.local, in order; xi_k is vertex k + 1's
    for (int i = 0, j = 0; i <= d; ++i) {
      if (i == f.local) continue;
      if (i > 0) xi[i - 1] = bary[j];
      ++j;
    }
    return;
  }
  // a quadrilateral's edge, a hexahedron's face: the reference square's or
  // cube's (straight, flat) with the same weights of its corners
  const int n = m.facet_size();
  double w[4];
  facet_weights(n, bary, w);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < d; ++k) xi[k] += w[j] * cube::kCorner[cube::facet_vertex(d, f.local, j)][k];
}

void counterpart_displacement(const Space &sp, const DofMap &dofs, int64_t facet, const double *bary, const double *U,
                              double *u) {
  const int d = sp.dim;
  if (facet < 0 || facet >= static_cast<int64_t>(sp.mesh->boundary.size()))
    fail(ND_ERR_INTERNAL, "a pairing's facet is out of range");
  const Facet &f = sp.mesh->boundary[facet];
  double xi[3] = {0, 0, 0};
  facet_point_reference(*sp.mesh, f, bary, xi);
  const int nb = sp.basis_of(f.cell).n;
  std::vector<double> phi(static_cast<size_t>(nb));
  sp.basis_of(f.cell).values(xi, phi.data());
  const int64_t *nodes = sp.nodes_of(f.cell);
  for (int c = 0; c < d; ++c) u[c] = 0;
  for (int i = 0; i < nb; ++i)
    for (int c = 0; c < d; ++c) {
      const int64_t r = dofs.free[nodes[i] * d + c];
      if (r >= 0) u[c] += phi[i] * U[r];
    }
}

}  // namespace nd
