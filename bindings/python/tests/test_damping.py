#!/usr/bin/env python3
"""Rayleigh damping and plane stress from Python (docs/design.md §10.5), the
twin of tests/test_damping.c in brief: the bar of docs/design.md §7 with the
hybrid scheme, Theta = 1 and damping keeps the ledger
E_Theta + D_damping - W - W_obstacle non-increasing step by step (round-off
8 n eps of the energies, n the unknowns); damping 0, 0 is the undamped run
bitwise; ND_MATRIX_DAMPING is alpha M + beta K; bad values are nd.Error with
their codes; plane stress is refused in 1D.

usage: test_damping.py   (prints "N passed, M failed"; exit 1 on a failure)
"""
import sys

import nitschedyn as nd
from ndcheck import check, finish

EPS = 2.0 ** -52



def bar(nx=40, damping=None):
    with nd.Mesh.interval(nx, 0.0, 1.0) as m:
        m.mark_boundary_box(1, [0.5], [1.5])
        m.mark_boundary_box(2, [-0.5], [0.5])
        p = nd.Problem(m, 1)
    p.set_material(1.0, 0.0, 1.0)
    p.set_dirichlet(1)
    p.set_contact_plane(2, [0.0], [1.0])
    p.set_body_force([-0.5])
    p.set_nitsche(1.0, 0.2)
    p.set_scheme(nd.ND_SCHEME_HYBRID)
    p.set_timestep(0.5 / nx)
    p.set_initial_state([0.5 * (1 - x[0]) for x in p.node_coordinates()], None)
    if damping is not None:
        p.set_damping(*damping)
    return p


def status_of(fn):
    """the ND_ERR_* code fn raised (nd.Error), 0 if it raised none"""
    try:
        fn()
        return 0
    except nd.Error as e:
        return e.code


# the ledger, step by step
p = bar(damping=(0.05, 0.002))
p.setup()
E0 = p.scalar(nd.ND_ENERGY_AUGMENTED)
prev = E0
worst = 0.0
for k in range(400):
    p.step()
    W, D = p.scalar(nd.ND_WORK), p.scalar(nd.ND_DISSIPATION_DAMPING)
    L = p.scalar(nd.ND_ENERGY_AUGMENTED) + D - W - p.scalar(nd.ND_WORK_OBSTACLE)
    tol = 8 * 40 * EPS * (E0 + abs(W) + D)
    worst = max(worst, L - prev)
    check(L <= prev + tol, "step %d: the ledger rose from %.17g to %.17g" % (k + 1, prev, L))
    prev = L
D = p.scalar(nd.ND_DISSIPATION_DAMPING)
check(D > 0, "the damping dissipated energy: D = %g" % D)
print("hybrid ledger with damping: largest rise %.3g, D_damping %.6g" % (worst, D))
p.close()

# damping 0, 0 is bitwise the undamped run
a, b = bar(), bar(damping=(0.0, 0.0))
for k in range(100):
    a.step()
    b.step()
check(bool((a.field() == b.field()).all()), "damping 0, 0 changed the bits")
check(b.scalar(nd.ND_DISSIPATION_DAMPING) == 0, "no dissipation without damping")

# ND_MATRIX_DAMPING = alpha M + beta K
b.set_damping(0.3, 0.007)
M, K, C = (b.matrix(w) for w in (nd.ND_MATRIX_MASS, nd.ND_MATRIX_STIFFNESS, nd.ND_MATRIX_DAMPING))
check(bool((C[2] == 0.3 * M[2] + 0.007 * K[2]).all()), "C = alpha M + beta K")
a.close()

# bad values, plane stress outside 2D
check(status_of(lambda: b.set_damping(-1.0, 0.0)) == nd.ND_ERR_VALUE, "alpha < 0 refused")
check(status_of(lambda: b.set_damping(0.0, float("nan"))) == nd.ND_ERR_VALUE, "beta NaN refused")
check(status_of(lambda: b.set_plane_stress(1)) == nd.ND_ERR_DIMENSION, "plane stress in 1D refused")
b.set_plane_stress(0)
b.close()

sys.exit(finish())
