#!/usr/bin/env python3
"""Two bodies from Python (docs/design.md §10.3), the twin of
tests/test_pairs.c and bindings/fortran/tests/test_api.f90 (pairs): two bars
hitting head-on keep their total momentum to round-off and, with Theta = 1,
the hybrid scheme's ledger; the contact lasts about 2L/c and the bars
rebound; bad pairs are nd.Error with their codes.

usage: test_pairs.py   (prints "N passed, M failed"; exit 1 on a failure)
"""
import numpy as np

import nitschedyn as nd
from ndcheck import check, finish, raises

# bars [0, 1] and [1.01, 2.01], ten cells each, rho = E = 1, at +-0.1
x = np.concatenate([np.arange(11) / 10.0, 1.01 + np.arange(11) / 10.0])
cells = [[i, i + 1] for i in range(10)] + [[i, i + 1] for i in range(11, 21)]
m = nd.Mesh(x, cells)
m.set_region(1, [[10]])
m.set_region(2, [[11]])
p = nd.Problem(m, 1)
p.set_material(1.0, 0.0, 1.0)
check(raises(nd.ND_ERR_REGION, lambda: p.set_contact_pair(1, 1)), "a region as its own master")
check(raises(nd.ND_ERR_REGION, lambda: p.set_contact_pair(1, 7)), "an unknown master region")
p.set_contact_pair(1, 2)
p.set_nitsche(1.0, 0.0)
p.set_scheme(nd.ND_SCHEME_HYBRID)
p.set_timestep(0.01)
p.set_initial_state(v0=np.where(np.arange(22) <= 10, 0.1, -0.1))
previous = p.scalar(nd.ND_ENERGY_AUGMENTED)
drift, rise, touched, region_gap = 0.0, 0.0, [], 0.0
for k in range(300):
    p.step()
    drift = max(drift, abs(p.scalar(nd.ND_MOMENTUM_X)))
    ledger = p.scalar(nd.ND_ENERGY_AUGMENTED) - p.scalar(nd.ND_WORK_GEOMETRY)
    rise = max(rise, ledger - previous)
    previous = ledger
    if p.scalar(nd.ND_ACTIVE_POINTS) > 0:
        touched.append(p.scalar(nd.ND_TIME))
    # the pair's slave region carries every contact point: its force is the whole
    region_gap = max(region_gap, abs(p.region_scalar(1, nd.ND_CONTACT_FORCE) - p.scalar(nd.ND_CONTACT_FORCE)))
check(region_gap <= 1e-15, "nd_get_region_scalar: the one pair's force is the whole (%.3g)" % region_gap)
check(raises(nd.ND_ERR_REGION, lambda: p.region_scalar(2, nd.ND_CONTACT_FORCE)), "a region without points")
# (300 steps of forces on ~20 rows that cancel in the sum, momenta 0.1)
check(drift <= 1.3e-12, "the total momentum stays 0 to round-off (%.3g)" % drift)
check(rise <= 1e-12 * 0.01, "E_Theta - W_geometry never rises with Theta = 1 (%.3g)" % rise)
check(len(touched) > 0 and abs(touched[-1] - touched[0] - 2) <= 0.05, "the contact lasts 2L/c = 2")
v = p.field(nd.ND_FIELD_VELOCITY).ravel()
check(v[:11].mean() < -0.09 and v[11:].mean() > 0.09, "the bars rebound at about -+v0")
finish()
