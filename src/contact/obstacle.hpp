// A rigid obstacle (docs/design.md §10.1): a shape, one file each
// (obstacle_plane.cpp, obstacle_sphere.cpp, obstacle_cylinder.cpp,
// obstacle_distance.cpp), placed by a rigid pose. What a contact point needs
// of it is its signed distance d (positive on the body's side) and the unit
// normal nu pointing from the obstacle towards the body, at a point x and a
// time t; the selection of the acting obstacle, the frozen normals and the
// gaps are in obstacles.hpp.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "common/hash.hpp"
#include "nitschedyn.h"

namespace nd {

// x -> R x + t, R row-major 3x3 (the 2D rotation in its upper-left block):
// where the obstacle is relative to its definition
struct Pose {
  double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double t[3] = {0, 0, 0};
  static constexpr int kValues = 12;  // R then t: a pose in a checkpoint
};

class Shape {
 public:
  virtual ~Shape() = default;
  virtual const char *kind() const = 0;
  // d and nu (dim values) at x (dim values) in the shape's own frame at time
  // t; throws nd::Error when it cannot (a user's callback failed)
  virtual void distance(double t, const double *x, double &d, double *nu) const = 0;
  // what the shape is (not where it is): the definition's digests
  virtual void fingerprint(Hash &h) const = 0;
};

// An obstacle of a region: its shape where the pose puts it.
struct Obstacle {
  int region;
  std::shared_ptr<const Shape> shape;
  Pose pose;
};

// d and nu with the shape at `pose`: the shape's at R^T (x - t), nu turned by R
void obstacle_distance(const Shape &s, const Pose &pose, int dim, double t, const double *x, double &d, double *nu);

// The shapes (each checks its arguments: ND_ERR_VALUE, ND_ERR_DIMENSION).
// normal: unit; the plane d = (x - point).normal
std::shared_ptr<const Shape> make_plane_shape(const double *point, const double *normal, int dim);
// the same distance and normal without a Shape (a region's ContactPlane among
// its other obstacles, contact/obstacles.cpp)
void plane_distance(const double *point, const double *normal, int dim, const double *x, double &d, double *nu);
// a sphere (a circle in 2D, points in 1D); inside: the body within it
std::shared_ptr<const Shape> make_sphere(const double *center, double radius, bool inside, int dim);
// 3D only: the infinite circular cylinder of this axis through point
std::shared_ptr<const Shape> make_cylinder(const double *point, const double *axis, double radius, bool inside,
                                           int dim);
// the user's signed distance (nd_distance_fn), its values checked
std::shared_ptr<const Shape> make_distance(nd_distance_fn f, void *user, int dim);

// the Euclidean length of v (dim values) scaled first, so that it neither
// overflows nor underflows; and v / |v|
double length(const double *v, int dim);

}  // namespace nd
