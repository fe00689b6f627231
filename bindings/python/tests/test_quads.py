#!/usr/bin/env python3
"""Quadrilaterals and hexahedra from Python (docs/design.md §10.7), the twin
of tests/test_quads.c's mass identity: on Q1 and Q2 cells of the generators
and of Mesh(coords, cells, cell_type), the mass matrix's entries and the
lumped diagonal sum to rho |Omega| per component (exact rules: round-off);
bad cell types are nd.Error.

usage: test_quads.py   (prints "N passed, M failed"; exit 1 on a failure)
"""
import sys

import numpy as np

import nitschedyn as nd
from ndcheck import check, finish, raises





rho = 2.0
meshes = [
    ("rectangle", lambda: nd.Mesh.rectangle(3, 2, [0, 0], [2, 1], cell_type=nd.ND_CELL_QUADRILATERAL), 2.0, 2),
    ("box", lambda: nd.Mesh.box(2, 2, 1, [0, 0, 0], [2, 1, 1], cell_type=nd.ND_CELL_HEXAHEDRON), 2.0, 3),
    # a trapezoid in one quadrilateral: area (2 + 1)/2
    ("trapezoid", lambda: nd.Mesh(np.array([[0, 0], [2, 0], [1.5, 1], [0.5, 1]], dtype=float),
                                  np.array([[0, 1, 2, 3]]), cell_type=nd.ND_CELL_QUADRILATERAL), 1.5, 2),
]
for name, make, volume, dim in meshes:
    for degree in (1, 2):
        with make() as m, nd.Problem(m, degree) as p:
            p.set_material(1.0, 0.3, rho)
            _, _, mass = p.matrix(nd.ND_MATRIX_MASS)
            _, _, lumped = p.matrix(nd.ND_MATRIX_LUMPED_MASS)
            exact = rho * volume * dim
            check(abs(mass.sum() - exact) <= 1e-13 * exact, "%s Q%d: sum M = %.17g, not %g" % (name, degree, mass.sum(), exact))
            check(abs(lumped.sum() - exact) <= 1e-13 * exact and lumped.min() > 0,
                  "%s Q%d: lumped sum %.17g, smallest %g" % (name, degree, lumped.sum(), lumped.min()))

check(raises(nd.ND_ERR_VALUE, lambda: nd.Mesh.rectangle(2, 2, [0, 0], [1, 1], cell_type=nd.ND_CELL_HEXAHEDRON)),
      "a hexahedral rectangle is refused")
check(raises(nd.ND_ERR_DEGENERATE, lambda: nd.Mesh(np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float),
                                                   np.array([[0, 3, 2, 1]]), cell_type=nd.ND_CELL_QUADRILATERAL)),
      "a clockwise quadrilateral is refused")

sys.exit(finish())
