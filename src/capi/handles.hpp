// What the opaque handles of the public header hold.
#pragma once
#include <memory>

#include "capi/guard.hpp"
#include "mesh/mesh.hpp"
#include "nitschedyn.h"
#include "problem/problem.hpp"

struct nd_mesh_s {
  nd::Mesh mesh;
};

struct nd_problem_s {
  nd::Problem problem;
  nd_monitor_fn monitor = nullptr;
  void *userdata = nullptr;
};

namespace nd {
inline Problem &problem_of(nd_problem p) {
  need(p, "problem");
  return p->problem;
}
}  // namespace nd
