#!/usr/bin/env python3
"""Adaptive time steps from Python, the twin of tests/test_adaptive.c and
bindings/fortran/tests/test_api.f90 (adaptive): a free bar flying at -1
towards the plane x = -0.1037 has a step ending at the first touch exactly,
the hybrid Theta = 1 ledger never rises past round-off, a fixed-step run
given the adaptive run's sizes one by one is bitwise the same, and bad
arguments are nd.Error with their codes.

usage: test_adaptive.py   (prints "N passed, M failed"; exit 1 on a failure)
"""
import sys

import numpy as np

import nitschedyn as nd
from ndcheck import check, finish, raises


def flying_bar():
    m = nd.Mesh.interval(20, 0.0, 1.0)
    m.mark_boundary_box(1, [-0.5], [0.5])
    p = nd.Problem(m, 1)
    p.set_material(1.0, 0.0, 1.0)
    p.set_contact_plane(1, [-0.1037], [1.0])
    p.set_nitsche(1.0, 0.2)
    p.set_scheme(nd.ND_SCHEME_HYBRID)
    p.set_timestep(0.04)
    p.set_initial_state(v0=-np.ones(21))
    return p


a, b = flying_bar(), flying_bar()
check(raises(nd.ND_ERR_VALUE, lambda: a.set_adaptive_timestep(-1.0, 1e-6, 0.04)), "a negative tolerance")
check(raises(nd.ND_ERR_TIMESTEP, lambda: a.set_adaptive_timestep(1e-3, 0.0, 0.04)), "tau_min 0")
a.set_adaptive_timestep(1e-3, 1e-6, 0.04)
ledger = lambda p: p.scalar(nd.ND_ENERGY_AUGMENTED) - p.scalar(nd.ND_WORK) - p.scalar(nd.ND_WORK_OBSTACLE)
previous, rise, landed, same = ledger(a), 0.0, np.inf, True
for k in range(150):
    a.step()
    b.set_timestep(a.scalar(nd.ND_TIMESTEP_LAST))
    b.step()
    landed = min(landed, abs(a.scalar(nd.ND_TIME) - 0.1037))
    rise = max(rise, ledger(a) - previous)
    previous = ledger(a)
    for f in (nd.ND_FIELD_DISPLACEMENT, nd.ND_FIELD_VELOCITY):
        same = same and np.array_equal(a.field(f), b.field(f))
check(landed <= 1e-12, "a step ends at the first touch (%g off)" % landed)
check(rise <= 1e-13 * 0.5, "the ledger never rises past round-off (%g)" % rise)
check(same, "the fixed run given the same sizes is bitwise the adaptive one")
check(a.scalar(nd.ND_STAT_STEPS_REJECTED) >= 1, "the step past the touch was rejected")
sys.exit(finish())
