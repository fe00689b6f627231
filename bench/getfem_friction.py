#!/usr/bin/python3
"""Coulomb friction side by side with GetFEM: the block of tests/test_friction.c.

The rectangle [0,2] x [0,1], 8 x 4 squares cut along (i,j)-(i+1,j+1) into two
triangles (nd_mesh_create_rectangle), P1, E = 1e4, nu = 0.3 (plane strain),
rho = 1, its lowest face on the rigid plane y = 0, gravity (sin a, -cos a)
with a = 0.5, Coulomb F = 0.3, Nitsche Theta = 1 with the library's automatic
gamma0 (ND_GAMMA0, gamma = gamma0 h_K, h_K the longest edge), theta-scheme
theta = 1 (implicit Euler), tau = 2e-3, 500 steps, from rest at u = 0.

Both codes are run from this script: the library through its Python binding
(bindings/python, from the build tree given), GetFEM (Debian's python3-getfem)
with its Nitsche rigid-obstacle brick with friction,

    add_Nitsche_contact_with_rigid_obstacle_brick(mim, u, G, obstacle, gamma0_getfem,
                                                  region, Theta, F, alpha, wt)

whose traction is Coulomb_friction_coupled_projection(G, n, alpha (u - wt), gap, F, 1/gamma)
and whose weak form, with G = sigma(u) n (the whole stress vector), is term for
term docs/design.md §10.2's (the Theta-term -Theta gamma sigma(u)n . sigma(v)n
and the blocks phi . (v - Theta gamma sigma(v)n)). gamma as bench/getfem_drop.py
matches it (a P0 field gamma0_getfem = element_size / (gamma0 h_K)); the face
rule of IM_TRIANGLE(2) is the 2-point Gauss rule of ours; the mass is
consistent in both; the time loop is the theta-scheme's (docs/design.md §3)
around Model.solve, whose Newton stops at ||G||_1 <= rtol (||r||_1 + c ||M U^n||_1)
as ours.

What differs is the slip reference: GetFEM's tangential value is
P_t = T(u - wt) - gamma sigma_t(u) with wt = U^n (alpha = 1), ours
P_t = T u - s - gamma sigma_t(u) with s the return-mapped reference. Runs:

  coulomb   library F = 0.3  vs GetFEM F = 0.3, wt = U^n
  local     the same, but every GetFEM step starts from the library's state
            (U^n, V^n): the difference one step makes
  twin      library F = 0.3  vs GetFEM F = 0.3, wt = the library's s (an im_data
            field at the contact points, updated by the same return mapping)
  zero      library Coulomb F = 0 vs GetFEM F = 0 (both carry the tangential Theta-term)
  none      library ND_FRICTION_NONE vs GetFEM's frictionless brick with
            G = (n.sigma n) n (bench/getfem_drop.py's match)

Per step (both codes): the mean x-displacement (1/m) sum (M U)_x, the momentum
sum (M V)_x, the tangential resultant f_t,x (obstacle on body) and the normal
one f_n = sum_q w_q phi_n/gamma_q, and max |U_lib - U_getfem| over the nodes.

usage: /usr/bin/python3 bench/getfem_friction.py BUILD_DIR [STEPS]
Writes bench/results/getfem_friction.csv (the coulomb run and the twin's
columns) and bench/results/getfem_friction.txt (the table printed).
"""

import math
import os
import sys

import numpy as np
import getfem as gf

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from getfem_drop import gamma0_field  # noqa: E402  (the same gamma as bench/getfem_drop.py)

NX, NY, LO, HI = 8, 4, (0.0, 0.0), (2.0, 1.0)
YOUNG, POISSON, RHO = 1e4, 0.3, 1.0
LAMBDA = YOUNG * POISSON / ((1 + POISSON) * (1 - 2 * POISSON))  # plane strain
MU = YOUNG / (2 * (1 + POISSON))
ALPHA, FRICTION, THETA_NITSCHE, TAU = 0.5, 0.3, 1.0, 2e-3
RTOL = 1e-12
CONTACT = 1
MASS = RHO * (HI[0] - LO[0]) * (HI[1] - LO[1])


def library(build):
    sys.path.insert(0, os.path.join(os.path.abspath(build), "bindings", "python"))
    import nitschedyn
    return nitschedyn


class Library:
    """The block through the library's Python binding (tests/test_friction.c's block())."""

    def __init__(self, nd, law, coefficient):
        self.nd = nd
        m = nd.Mesh.rectangle(NX, NY, LO, HI)
        m.mark_boundary_box(CONTACT, [-1, -1e-9], [3, 1e-9])
        p = nd.Problem(m, 1)
        p.set_material(YOUNG, POISSON, RHO)
        p.set_contact_plane(CONTACT, [0, 0], [0, 1])
        p.set_nitsche(THETA_NITSCHE, 0)
        p.set_friction(CONTACT, law, coefficient)
        p.set_body_force([math.sin(ALPHA), -math.cos(ALPHA)])
        p.set_scheme(nd.ND_SCHEME_THETA, [1])
        p.set_timestep(TAU)
        p.set_newton(RTOL, 0, 50)
        p.setup()
        self.p = p
        self.x = p.node_coordinates()

    def velocity(self):
        return self.p.field(self.nd.ND_FIELD_VELOCITY)

    def step(self):
        self.p.step()
        nd, p = self.nd, self.p
        return (p.field(nd.ND_FIELD_DISPLACEMENT), p.scalar(nd.ND_MOMENTUM_X),
                p.scalar(nd.ND_CONTACT_FORCE_TANGENTIAL_X), p.scalar(nd.ND_CONTACT_FORCE_APPLIED),
                int(p.scalar(nd.ND_STICKING_POINTS)), int(p.scalar(nd.ND_SLIDING_POINTS)))


def getfem_mesh():
    """nd_mesh_create_rectangle's triangles, same vertices, same diagonals."""
    m = gf.Mesh("empty", 2)
    gt = gf.GeoTrans("GT_PK(2,1)")
    xs = np.linspace(LO[0], HI[0], NX + 1)
    ys = np.linspace(LO[1], HI[1], NY + 1)
    for j in range(NY):
        for i in range(NX):
            a, b, c, d = (xs[i], ys[j]), (xs[i + 1], ys[j]), (xs[i + 1], ys[j + 1]), (xs[i], ys[j + 1])
            m.add_convex(gt, np.array([a, b, c]).T)
            m.add_convex(gt, np.array([a, c, d]).T)
    m.set_region(CONTACT, m.outer_faces_with_direction([0.0, -1.0], 0.01))
    return m


class GetFEM:
    """The same block in GetFEM. reference: 'start' (wt = U^n), 'twin' (wt = the
    return-mapped s at the contact points) or None (frictionless brick)."""

    def __init__(self, gamma0, friction, reference):
        self.friction, self.reference = friction, reference
        m = getfem_mesh()
        self.mf = gf.MeshFem(m, 2)
        self.mf.set_classical_fem(1)
        self.mim = gf.MeshIm(m, gf.Integ("IM_TRIANGLE(2)"))
        self.n = self.mf.nbdof()
        self.c = 1.0 / (TAU * TAU)  # theta-scheme, theta = 1

        mf0, g0 = gamma0_field(m, self.mim, gamma0)

        md = gf.Model("real")
        md.add_fem_variable("u", self.mf)
        md.add_initialized_data("lambda", [LAMBDA])
        md.add_initialized_data("mu", [MU])
        md.add_isotropic_linearized_elasticity_brick(self.mim, "u", "lambda", "mu")
        md.add_initialized_data("c", [self.c * RHO])
        md.add_mass_brick(self.mim, "u", "c")
        self.i_rhs = md.add_explicit_rhs("u", np.zeros(self.n))
        mfs = gf.MeshFem(m, 1)
        mfs.set_classical_fem(1)
        md.add_initialized_fem_data("obstacle", mfs, np.asarray(mfs.basic_dof_nodes()[1], dtype=float))
        md.add_initialized_fem_data("gamma0_getfem", mf0, g0)
        md.add_initialized_data("F", [friction])
        self.G = "((lambda*Trace(Grad_u)*Id(2) + mu*(Grad_u + Grad_u'))*[0;-1])"  # sigma(u) n
        self.gamma = "(element_size/gamma0_getfem)"
        if reference is None:  # G = (n.sigma n) n: no tangential Theta-term (bench/getfem_drop.py)
            G = "((%s.[0;-1])*[0;-1])" % self.G
            md.add_Nitsche_contact_with_rigid_obstacle_brick(self.mim, "u", G, "obstacle", "gamma0_getfem",
                                                             CONTACT, THETA_NITSCHE)
        else:
            if reference in ("start", "local"):
                md.add_initialized_fem_data("wt", self.mf, np.zeros(self.n))
            else:
                self.mimd = gf.MeshImData(self.mim, CONTACT, [2])
                md.add_im_data("wt", self.mimd)
            # GetFEM 5.4 (and its master) writes the slip as "((" + alpha + ")*(u-(wt))",
            # one parenthesis short: alpha = "1)" closes it, the slip is then u - wt
            md.add_Nitsche_contact_with_rigid_obstacle_brick(self.mim, "u", self.G, "obstacle", "gamma0_getfem",
                                                             CONTACT, THETA_NITSCHE, "F", "1)", "wt")
        self.md = md
        self.M = gf.asm_mass_matrix(self.mim, self.mf)
        g = np.zeros(self.n)
        g[0::2], g[1::2] = math.sin(ALPHA), -math.cos(ALPHA)
        self.g = RHO * g
        self.U = np.zeros(self.n)
        self.V = np.zeros(self.n)
        self.x = np.asarray(self.mf.basic_dof_nodes(), dtype=float)

    def traction(self):
        """The brick's traction on the body (obstacle on body), as GWFL."""
        if self.reference is None:
            P = "(u.[0;-1] - obstacle - %s*(%s.[0;-1]))" % (self.gamma, self.G)
            return "(pos_part(%s)/%s*[0;1])" % (P, self.gamma)
        return ("(Coulomb_friction_coupled_projection(%s, [0;-1], (u-wt), obstacle+u(2), F, 1/%s))"
                % (self.G, self.gamma))

    def restart(self, U, V):
        """Start the next step from (U, V) (the 'local' run: one step from the library's state)."""
        self.U, self.V = U.copy(), V.copy()
        self.md.set_variable("u", U)
        self.md.set_variable("wt", U)

    def step(self):
        w = self.c * self.U + self.V / TAU + self.g
        r = np.asarray(self.M.mult(w))
        self.md.set_private_rhs(self.i_rhs, r)
        scale = np.abs(r).sum() + self.c * np.abs(np.asarray(self.M.mult(self.U))).sum()
        res = self.md.solve("max_res", RTOL * scale, "max_iter", 50)
        if isinstance(res, (tuple, list)) and not res[1]:
            raise RuntimeError("GetFEM's Newton did not converge")
        Un = np.array(self.md.variable("u"), dtype=float)
        self.V = (Un - self.U) / TAU
        t = self.traction()
        ft = float(gf.asm_generic(self.mim, 0, "%s(1)" % t, CONTACT, self.md))
        fn = float(gf.asm_generic(self.mim, 0, "%s(2)" % t, CONTACT, self.md))
        if self.reference in ("start", "local"):
            self.md.set_variable("wt", Un)
        elif self.reference == "twin":
            # s <- s + (Y_t - phi_t), Y_t = T(u - s) - gamma sigma_t(u) (docs/design.md §10.2)
            # (the brick's tangential traction is -phi_t/gamma; t = e_x)
            Y = "([1,0;0,0]*(u - wt - %s*%s))" % (self.gamma, self.G)
            s = "wt + %s + %s*[1,0;0,0]*%s" % (Y, self.gamma, self.traction())
            self.md.set_variable("wt", np.asarray(self.md.interpolation(s, self.mimd, CONTACT), dtype=float))
        self.U = Un
        return Un, float(np.asarray(self.M.mult(self.V))[0::2].sum()), ft, fn

    def mean_ux(self, U):
        return float(np.asarray(self.M.mult(U))[0::2].sum()) / MASS


def node_map(lib_x, gf_x):
    """GetFEM dof pairs (x, y) of each library node, by coordinates."""
    key = {(round(x, 9), round(y, 9)): i for i, (x, y) in enumerate(zip(gf_x[0, 0::2], gf_x[1, 0::2]))}
    return np.array([2 * key[(round(x, 9), round(y, 9))] for x, y in lib_x])


def run(nd, law, coefficient, reference, steps):
    lib = Library(nd, law, coefficient)
    ge = GetFEM(lib.p.scalar(nd.ND_GAMMA0), coefficient if reference else 0.0, reference)
    at = node_map(lib.x, ge.x)
    rows = []
    mapped = lambda W: np.bincount(np.concatenate([at, at + 1]), np.concatenate([W[:, 0], W[:, 1]]), ge.n)
    for k in range(steps):
        if reference == "local":
            ge.restart(mapped(lib.p.field(nd.ND_FIELD_DISPLACEMENT)), mapped(lib.velocity()))
        Ul, Pl, ftl, fnl, stick, slide = lib.step()
        Ug, Pg, ftg, fng = ge.step()
        U = mapped(Ul)
        du = float(np.abs(U - Ug).max())
        rows.append(((k + 1) * TAU, ge.mean_ux(U), ge.mean_ux(Ug), Pl, Pg, ftl, ftg, fnl, fng, du, stick, slide))
    return np.array(rows), lib.p.scalar(nd.ND_GAMMA0)


def largest(h):
    """max_n |lib - GetFEM| and max_n |lib| of ux, P_x, f_t,x, f_n; max |dU|."""
    out = []
    for c in (1, 3, 5, 7):
        out.append((float(np.abs(h[:, c] - h[:, c + 1]).max()), float(np.abs(h[:, c]).max())))
    return out, float(h[:, 9].max())


def main(argv):
    if len(argv) not in (2, 3):
        sys.stderr.write(__doc__)
        return 2
    gf.util_trace_level(0)
    gf.util_warning_level(0)
    nd = library(argv[1])
    steps = int(argv[2]) if len(argv) == 3 else 500
    runs = [("coulomb", nd.ND_FRICTION_COULOMB, FRICTION, "start"),
            ("local", nd.ND_FRICTION_COULOMB, FRICTION, "local"),
            ("twin", nd.ND_FRICTION_COULOMB, FRICTION, "twin"),
            ("zero", nd.ND_FRICTION_COULOMB, 0.0, "start"),
            ("none", nd.ND_FRICTION_NONE, None, None)]
    lines = ["block of tests/test_friction.c, P1 8x4, theta = 1, tau = %g, %d steps, Newton rtol %g in both"
             % (TAU, steps, RTOL),
             "max_n |library - GetFEM| (max_n |library|):",
             "%-8s %-22s %-22s %-22s %-22s %s" % ("run", "mean u_x", "momentum P_x", "f_t,x", "f_n", "max |dU|")]
    hist = {}
    for name, law, coef, ref in runs:
        h, gamma0 = run(nd, law, coef, ref, steps)
        hist[name] = h
        cols, du = largest(h)
        lines.append("%-8s " % name + " ".join("%-22s" % ("%.2e (%.3g)" % c) for c in cols) + " %.2e" % du)
    h = hist["coulomb"]
    stick_steps = int((h[:, 10] > 0).sum())
    lines.append("gamma0 = %.6e (ND_GAMMA0); coulomb run: %d of %d steps with a sticking point (library), "
                 "last step f_t,x/f_n = %.12f" % (gamma0, stick_steps, steps, h[-1, 5] / h[-1, 7]))
    h = hist["local"]
    for what, rows in (("with a sticking point", h[:, 10] > 0), ("all active points sliding", h[:, 10] == 0)):
        if rows.any():
            cols, du = largest(h[rows])
            lines.append("local, %d steps %s: max |dU| %.2e, |d f_t,x| %.2e, |d f_n| %.2e"
                         % (int(rows.sum()), what, du, cols[2][0], cols[3][0]))
    h = hist["coulomb"]
    first = np.nonzero(np.abs(h[:, 9]) > 1e-12 * np.abs(h[:, 1]).max())[0]
    if first.size:
        k = int(first[0])
        lines.append("coulomb run: the first step where |dU| > 1e-12 max|u_x| is %d (t = %g; library sticking %d, "
                     "sliding %d)" % (k + 1, h[k, 0], h[k, 10], h[k, 11]))
    text = "\n".join(lines)
    print(text)
    out = os.path.join(HERE, "results")
    with open(os.path.join(out, "getfem_friction.txt"), "w") as f:
        f.write(text + "\n")
    t = hist["twin"]
    with open(os.path.join(out, "getfem_friction.csv"), "w") as f:
        f.write("t,ux_lib,ux_getfem,px_lib,px_getfem,ft_lib,ft_getfem,fn_lib,fn_getfem,du_max,"
                "sticking_lib,sliding_lib,ux_twin,px_twin,ft_twin,fn_twin,du_twin\n")
        for a, b in zip(h, t):
            f.write(",".join("%.12g" % v for v in list(a) + [b[2], b[4], b[6], b[8], b[9]]) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
