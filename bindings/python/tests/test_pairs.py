#!/usr/bin/env python3
"""Two bodies from Python (docs/design.md §10.3), the twin of
tests/test_pairs.c and bindings/fortran/tests/test_api.f90 (pairs): two bars
hitting head-on keep their total momentum to round-off and, with Theta = 1,
the hybrid scheme's ledger; the contact lasts about 2L/c and the bars
rebound (and as Q1 hexahedra: a bilinear master face); bad pairs are
nd.Error with their codes. Friction between the
bodies (2D): a block thrown onto another and sliding over it with Coulomb
F = 0.3 keeps the total momentum and, with Theta = 1, the hybrid ledger
E_Theta + D_f - W_geometry, with D_f > 0 (test_pairs.c's
coulomb_friction_between_two_blocks). A U-shaped body whose whole boundary
is one region, its own master, closes its slot with friction, likewise
(test_self_contact.c).

usage: test_pairs.py   (prints "N passed, M failed"; exit 1 on a failure)
"""
import sys

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
p.set_contact_pair(1, 1)  # a region as its own master is accepted (replaced next: a slave has one master)
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

# the bars again as Q1 hexahedra, one cell across a square section of side
# w = 0.1, nu = 0 (the 1D bars' motion per unit section; test_pairs.c's
# hex_bars_head_on_are_the_1d_bars): the master face bilinear, the same checks
corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
x, cells = [], []
for x0 in (0.0, 1.01):
    base = len(x)
    x += [[x0 + i / 10.0, 0.1 * j, 0.1 * k] for k in range(2) for j in range(2) for i in range(11)]
    cells += [[base + (k * 2 + j) * 11 + i + a for (a, j, k) in corners] for i in range(10)]
m = nd.Mesh(np.array(x), np.array(cells), cell_type=nd.ND_CELL_HEXAHEDRON)
m.mark_boundary_box(1, [1 - 1e-9, -1, -1], [1.005, 1, 1])
m.mark_boundary_box(2, [1.005, -1, -1], [1.01 + 1e-9, 1, 1])
p = nd.Problem(m, 1)
p.set_material(1.0, 0.0, 1.0)
p.set_contact_pair(1, 2)
p.set_nitsche(1.0, 0.0)
p.set_scheme(nd.ND_SCHEME_HYBRID)
p.set_timestep(0.01)
first = p.node_coordinates()[:, 0] < 1.005
v0 = np.zeros((p.node_count, 3))
v0[:, 0] = np.where(first, 0.1, -0.1)
p.set_initial_state(v0=v0)
ledger = lambda: p.scalar(nd.ND_ENERGY_AUGMENTED) - p.scalar(nd.ND_WORK_GEOMETRY)
previous, E0, drift, rise, touched = ledger(), ledger(), 0.0, 0.0, []
for k in range(300):
    p.step()
    drift = max([drift] + [abs(p.scalar(key)) for key in (nd.ND_MOMENTUM_X, nd.ND_MOMENTUM_Y, nd.ND_MOMENTUM_Z)])
    rise = max(rise, ledger() - previous)
    previous = ledger()
    if p.scalar(nd.ND_ACTIVE_POINTS) > 0:
        touched.append(p.scalar(nd.ND_TIME))
v = p.field(nd.ND_FIELD_VELOCITY)
# (300 steps of forces on 264 rows that cancel in the sum, momenta 1e-3:
# 300 x 264 x 2.2e-16 x 1e-3, and a factor of ten)
check(drift <= 1.7e-13, "hexahedra: the total momentum stays 0 to round-off (%.3g)" % drift)
check(rise <= 1e-12 * E0, "hexahedra: E_Theta - W_geometry never rises with Theta = 1 (%.3g)" % rise)
check(len(touched) > 0 and abs(touched[-1] - touched[0] - 2) <= 0.05, "hexahedra: the contact lasts 2L/c = 2")
check(v[first, 0].mean() < -0.09 and v[~first, 0].mean() > 0.09, "hexahedra: the bars rebound at about -+v0")
print("hex bars: momentum drift %.3g, ledger rise %.3g of %.3g, contact %.2f to %.2f, rebound %.5f" %
      (drift, rise, E0, touched[0], touched[-1], v[first, 0].mean()))


def block(lo, hi, n):
    """the rectangle [lo, hi] of n[0] x n[1] cells, each split in two triangles"""
    xs, ys = np.linspace(lo[0], hi[0], n[0] + 1), np.linspace(lo[1], hi[1], n[1] + 1)
    x = np.array([[a, b] for b in ys for a in xs])
    at = lambda i, j: j * (n[0] + 1) + i
    cells = []
    for j in range(n[1]):
        for i in range(n[0]):
            cells += [[at(i, j), at(i + 1, j), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i, j + 1)]]
    return x, np.array(cells)


# the block [0.5, 1.5] x [1.001, 1.5] thrown at (1, -0.5) onto [0, 2] x [0, 1],
# no gravity, no support: it lands and slides over the lower block (paired
# anew from facet to facet), friction F = 0.3 on the slave region 1
x1, c1 = block([0, 0], [2, 1], [8, 4])
x2, c2 = block([0.5, 1.001], [1.5, 1.5], [5, 3])
m = nd.Mesh(np.vstack([x1, x2]), np.vstack([c1, c2 + len(x1)]))
m.mark_boundary_box(1, [-1, 1.0005], [3, 1.002])
m.mark_boundary_box(2, [-1, 0.9995], [3, 1.0005])
p = nd.Problem(m, 1)
p.set_material(100.0, 0.3, 1.0)
p.set_contact_pair(1, 2)
p.set_friction(1, nd.ND_FRICTION_COULOMB, 0.3)
p.set_nitsche(1.0, 0.0)
p.set_scheme(nd.ND_SCHEME_HYBRID)
p.set_timestep(0.01)
upper = p.node_coordinates()[:, 1] > 1
v0 = np.zeros((p.node_count, 2))
v0[upper] = [1.0, -0.5]
p.set_initial_state(v0=v0)
P0 = [p.scalar(nd.ND_MOMENTUM_X), p.scalar(nd.ND_MOMENTUM_Y)]
ledger = lambda: (p.scalar(nd.ND_ENERGY_AUGMENTED) + p.scalar(nd.ND_DISSIPATION_FRICTION)
                  - p.scalar(nd.ND_WORK_GEOMETRY))
previous, drift, rise, E0 = ledger(), 0.0, 0.0, ledger()
for k in range(100):
    p.step()
    drift = max(drift, abs(p.scalar(nd.ND_MOMENTUM_X) - P0[0]), abs(p.scalar(nd.ND_MOMENTUM_Y) - P0[1]))
    rise = max(rise, ledger() - previous)
    previous = ledger()
# (momenta of order 0.5, forces of order 1 on ~100 rows over 100 steps)
check(drift <= 1e-12, "friction between bodies: the total momentum is conserved (%.3g)" % drift)
# (a block far from where it started: E's terms cancel ~1e4 times E, as
# test_pairs.c's thrown block measures; there 2e-17 of them)
check(rise <= 1e-12 * E0, "friction between bodies: E_Theta + D_f - W_geometry never rises (%.3g of %.3g)"
      % (rise, E0))
check(p.scalar(nd.ND_DISSIPATION_FRICTION) > 0, "friction between bodies dissipates")
# the one contact region's friction values are the problem's, to the bit (the same sums)
for key in (nd.ND_DISSIPATION_FRICTION, nd.ND_SLIDING_POINTS, nd.ND_STICKING_POINTS, nd.ND_CONTACT_FORCE_TANGENTIAL_X):
    check(p.region_scalar(1, key) == p.scalar(key), "nd_get_region_scalar: the pair's friction value %d" % key)
check(p.scalar(nd.ND_STAT_NORMAL_REFRESHES) > 0, "the sliding block is paired anew")
print("friction between bodies: momentum drift %.3g, ledger rise %.3g of %.3g, D_f %.6g" %
      (drift, rise, E0, p.scalar(nd.ND_DISSIPATION_FRICTION)))

# One region as its own master (test_self_contact.c's whole boundary with
# friction): [0, 2.1] x [0, 2] without the slot [1, 1.1] x [0.5, 2], its whole
# boundary region 3 paired with itself, Coulomb F = 0.3 on it; the arms thrown
# towards each other at up to 0.5 and along the slot at -+0.2: no point active
# at the first step (none pairs through the body, past a corner or with its own
# facets), the slot closes, the momentum stays, D_f > 0 never decreases, and
# with Theta = 1 the ledger E_Theta + D_f - W_geometry never rises
x, c = block([0, 0], [2.1, 2], [21, 20])
slot = [k for k in range(len(c)) if 1.0 < x[c[k]][:, 0].mean() < 1.1 and x[c[k]][:, 1].mean() > 0.5]
m = nd.Mesh(x, np.delete(c, slot, axis=0))
m.mark_boundary_box(3, [-1, -1], [3, 3])
p = nd.Problem(m, 1)
p.set_material(100.0, 0.3, 1.0)
p.set_contact_pair(3, 3)
p.set_friction(3, nd.ND_FRICTION_COULOMB, 0.3)
p.set_nitsche(1.0, 0.0)
p.set_scheme(nd.ND_SCHEME_HYBRID)
p.set_timestep(0.005)
y = p.node_coordinates()
side, lift = np.where(y[:, 0] < 1.05, 1.0, -1.0), np.maximum(y[:, 1] - 0.5, 0) / 1.5
p.set_initial_state(v0=np.column_stack([0.5 * side * lift, -0.2 * side * lift]))
P0 = [p.scalar(nd.ND_MOMENTUM_X), p.scalar(nd.ND_MOMENTUM_Y)]
previous, drift, rise, E0, D_step, active = ledger(), 0.0, 0.0, ledger(), 0.0, []
for k in range(150):
    D = p.scalar(nd.ND_DISSIPATION_FRICTION)
    p.step()
    drift = max(drift, abs(p.scalar(nd.ND_MOMENTUM_X) - P0[0]), abs(p.scalar(nd.ND_MOMENTUM_Y) - P0[1]))
    rise = max(rise, ledger() - previous)
    previous = ledger()
    D_step = min(D_step, p.scalar(nd.ND_DISSIPATION_FRICTION) - D)
    active.append(p.scalar(nd.ND_ACTIVE_POINTS))
check(active[0] == 0, "a region as its own master: no point active at the first step (the arms 0.1 apart)")
check(max(active) > 0, "a region as its own master: the slot closes")
# (each arm's momentum 0.375, forces of order 3; the C twin measures 3.5e-13)
check(drift <= 1e-11 * 0.375, "a region as its own master: the total momentum is conserved (%.3g)" % drift)
# (the C twin: 3.8e-17 of the energy's terms, of the order of E0)
check(rise <= 1e-12 * E0, "a region as its own master: E_Theta + D_f - W_geometry never rises (%.3g of %.3g)"
      % (rise, E0))
check(p.scalar(nd.ND_DISSIPATION_FRICTION) > 0 and D_step >= 0, "a region as its own master: D_f > 0, never decreasing")
print("a region as its own master: momentum drift %.3g, ledger rise %.3g of %.3g, D_f %.6g" %
      (drift, rise, E0, p.scalar(nd.ND_DISSIPATION_FRICTION)))
sys.exit(finish())
