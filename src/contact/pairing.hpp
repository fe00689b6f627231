// Contact between two boundary regions of one problem (docs/design.md §10.3):
// the master region's surface where U places it, and the projection of a
// slave point onto it. Master/slave Nitsche: the slave region carries the
// contact points; each is paired with a point of a master facet, which its
// rows hold (assembly/contact.hpp: append_counterpart), frozen between
// re-pairings as the curved obstacles' normals are (contact/obstacles.hpp).
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "assembly/contact.hpp"
#include "fem/space.hpp"

namespace nd {

// The contact points of region `slave` against the surface of region
// `master` (may be the same region: a body touching itself).
struct ContactPair {
  int slave, master;
};

// A pairing (kPairingValues per point in ContactPoints::pairing, in
// assembly/contact.hpp, and in the state): the master facet (an index into
// Mesh::boundary, as a double: exact below 2^53) and the point's coordinates
// on it, 3 values: a simplex's facet's or a quadrilateral's edge's
// barycentric coordinates (its facet_size() vertices, Mesh::facet_vertices
// order; the rest 0); a hexahedron's face's (4 vertices, turning) its
// bilinear parameters (s, t) in [0, 1]^2, then 0: the point x(s, t) =
// (1-s)(1-t) x_0 + s(1-t) x_1 + s t x_2 + (1-s) t x_3.

// The weights of a facet's n = facet_size() vertices (n values) at the
// point of coordinates c: c itself but on a hexahedron's face
void facet_weights(int n, const double *c, double *w);
// whether a landing of coordinates c is more than `slack` beyond its facet
// (a barycentric coordinate below -slack; s or t outside [-slack, 1 + slack])
bool beyond_facet(int n, const double *c, double slack);

// Where a point lands on the master surface: the nearest point z of the
// nearest facet, the facet's outward unit normal nu there (from the master
// towards the slave side; a hexahedron's bilinear face's at z) and d =
// (y - z).nu, the signed distance to the facet's tangent plane (negative: y
// is inside the master).
struct Projection {
  int64_t facet = -1;
  double bary[3] = {0, 0, 0};  // z's coordinates on the facet (a pairing's)
  double d = 0, nu[3] = {0, 0, 0};
};

// A point of a region paired with itself (a body touching itself, docs/design.md
// §10.3): the boundary facet it lies on and its cell's diameter h. Its search
// takes only the facets of another side of the body facing it: none sharing a
// vertex with its own facet; none whose outward normal turns more than
// kSelfFacing from its own facet's inward one (a right-angled convex corner,
// 90 degrees, is left out with 30 to spare for the turns between pairings);
// none it lies more than kSelfDepth h behind (the body's other side, through
// the body: a penetration that deep is no contact's); none it lands beyond
// by more than the slid-off slack (beyond a side's edge its plane is no
// surface of the body)
struct OwnFacet {
  int64_t facet = -1;
  double h = 0;
};
constexpr double kSelfFacing = 1.0471975511965976;  // pi / 3
constexpr double kSelfDepth = 0.5;

// The facets of a region at the positions x + u (the facets' vertices moved
// by U's vertex values; a P2 facet by its corners: its chord, a Q2 face the
// bilinear face of its 4 corners), with a bucket
// grid for the nearest-facet search: built in O(n log n) for n facets, a
// query O(1) for a point near the surface.
class MasterSurface {
 public:
  // U: the free DOFs' values (null: the reference positions); clamped DOFs
  // do not move (as contact/obstacles.hpp's displacement_at)
  MasterSurface(const Space &sp, const DofMap &dofs, int region, const double *U);
  // The nearest facet to y (dim values) and where y lands on it; with
  // `within`, none (facet -1) when every facet is farther than that from y
  // (the search then stops at that distance)
  // (hint: a facet to try first, e.g. the point's pairing: the same answer,
  // found sooner; own: y is a point of this region's facet own->facet, and
  // only the facets that OwnFacet admits are searched; none admitted within
  // reach: facet -1, also with `within` infinite)
  Projection project(const double *y, double within = std::numeric_limits<double>::infinity(),
                     int64_t hint = -1, const OwnFacet *own = nullptr) const;
  // the size of the search's buckets: the largest facet's extent
  double bucket() const { return cell_; }
  // y's landing on this facet's plane (a hexahedron's face: its bilinear
  // extension), its coordinates not clamped to the facet (how far outside
  // the facet y has slid: beyond_facet)
  Projection on_facet(int64_t facet, const double *y) const;

 private:
  struct Moved {
    int64_t facet;  // into Mesh::boundary
    int n;          // vertices
    double x[4][3];  // their positions
    double nu[3];    // outward unit normal
    double lo[3], hi[3];
  };
  Projection land(const Moved &f, const double *y, bool clamp) const;
  Projection land_face(const Moved &f, const double *y, bool clamp) const;  // (a hexahedron's)
  // whether a point y of facet own->facet may land on facet i (p: where it does)
  bool admits(const OwnFacet &own, int64_t i, const Projection &p, const double *y) const;
  int dim_;
  std::vector<Moved> facets_;
  std::vector<std::array<int64_t, 4>> vertices_;  // facets_[i]'s vertices (Mesh::facet_vertices)
  std::vector<int64_t> where_;  // facet index -> position in facets_ (-1: not of the region)
  // the grid: cells of size `cell_` from `origin_`, `counts_` per axis;
  // bucket b's facets are entries [start_[b], start_[b + 1]) of `members_`
  double origin_[3] = {0, 0, 0}, cell_ = 1;
  double lo_[3] = {0, 0, 0}, hi_[3] = {0, 0, 0};  // the facets' box
  int64_t counts_[3] = {1, 1, 1};
  std::vector<int64_t> start_, members_;
};

// The outward unit normal (3 values, the unused 0) of boundary facet b where
// U places it (null: the reference configuration; a P2 facet by its
// corners); false when the facet has collapsed
bool facet_normal(const Space &sp, const DofMap &dofs, int64_t b, const double *U, double *nu);

// The master cell's reference coordinates (xi, dim values) of the point with
// coordinates `bary` on its boundary facet f (a pairing's).
void facet_point_reference(const Mesh &m, const Facet &f, const double *bary, double *xi);

// u at the paired point (dim values): the master cell's interpolation of U
// (clamped DOFs: zero) at the point of facet `facet` with coordinates `bary`
void counterpart_displacement(const Space &sp, const DofMap &dofs, int64_t facet, const double *bary, const double *U,
                              double *u);

}  // namespace nd
