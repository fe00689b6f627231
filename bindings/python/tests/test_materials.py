#!/usr/bin/env python3
"""Several materials from Python (docs/design.md §10.6), the twin of
tests/test_materials.c: a bar of two materials (cell regions 0 and 2) at
Courant number 1 in both splits a pulse into the exact reflected and
transmitted waves, R = (Z1 - Z2)/(Z1 + Z2), T = 2 Z1/(Z1 + Z2), to
round-off; the cell regions read back; bad arguments are nd.Error.

usage: test_materials.py   (prints "N passed, M failed"; exit 1 on a failure)
"""
import math
import sys

import numpy as np

import nitschedyn as nd
from ndcheck import check, finish, raises





def pulse(x):
    s = (x - 1) / 0.5
    return np.where(np.abs(s) < 1, 1e-3 * (1 - s * s) ** 3, 0.0)


E1, rho1, E2, rho2 = 1.0, 1.0, 8.0, 2.0
c1, c2 = math.sqrt(E1 / rho1), math.sqrt(E2 / rho2)
Z1, Z2 = math.sqrt(E1 * rho1), math.sqrt(E2 * rho2)
R, T = (Z1 - Z2) / (Z1 + Z2), 2 * Z1 / (Z1 + Z2)
tau, n1, n2, steps = 0.01, 200, 200, 200
h1, h2 = c1 * tau, c2 * tau
L1 = n1 * h1
x = np.concatenate([np.arange(n1 + 1) * h1, L1 + np.arange(1, n2 + 1) * h2])
cells = np.array([[c, c + 1] for c in range(n1 + n2)])
m = nd.Mesh(x, cells)
m.set_cell_region(2, np.arange(n1, n1 + n2))
check(np.array_equal(m.cell_regions, np.repeat([0, 2], [n1, n2])), "the cell regions read back")
check(raises(nd.ND_ERR_INDEX, lambda: m.set_cell_region(1, [n1 + n2])), "a cell that is not there")
check(raises(nd.ND_ERR_REGION, lambda: m.set_cell_region(-1, [0])), "a negative cell region")
p = nd.Problem(m, 1)
p.set_material(E1, 0.0, rho1)
p.set_material_region(2, E2, 0.0, rho2)
check(raises(nd.ND_ERR_REGION, lambda: p.set_material_region(3, E2, 0.0, rho2)), "a cell region without cells")
check(raises(nd.ND_ERR_MATERIAL, lambda: p.set_material_region(2, -1.0, 0.0, rho2)), "a negative Young's modulus")
p.set_mass_lumping(True)
p.set_scheme(nd.ND_SCHEME_NEWMARK, [0.0, 0.5])
p.set_timestep(tau)
p.set_guard(nd.ND_GUARD_CRITICAL_TIMESTEP, 0)  # at tau_c itself
v0 = np.where(np.arange(x.size) < n1, (pulse(x - h1) - pulse(x + h1)) / (2 * tau), 0.0)
p.set_initial_state(pulse(x), v0)
for _ in range(steps):
    p.step()
t = steps * tau
exact = np.where(x <= L1, pulse(x - c1 * t) + R * pulse(2 * L1 - x - c1 * t),
                 T * pulse(L1 - c1 * (t - (x - L1) / c2)))
err = np.max(np.abs(p.field().reshape(-1) - exact))
print("two materials: R = %.3f, T = %.3f, max error %.3g of the pulse's height" % (R, T, err / 1e-3))
check(err <= 1e-9 * 1e-3, "the reflected and transmitted waves are the closed form")
sys.exit(finish())
