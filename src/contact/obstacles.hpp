// The obstacles of the contact regions (docs/design.md §10.1): which regions
// have contact points, the acting obstacle at a point (the nearest), and the
// gaps of a step with each point's normal frozen in its rows.
//
// A region with its plane alone keeps the closed form g_q = (x_q - x_o).nu_o
// (contact_gaps, assembly/contact.hpp). A region with added obstacles
// (sphere, cylinder, distance: obstacle_*.cpp) is "curved": at the start of a
// step each point's current position y_q = x_q + u_q(U^n) is measured
// against every obstacle of its region (the plane too) where it is at
// t^{n+1}; the nearest gives d_q and nu_q. The point's rows hold a frozen
// normal n_q = -nu_f, refreshed (a new discretization, every point's at
// once) only when a point near the obstacle has a nu_q turned from nu_f by
// more than kNormalTurn; between refreshes the gap is the distance along n_q
// to the tangent plane at the nearest point, g_q = d_q / (nu_q.nu_f) + n_q.u_q.
#pragma once
#include <cstdint>
#include <vector>

#include "assembly/contact.hpp"
#include "contact/obstacle.hpp"
#include "contact/pairing.hpp"
#include "fem/space.hpp"

namespace nd {

// delta: the angle (radians) a curved point's normal may turn before its rows
// are made again; the direction error of the contact force is <= delta, the
// gap's against measuring along nu_q d (1/cos delta - 1) ~ d delta^2 / 2
constexpr double kNormalTurn = 0.01;
// a point is near its obstacle (its normal turning past delta triggers a
// refresh) within this many times the diameter of its cell; a farther
// point's gap is conservative, and it is free
constexpr double kNearCells = 0.5;

// The regions with contact points, in the order of their points: the
// planes' regions as given, then those with obstacles but no plane, in the
// order of their first obstacle, then the pairs' slave regions.
std::vector<int> contact_regions(const std::vector<ContactPlane> &planes, const std::vector<Obstacle> &obstacles,
                                 const std::vector<ContactPair> &pairs = {});
// Those and the pairs' master regions: the nodes a contact force acts on
// (mass redistribution)
std::vector<int> contact_node_regions(const std::vector<ContactPlane> &planes, const std::vector<Obstacle> &obstacles,
                                      const std::vector<ContactPair> &pairs);
// The pair whose slave region is `region` (-1: none)
int pair_of(int region, const std::vector<ContactPair> &pairs);
// a pair's point is paired anew when it has slid this far off its facet:
// its projection's barycentric coordinates on the facet's plane below
// -kPairSlack, or on a hexahedron's face (s, t) outside [-kPairSlack, 1 +
// kPairSlack] (contact/pairing.hpp: beyond_facet; a quarter of the facet
// beyond its edge; the slack keeps a point that sits on an edge from being
// paired back and forth)
constexpr double kPairSlack = 0.25;
// a pair's point farther than this many of the master's buckets (its
// largest facet) from every master facet is not projected: its gap is that
// distance, a lower bound of the true one, its pairing kept
constexpr double kPairReach = 1;
// a pair's delta: the angle its paired facet may turn (the master deforms)
// before every point is paired anew. Three times the rigid obstacles': on
// two disks colliding against one disk on the symmetry plane the
// difference stayed 2.0 % (h = 4) and 1.3 % (h = 2) of the largest
// displacement for 0.01 and 0.03, the re-pairings fell by 2 to 3
// (docs/design.md §10.3)
constexpr double kPairTurn = 0.03;
// whether the region has an added obstacle (its points follow the curved rule)
bool curved_region(int region, const std::vector<Obstacle> &obstacles);

// Where the planes' points and the obstacles' poses are: 3 values per
// plane, then Pose::kValues per obstacle (a state keeps those of t^n).
std::vector<double> positions(const std::vector<ContactPlane> &planes, const std::vector<Obstacle> &obstacles);
void place(std::vector<ContactPlane> &planes, std::vector<Obstacle> &obstacles, const std::vector<double> &at);

// The nearest obstacle of a region at y: -1 its plane, else the index in
// obstacles; d and nu (dim values).
struct Nearest {
  int which = -1;
  double d = 0, nu[3] = {0, 0, 0};
};
Nearest nearest(int region, const std::vector<ContactPlane> &planes, const std::vector<Obstacle> &obstacles, int dim,
                double t, const double *y);

// What a curved step sees at its points (the plane regions' entries: their
// closed forms, given): g^{n+1} with the obstacles at t^{n+1}, g^n with them
// at t^n (the same y_q, nearest obstacle and normal: g^{n+1} - g^n is the
// obstacles' motion alone), and the frozen normals (3 per point) after the
// refresh rule (may_refresh false: kept, as for a state's own gaps). U: the
// state's at t^n. Throws what a shape throws (a callback that failed).
struct StepGeometry {
  std::vector<double> gap, gap_old, normal, pairing;
  int64_t refreshed = 0;
};
struct StepPlaces {
  const std::vector<ContactPlane> &planes;
  const std::vector<Obstacle> &obstacles;
  double t;
  // the pairs (their points' gaps: from the master surface at U, no motion
  // of its own: g^n = g^{n+1}) and the pairings the rows hold
  const std::vector<ContactPair> *pairs = nullptr;
  const std::vector<double> *pairing = nullptr;
};
StepGeometry step_geometry(const Space &sp, const DofMap &dofs, const ContactPoints &cp, const StepPlaces &now,
                           const StepPlaces &before, const std::vector<double> &U, const std::vector<double> &frozen,
                           const std::vector<double> &plane_gap, const std::vector<double> &plane_gap_old,
                           bool may_refresh);

// u_q(U) at point q (dim values): the point's interpolation of U (clamped
// DOFs: zero)
void displacement_at(const Space &sp, const DofMap &dofs, const ContactPoints &cp, size_t q, const double *U,
                     double *u);

}  // namespace nd
