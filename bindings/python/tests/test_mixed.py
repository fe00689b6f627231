#!/usr/bin/env python3
"""Meshes mixing triangles and quadrilaterals from Python (docs/design.md
§10.7), the twin of tests/test_mixed.c's mass identity: on a rectangle of
one quadrilateral and two triangles (Mesh.mixed) and on the Gmsh file
examples/meshes/mixed.msh, P1/Q1 and P2/Q2, the mass matrix's entries and
the lumped diagonal sum to rho |Omega| per component (exact rules:
round-off), the lumped diagonal positive; a 3D mix is refused.

usage: test_mixed.py MESH_DIR   (prints "N passed, M failed"; exit 1 on a failure)
"""
import os
import sys

import numpy as np

import nitschedyn as nd
from ndcheck import check, finish, raises

mesh_dir = sys.argv[1]
rho = 2.0
xy = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], dtype=float)
types = [nd.ND_CELL_QUADRILATERAL, nd.ND_CELL_SIMPLEX, nd.ND_CELL_SIMPLEX]
meshes = [
    ("arrays", lambda: nd.Mesh.mixed(xy, types, [[0, 1, 4, 3], [1, 2, 5], [1, 5, 4]])),
    ("mixed.msh", lambda: nd.Mesh.read_gmsh(os.path.join(mesh_dir, "mixed.msh"))),
]
for name, make in meshes:
    for degree in (1, 2):
        with make() as m, nd.Problem(m, degree) as p:
            p.set_material(1.0, 0.3, rho)
            _, _, mass = p.matrix(nd.ND_MATRIX_MASS)
            _, _, lumped = p.matrix(nd.ND_MATRIX_LUMPED_MASS)
            exact = rho * 2.0 * 2  # |Omega| = 2, two components
            check(abs(mass.sum() - exact) <= 1e-13 * exact,
                  "%s P%d/Q%d: sum M = %.17g, not %g" % (name, degree, degree, mass.sum(), exact))
            check(abs(lumped.sum() - exact) <= 1e-13 * exact and lumped.min() > 0,
                  "%s P%d/Q%d: lumped sum %.17g, smallest %g" % (name, degree, degree, lumped.sum(), lumped.min()))

x3 = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1], [0, 0, 2]],
              dtype=float)
check(raises(nd.ND_ERR_DIMENSION, lambda: nd.Mesh.mixed(x3, [nd.ND_CELL_HEXAHEDRON, nd.ND_CELL_SIMPLEX],
                                                         [list(range(8)), [4, 5, 7, 8]])),
      "a tetrahedron/hexahedron mix is refused")

sys.exit(finish())
