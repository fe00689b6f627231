#!/usr/bin/env python3
"""The obstacles from Python (docs/design.md §10.1), the twin of
tests/test_obstacles.c and bindings/fortran/tests/test_api.f90 (obstacles):
a plane given as a Python distance callback (ctypes CFUNCTYPE) steps
bitwise as the built-in plane; a circle added, moved and rotated; a
callback's exception fails the step, leaves the problem unchanged, and is
raised again; bad arguments are nd.Error with their codes.

usage: test_obstacles.py   (prints "N passed, M failed"; exit 1 on a failure)
"""
import math
import sys

import numpy as np

import nitschedyn as nd
from ndcheck import check, finish, raises




def block():
    """A 2 x 1 block [-1, 1] x [0.5, 1.5] under gravity; region 1 its bottom."""
    m = nd.Mesh.rectangle(8, 4, [-1.0, 0.5], [1.0, 1.5])
    m.mark_boundary_box(1, [-2.0, 0.4], [2.0, 0.6])
    p = nd.Problem(m, 1)
    p.set_material(100.0, 0.3, 1.0)
    p.set_body_force([0.0, -1.0])
    p.set_nitsche(1.0, 0.0)
    p.set_scheme(nd.ND_SCHEME_HYBRID)
    p.set_timestep(0.02)
    return p



calls = [0]


def plane(t, x):
    calls[0] += 1
    return x[1], (0.0, 1.0)


a, b = block(), block()
a.add_contact_distance(1, plane)
b.set_contact_plane(1, [0.0, 0.0], [0.0, 1.0])
same, touched = True, 0
for k in range(60):
    a.step()
    b.step()
    same = same and np.array_equal(a.field(), b.field())
    touched = max(touched, b.scalar(nd.ND_ACTIVE_POINTS))
check(touched > 0, "the block came into contact")
check(calls[0] > 0, "the Python callback was called")
check(same, "the plane as a Python callback steps bitwise as the built-in plane")

# the contact term at a U the host gives (Problem.contact_*), the hybrid scheme's
# step form: at u_old = u its Phi_q is [P_q]_+ bit for bit; its tangent on
# the at-end form's pattern
node, comp = b.dof_map()
u = b.field()[node, comp]
u[comp == 1] = -0.51  # the bottom 0.01 into the plane: every bottom point active
check(np.array_equal(b.contact_step_residual(u, u), b.contact_residual(u)), "step form at u_old = u")
ptr, col, _ = b.contact_tangent(u)
sptr, scol, sval = b.contact_step_tangent(u, u)
check(np.array_equal(ptr, sptr) and np.array_equal(col, scol) and np.any(sval != 0), "step form's tangent")
check(raises(nd.ND_ERR_NONFINITE, lambda: b.contact_step_residual(u, u * np.nan)), "a NaN in u_old")

# a callback that raises: the step fails, the problem is unchanged, the exception comes back
c = block()
boom = [False]


def failing(t, x):
    if boom[0]:
        raise RuntimeError("the host's geometry failed")
    return x[1] + 10.0 * (1 - math.cos(0.1 * x[0])), (0.0, 1.0)


c.add_contact_distance(1, failing)
for k in range(5):
    c.step()
u = c.field()
boom[0] = True
try:
    c.step()
    check(False, "a raising callback fails the step")
except RuntimeError as e:
    check("geometry failed" in str(e), "the callback's exception is raised again by step()")
check(np.array_equal(u, c.field()) and c.scalar(nd.ND_STEP_INDEX) == 5, "the failed step changed nothing")
boom[0] = False
c.step()
check(c.scalar(nd.ND_STEP_INDEX) == 6, "the run goes on once the callback works")

# a circle, moved and rotated
d = block()
d.add_contact_sphere(1, [0.0, -10.0], 10.0)
d.move_obstacle(1, 0, [0.01, 0.0])
ang = 0.01
d.move_obstacle(1, 0, [0.01, 0.0], [[math.cos(ang), -math.sin(ang)], [math.sin(ang), math.cos(ang)]])
touched = 0
for k in range(60):
    d.step()
    touched = max(touched, d.scalar(nd.ND_ACTIVE_POINTS))
check(touched > 0, "the block came onto the circle")
wg = d.scalar(nd.ND_WORK_GEOMETRY)
check(math.isfinite(wg) and wg != 0, "ND_WORK_GEOMETRY: the re-linearisations on the circle changed E_Theta")

# bad arguments
check(raises(nd.ND_ERR_VALUE, lambda: d.add_contact_sphere(1, [0.0, 0.0], -1.0)), "a negative radius")
check(raises(nd.ND_ERR_REGION, lambda: d.add_contact_sphere(7, [0.0, 0.0], 1.0)), "an unknown region")
check(raises(nd.ND_ERR_DIMENSION, lambda: d.add_contact_cylinder(1, [0.0, 0.0], [1.0, 0.0], 1.0)),
      "a cylinder in 2D")
check(raises(nd.ND_ERR_INDEX, lambda: d.move_obstacle(1, 1, [0.0, 0.0])), "a second obstacle that is not there")
check(raises(nd.ND_ERR_VALUE, lambda: d.move_obstacle(1, 0, [0.0, 0.0], [[1.0, 0.5], [0.0, 1.0]])),
      "a matrix that is no rotation")
sys.exit(finish())
