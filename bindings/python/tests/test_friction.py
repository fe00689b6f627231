#!/usr/bin/env python3
"""Friction from Python (docs/design.md §10.2), the twin of
tests/test_friction.c and bindings/fortran/tests/test_api.f90 (friction): a
block on a 0.5 rad slope with Coulomb's F = 0.3 slides, its tangential
resultant F times the normal one while every pressed point slides, and
friction dissipates; with F = 0.6 it sticks and dissipates nothing more;
on a plane sliding along x at v the plane's work is v times the impulse its
friction gave; bad arguments are nd.Error with their codes.

usage: test_friction.py   (prints "N passed, M failed"; exit 1 on a failure)
"""
import math
import sys

import nitschedyn as nd
from ndcheck import check, finish, raises





def block(F):
    """The 2 x 1 block of tests/test_friction.c on the plane y = 0, gravity tilted by 0.5."""
    m = nd.Mesh.rectangle(8, 4, [0.0, 0.0], [2.0, 1.0])
    m.mark_boundary_box(1, [-1.0, -1e-9], [3.0, 1e-9])
    p = nd.Problem(m, 1)
    p.set_material(1e4, 0.3, 1.0)
    p.set_contact_plane(1, [0.0, 0.0], [0.0, 1.0])
    p.set_nitsche(1.0, 0.0)
    p.set_friction(1, nd.ND_FRICTION_COULOMB, F)
    p.set_body_force([math.sin(0.5), -math.cos(0.5)])
    p.set_scheme(nd.ND_SCHEME_THETA, [1.0])
    p.set_timestep(2e-3)
    return p


F = 0.3
p = block(F)
worst, sliding = 0.0, 0
for k in range(150):
    p.step()
    if p.scalar(nd.ND_STICKING_POINTS) == 0 and p.scalar(nd.ND_SLIDING_POINTS) > 0:
        sliding += 1
        fn = p.scalar(nd.ND_CONTACT_FORCE_APPLIED)
        worst = max(worst, abs(p.scalar(nd.ND_CONTACT_FORCE_TANGENTIAL_X) + F * fn) / (F * fn))
check(sliding > 0, "the block slides")
check(worst <= 1e-12, "f_t = -F f_n while every pressed point slides (%.2e)" % worst)
check(p.scalar(nd.ND_DISSIPATION_FRICTION) > 0, "friction dissipates")

q = block(0.6)
for k in range(300):
    q.step()
D = q.scalar(nd.ND_DISSIPATION_FRICTION)
for k in range(100):
    q.step()
check(q.scalar(nd.ND_SLIDING_POINTS) == 0 and q.scalar(nd.ND_DISSIPATION_FRICTION) == D,
      "with F = 0.6 > tan 0.5 it sticks and dissipates nothing more")

# a moving plane (slip is relative): the plane slides along x at v = 0.5,
# faster than the block, and drags it up the slope; theta = 1 gives the
# momentum tau (m g sin + f_t,x) a step, the plane's work v tau f_t,x a
# step, so W_obstacle = v (P - P0 - m g sin t) to the steps' round-off: a
# momentum is a sum over the 45 nodes, each step's rounded to 45 eps of the
# momenta and impulses in it
v, m, tau = 0.5, 2.0, 2e-3
r = block(F)
P0 = r.scalar(nd.ND_MOMENTUM_X)
for k in range(1, 201):
    r.set_contact_plane(1, [v * k * tau, 0.0], [0.0, 1.0])
    r.step()
W = r.scalar(nd.ND_WORK_OBSTACLE)
lhs = v * (r.scalar(nd.ND_MOMENTUM_X) - P0 - m * math.sin(0.5) * r.scalar(nd.ND_TIME))
P, G = r.scalar(nd.ND_MOMENTUM_X), m * math.sin(0.5) * r.scalar(nd.ND_TIME)
bound = v * 200 * 45 * sys.float_info.epsilon * (abs(P) + abs(P0) + G)
check(W > 0 and abs(W - lhs) <= bound, "a moving plane's work is v times its impulse (%.2e off, bound %.2e)"
      % (abs(W - lhs), bound))
check(r.scalar(nd.ND_CONTACT_FORCE_TANGENTIAL_X) > 0, "the plane drags the block up the slope")

check(raises(nd.ND_ERR_VALUE, lambda: p.set_friction(1, nd.ND_FRICTION_COULOMB, -0.1)), "a negative coefficient")
check(raises(nd.ND_ERR_NULL, lambda: p.set_friction(1, nd.ND_FRICTION_TRESCA)), "Tresca without its threshold")
check(raises(nd.ND_ERR_KEY, lambda: p.set_friction(1, 7, 0.1)), "an unknown law")
check(raises(nd.ND_ERR_REGION, lambda: p.set_friction(9, nd.ND_FRICTION_COULOMB, 0.1)), "an unknown region")
sys.exit(finish())
