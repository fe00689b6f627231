// ParaView output: a VTK XML unstructured grid of one state, and .pvd time
// series. The writer takes what it prints, not the problem that holds it, so
// output stands below the problem in the data flow.
#pragma once
#include <cstdint>
#include <vector>

#include "assembly/contact.hpp"
#include "assembly/material.hpp"
#include "fem/space.hpp"

namespace nd {

// One state as the VTU file shows it: U and V on every DOF of the space
// (n_dofs each), the contact pressure lambda_q at each contact point.
struct VtuSnapshot {
  const Space *space = nullptr;
  const CellMaterials *material = nullptr;
  const ContactPoints *contact = nullptr;
  std::vector<double> U, V, pressure;
  double time = 0;
  int64_t step = 0;
};

void write_vtu(const VtuSnapshot &s, const char *path);
void write_pvd(const char *path, int64_t n, const char *const *files, const double *times);
}  // namespace nd
