// What the C API sets: the definition of a problem, grouped into aspects.
// Everything derived from it (discretization, integrator, initial state)
// declares the aspects it depends on (problem.cpp), so a setter only names
// its own aspect and what it invalidates follows.
#pragma once
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "assembly/bulk.hpp"
#include "assembly/contact.hpp"
#include "assembly/material.hpp"
#include "contact/law.hpp"
#include "common/error.hpp"
#include "contact/obstacle.hpp"
#include "time/step_control.hpp"
#include "contact/pairing.hpp"
#include "monitor/guards.hpp"
#include "nitschedyn.h"
#include "parallel/communicator.hpp"
#include "fast/contact_columns.hpp"
#include "fast/tangents.hpp"
#include "solve/newton.hpp"

namespace nd {

enum Aspect : unsigned {
  kMaterial = 1u << 0,
  kDirichlet = 1u << 1,
  kLoads = 1u << 2,     // body force, tractions
  kContact = 1u << 3,   // obstacle planes
  kNitsche = 1u << 11,  // Theta, gamma0
  kLumping = 1u << 4,
  kScheme = 1u << 5,
  kTimestep = 1u << 6,
  kSolver = 1u << 7,
  kNodal = 1u << 8,     // nodal forces
  kInitial = 1u << 9,   // u0, v0
  kNewton = 1u << 10,
  kGuards = 1u << 12,
  kObstacle = 1u << 13,  // a plane's point moved (same normal), an obstacle's pose: only the gaps change
  kDamping = 1u << 14,   // Rayleigh damping alpha, beta
  kMotion = 1u << 15,    // the clamped DOFs' prescribed displacement: only the step's data change
  kAdaptive = 1u << 16,  // adaptive time steps: how a step's size is chosen, nothing derived
};

// What may change from step to step without new operators: the loads and
// the obstacles' positions (a plane's point). The state at t^0 keeps the
// values of t^0 (Problem::at_start).
struct TimeData {
  bool has_body_force = false;
  double body_force[3] = {0, 0, 0};
  std::vector<NeumannLoad> neumann;
  std::vector<double> nodal;  // n_dofs, or empty
  std::vector<ContactPlane> planes;
  // more obstacles of the regions (contact/obstacle.hpp), each with its pose
  std::vector<Obstacle> obstacles;
  // the prescribed displacement of every DOF (n_dofs; only the clamped ones
  // are read), or empty: the clamped DOFs stay at 0 (docs/design.md §10.5)
  std::vector<double> prescribed;
};

struct Definition : TimeData {
  Material material;  // the default: every cell whose region has no material of its own
  std::map<int, Material> region_materials;  // cell region -> its material (docs/design.md §10.6)
  std::vector<int> dirichlet;
  double theta = 1, gamma0 = 0;  // gamma0 = 0: automatic
  int scheme = 0;  // ND_SCHEME_*
  // the contact law of each region with friction (nd_problem_set_friction;
  // contact/law.hpp's registry), part of the Nitsche aspect; the regions
  // not named are frictionless
  struct Friction {
    int region, law;
    double parameter;
  };
  std::vector<Friction> friction;
  // contact between two regions (docs/design.md §10.3; part of the contact
  // aspect): the slave's points against the master's surface
  std::vector<ContactPair> pairs;
  // whether points follow the curved rule (frozen normals, gaps measured
  // anew at each step: contact/obstacles.hpp): an added obstacle or a pair
  bool curved() const { return !obstacles.empty() || !pairs.empty(); }
  // whether a region with points has a frictional law
  bool has_friction() const {
    for (const Friction &f : friction)
      if (f.law != kFrictionNone) return true;
    return false;
  }
  // white-box (tests): a law outside the registry in its place (null: contact_law's)
  std::shared_ptr<const PointLaw> contact_law_given;
  std::vector<double> scheme_params;
  // the step size in use; with adaptive steps (tolerance > 0) the control's,
  // tau_given the one nd_problem_set_timestep gave (the fixed size again
  // when they are turned off)
  double tau = 0, tau_given = 0;
  AdaptiveOptions adaptive;
  NewtonOptions newton;
  bool lumped = false;
  // Rayleigh damping C = alpha M + beta K (both 0: off, no term anywhere)
  double damping_alpha = 0, damping_beta = 0;
  bool redistributed = false;  // mass redistribution away from the contact nodes
  int solver = ND_SOLVER_AUTO;
  // the Newton tangent solver (white-box, not in the C API: tests and benchmarks)
  TangentChoice tangent = TangentChoice::Auto;
  // where the contact columns are held (fast/contact_columns.hpp;
  // white-box: tests compare the choices)
  ColumnRows column_rows = ColumnRows::Auto;
  // the contact checks a step may settle by a bound from the last evaluated
  // P_q, and the new states' points it then leaves unevaluated (white-box,
  // not in the C API: tests compare the trajectories without it)
  bool contact_bounds = true;
  // whether a step may be its predictor (fast/predictor_check.hpp;
  // white-box, not in the C API: tests compare the trajectories without it)
  bool predicted_steps = true;
  // with split rows, each rank keeps the state right on the rows its steps
  // read only (State::partial): a step gathers no whole solution, and the
  // calls that read whole vectors complete them, collectively
  bool distributed_state = false;
  std::vector<double> u0, v0;  // n_dofs each, or empty
  Guards guards;
  unsigned given = 0;                 // the aspects set so far
  CommunicatorPtr comm;               // the ranks stepping this problem together; null: this process alone

  // The aspects still missing for the operators (material; Nitsche
  // parameters once there is an obstacle) and for a step (scheme, time step).
  unsigned missing_for_operators() const {
    unsigned m = 0;
    if (!(given & kMaterial)) m |= kMaterial;
    if ((!planes.empty() || !obstacles.empty() || !pairs.empty()) && !(given & kNitsche)) m |= kNitsche;
    return m;
  }
  unsigned missing_for_step() const {
    unsigned m = missing_for_operators();
    if (!(given & kScheme)) m |= kScheme;
    if (!(given & kTimestep)) m |= kTimestep;
    return m;
  }
};

// ND_ERR_INCOMPLETE with the aspects that are missing, for the C layer to
// name the calls that set them.
class Incomplete : public Error {
 public:
  Incomplete(unsigned missing, const std::string &what)
      : Error(ND_ERR_INCOMPLETE, "the problem is incomplete: missing " + what), missing_(missing) {}
  unsigned missing() const noexcept { return missing_; }

 private:
  unsigned missing_;
};

// Throws Incomplete when any aspect of `missing` is missing.
void require_complete(unsigned missing);

// "a, b, c": the names of the aspects in `mask`, from a table of
// {aspect, name} (the core's words, or the C layer's function names)
struct AspectName {
  unsigned aspect;
  const char *name;
};
template <size_t N>
std::string aspect_names(unsigned mask, const AspectName (&names)[N]) {
  std::string s;
  for (const AspectName &n : names)
    if (mask & n.aspect) s += (s.empty() ? "" : ", ") + std::string(n.name);
  return s;
}

}  // namespace nd
