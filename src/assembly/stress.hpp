// The Cauchy stress of a displacement at a point of a cell, as a 3x3 tensor
// (row-major, the VTK tensor layout). 2D is plane strain: sigma_zz =
// lambda (eps_xx + eps_yy); 1D: sigma_xx = E u_x, the rest 0.
#pragma once
#include <cstdint>

#include "assembly/material.hpp"
#include "fem/space.hpp"

namespace nd {

// U_full: n_dofs values (node-major); xi: reference coordinates in cell c
void cell_stress(const Space &s, const CellMaterials &mat, const double *U_full, int64_t c, const double *xi,
                 double sigma[9]);

}  // namespace nd
