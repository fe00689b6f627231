// ParaView output: a VTK XML unstructured grid of a problem's current state,
// and .pvd time series.
#pragma once
#include <cstdint>

namespace nd {
class Problem;
void write_vtu(Problem &p, const char *path);
void write_pvd(const char *path, int64_t n, const char *const *files, const double *times);
}  // namespace nd
