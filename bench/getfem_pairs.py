#!/usr/bin/python3
"""Two deformable bodies side by side with GetFEM (issue 59): GetFEM's Nitsche
large-sliding raytracing brick, unbiased and biased, against the library's
master/slave contact pair (docs/design.md §10.3), both at Theta = 0.

Cases (P1 triangles, plane strain, frictionless, one mesh holding both bodies):

  bars N      two rectangles [0,1]x[0,1/2] and [1+g,2+g]x[0,1/2], g = 0.01,
              N x N/2 cells each (nd_mesh_create_rectangle's triangles),
              E = 1, nu = 0.3, rho = 1, thrown head-on at +-V0 along x
  bars~ N     the same, the right bar with N x (N/2 + N/8) cells: its
              contact face's nodes are not the left one's (non-matching)
  disks h     examples/meshes/two_disks_hH.msh (radius 20, 1 apart,
              lambda = mu = 20, rho = 1) thrown at -+1 along y
              (tests/test_pairs.c's mirror disks)

Region 1 (the left bar's right face, the upper disk's lower half) is the
library's slave and GetFEM's biased slave; region 2 the master. Both codes:
the same vertices and cells, the same gamma = gamma0 h_K (the library's
automatic gamma0 at Theta = 0, ND_GAMMA0; GetFEM's brick takes
r = Nitsche_param/element_size = 1/gamma, Nitsche_param a P0 field equal to
element_size_K/(gamma0 h_K) cell by cell, bench/getfem_drop.py's
gamma0_field), the consistent mass, the face rule IM_TRIANGLE(2) (the
2-point Gauss rule of ours), implicit Euler (the theta-scheme at theta = 1,
bench/getfem_friction.py's loop around Model.solve), Newton stopped at
||G||_1 <= 1e-10 (||r||_1 + c ||M U^n||_1) in both, small-strain stress
sigma(u) (GetFEM: the linearized elasticity brick and, for the brick's
traction, sigma(u) Normal).

GetFEM's brick (getfem_contact_and_friction_large_sliding.cc, 5.4) is a
Theta = 0 Nitsche method only (no Theta-term): its traction is
Coulomb_friction_coupled_projection(sigma(u) N, n_x, Vs, g, F = 0, 1/gamma),
with F = 0 the pressure [-(sigma(u) N).n_x - g/gamma]_+ along -n_x on the
slave (ours: [P_q]_+/gamma_q, P_q = a_q U - gamma_q s_q U - g_q), with
  n_x  the slave's unit normal in the deformed configuration
       (Transformed_unit_vector(Grad_u, Normal)), a function of u,
  y    the master point hit by the ray from x + u(x) along n_x
       (raytracing transformation, redone at every Newton iteration),
  g    (y + u(y) - x - u(x)) . n_x, the gap along the ray, exactly,
and the biased form integrates it on the slave with weight 1 against the
master's test functions at y, the unbiased form on both surfaces, each the
other's master, with weight 1/2 each. The library's rows freeze, within a
step, the nearest-point pairing made at U^n, the master facet's normal and
the gap linearized at U^n (docs/design.md §10.3).

Per step (both codes, on GetFEM's DOFs, the library's fields mapped by
coordinates): each body's momentum P_b = sum_i (M V)_i along the impact
direction, its centre displacement (1/m_b) sum_i (M U)_i, the total momentum,
the contact resultant on body 1, (P_1^{n+1} - P_1^n)/tau (implicit Euler:
exactly the contact force the step applied, as K's rows of a body sum to
zero), the energy E = 1/2 V'MV + 1/2 U'KU, and max |U_lib - U_getfem|.

usage: /usr/bin/python3 bench/getfem_pairs.py BUILD_DIR [quick]
Writes bench/results/getfem_pairs.txt (the tables) and getfem_pairs.csv (for
bars N=16, bars~ N=16 and the disks, per step: P1, c1, F1, E, Q1, L1 of the
library, the library with the roles swapped, GetFEM biased and unbiased).
"""

import os
import sys
import time

import numpy as np
import getfem as gf

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from getfem_drop import gamma0_field, load_mesh  # noqa: E402  (the same gamma, the same Gmsh import)

MESHES = os.path.join(os.path.dirname(HERE), "examples", "meshes")
SLAVE, MASTER = 1, 2
RTOL = 1e-10
GAP = 0.01


def library(build):
    sys.path.insert(0, os.path.join(os.path.abspath(build), "bindings", "python"))
    import nitschedyn
    return nitschedyn


# ---- the cases -------------------------------------------------------------------


def block(x0, x1, y0, y1, nx, ny, base):
    """nd_mesh_create_rectangle's vertices and triangles (a,b,c), (a,c,d)."""
    xs, ys = np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1)
    X = np.array([(x, y) for y in ys for x in xs])
    at = lambda i, j: base + j * (nx + 1) + i
    T = []
    for j in range(ny):
        for i in range(nx):
            a, b, c, d = at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)
            T += [(a, b, c), (a, c, d)]
    return X, np.array(T)


class Case:
    """Vertices, triangles, the two contact faces and the bodies of one case."""

    def __init__(self, name, h, coords, cells, body, axis, velocity, young, poisson, tau, steps, release,
                 msh=None):
        self.name, self.h, self.x, self.cells, self.body, self.axis = name, h, coords, cells, body, axis
        self.velocity, self.young, self.poisson, self.tau, self.steps = velocity, young, poisson, tau, steps
        self.release, self.msh = release, msh
        self.lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))  # plane strain
        self.mu = young / (2 * (1 + poisson))


def bars(N, nonmatching, v0, tau=0.01, T=None):
    T = T or max(3.0, GAP / (2 * v0) + 2.5)  # (they touch at GAP/(2 v0), part about 2 later)
    ny = N // 2
    X1, T1 = block(0, 1, 0, 0.5, N, ny, 0)
    X2, T2 = block(1 + GAP, 2 + GAP, 0, 0.5, N, ny + (N // 8 if nonmatching else 0), len(X1))
    x = np.vstack([X1, X2])
    body = np.r_[np.zeros(len(X1), int), np.ones(len(X2), int)]
    name = "bars%s N=%d%s" % ("~" if nonmatching else "", N, "" if v0 == 0.1 else " v=%g" % v0)
    return Case(name, 1.0 / N, x, np.vstack([T1, T2]), body, 0, v0, 1.0, 0.3, tau, int(round(T / tau)), 0.25)


def disks(h, tau, T=12.0):
    return Case("disks h=%g" % h, h, None, None, None, 1, 1.0, 50.0, 0.25, tau, int(round(T / tau)), 3.0 + h,
                msh=os.path.join(MESHES, "two_disks_h%g.msh" % h))


# ---- the library -------------------------------------------------------------------


class Library:
    def __init__(self, nd, case, slave=SLAVE, master=MASTER):
        self.nd = nd
        if case.msh:
            m = nd.Mesh.read_gmsh(case.msh)
        else:
            m = nd.Mesh(case.x, case.cells)
            for region, at in ((SLAVE, 1.0), (MASTER, 1.0 + GAP)):
                m.mark_boundary_box(region, [at - 1e-9, -1.0], [at + 1e-9, 1.0])
        p = nd.Problem(m, 1)
        p.set_material(case.young, case.poisson, 1.0)
        p.set_contact_pair(slave, master)
        p.set_nitsche(0.0, 0.0)
        # Theta = 0 with the automatic gamma0 gains energy at impacts (docs/design.md §3b): the
        # balance guard would refuse it (tests/test_pairs.c switches it off for Theta <= 0 too)
        p.set_guard(nd.ND_GUARD_ENERGY_BALANCE, 0)
        p.set_scheme(nd.ND_SCHEME_THETA, [1])
        p.set_timestep(case.tau)
        p.set_newton(RTOL, 0, 50)
        self.x = p.node_coordinates()
        if case.msh:
            case.body = (self.x[:, 1] < 0).astype(int)  # 0: the upper disk (region 1 is its lower half)
        up = case.body[:len(self.x)] if not case.msh else case.body
        v = np.zeros_like(self.x)
        v[:, case.axis] = np.where(up == 0, 1.0, -1.0) * case.velocity * (1 if case.axis == 0 else -1)
        p.set_initial_state(None, v)
        p.setup()
        self.p = p
        self.gamma0 = p.scalar(nd.ND_GAMMA0)

    def state(self):
        nd = self.nd
        return self.p.field(nd.ND_FIELD_DISPLACEMENT), self.p.field(nd.ND_FIELD_VELOCITY)

    def step(self):
        self.p.step()
        return self.p.scalar(self.nd.ND_CONTACT_FORCE_APPLIED)


# ---- GetFEM -----------------------------------------------------------------------


def getfem_mesh(case):
    if case.msh:
        return load_mesh(case.msh, 2)  # regions 1 and 2: the physical curves
    m = gf.Mesh("empty", 2)
    gt = gf.GeoTrans("GT_PK(2,1)")
    for t in case.cells:
        m.add_convex(gt, case.x[t].T)
    for region, at in ((SLAVE, 1.0), (MASTER, 1.0 + GAP)):
        m.set_region(region, m.outer_faces_in_box([at - 1e-9, -1.0], [at + 1e-9, 1.0]))
    return m


class GetFEM:
    """Implicit Euler around Model.solve with the Nitsche large-sliding brick."""

    def __init__(self, case, m, gamma0, unbiased, U0, V0):
        self.case, self.tau = case, case.tau
        self.mf = gf.MeshFem(m, 2)
        self.mf.set_classical_fem(1)
        self.mim = gf.MeshIm(m, gf.Integ("IM_TRIANGLE(2)"))
        self.n = self.mf.nbdof()
        self.c = 1.0 / (self.tau * self.tau)
        mf0, g0 = gamma0_field(m, self.mim, gamma0)
        md = gf.Model("real")
        md.add_fem_variable("u", self.mf)
        md.add_initialized_data("lambda", [case.lam])
        md.add_initialized_data("mu", [case.mu])
        md.add_isotropic_linearized_elasticity_brick(self.mim, "u", "lambda", "mu")
        md.add_initialized_data("c", [self.c])
        md.add_mass_brick(self.mim, "u", "c")
        self.i_rhs = md.add_explicit_rhs("u", np.zeros(self.n))
        md.add_initialized_fem_data("nitsche_param", mf0, g0)  # r = nitsche_param/element_size = 1/gamma
        sigma = "((lambda*Trace(Grad_u)*Id(2) + mu*(Grad_u + Grad_u'))*Normal)"
        ib = md.add_Nitsche_large_sliding_contact_brick_raytracing(1 if unbiased else 0, "nitsche_param",
                                                                   case.release, "0", "1")
        if unbiased:
            md.add_contact_boundary_to_unbiased_Nitsche_large_sliding_contact_brick(ib, self.mim, SLAVE, "u", sigma)
            md.add_contact_boundary_to_unbiased_Nitsche_large_sliding_contact_brick(ib, self.mim, MASTER, "u", sigma)
        else:
            md.add_master_contact_boundary_to_biased_Nitsche_large_sliding_contact_brick(ib, self.mim, MASTER, "u")
            md.add_slave_contact_boundary_to_biased_Nitsche_large_sliding_contact_brick(ib, self.mim, SLAVE, "u",
                                                                                        sigma)
        self.md = md
        self.U, self.V = U0.copy(), V0.copy()
        md.set_variable("u", self.U)
        self.newton = 0

    def step(self):
        M = self.case.M
        r = np.asarray(M.mult(self.c * self.U + self.V / self.tau))
        self.md.set_private_rhs(self.i_rhs, r)
        scale = np.abs(r).sum() + self.c * np.abs(np.asarray(M.mult(self.U))).sum()
        res = self.md.solve("max_res", RTOL * scale, "max_iter", 50)
        its, ok = (res[0], res[1]) if isinstance(res, (tuple, list)) else (res, 1)
        if not ok:
            raise RuntimeError("GetFEM's Newton did not converge")
        self.newton += int(its)
        Un = np.array(self.md.variable("u"), dtype=float)
        self.V = (Un - self.U) / self.tau
        self.U = Un


# ---- side by side -------------------------------------------------------------------


class Measures:
    """The histories' quantities from (U, V) on GetFEM's DOFs."""

    def __init__(self, case, mf, mim):
        self.M = gf.asm_mass_matrix(mim, mf)
        aux = gf.Model("real")
        aux.add_fem_variable("u", mf)
        aux.add_initialized_data("lambda", [case.lam])
        aux.add_initialized_data("mu", [case.mu])
        self.K = gf.asm_generic(mim, 2, "lambda*Div_Test_u*Div_Test2_u + 2*mu*Sym(Grad_Test_u):Sym(Grad_Test2_u)",
                                -1, aux)
        X = np.asarray(mf.basic_dof_nodes(), dtype=float)
        self.X = X
        d = case.axis
        sel = np.zeros(mf.nbdof(), bool)
        sel[d::2] = True
        first = X[0] < 1 + GAP / 2 if case.msh is None else X[1] > 0
        self.e = [sel & first, sel & ~first]  # body 1 (slave side), body 2, impact components
        ones = np.zeros(mf.nbdof())
        ones[d::2] = 1
        Mo = np.asarray(self.M.mult(ones))
        self.mass = [Mo[e].sum() for e in self.e]
        # body 1's transverse momentum and angular momentum about its centre of mass (reference positions)
        t = np.zeros(mf.nbdof(), bool)
        t[1 - d::2] = True
        self.t1 = t & first
        self.arm = np.zeros(mf.nbdof())  # (MV)_x -> -(y - yc), (MV)_y -> (x - xc)
        w = Mo * self.e[0]
        xc, yc = (w @ X[0]) / w.sum(), (w @ X[1]) / w.sum()
        self.arm[0::2] = np.where(first[0::2], -(X[1][0::2] - yc), 0.0)
        self.arm[1::2] = np.where(first[1::2], X[0][1::2] - xc, 0.0)

    def __call__(self, U, V):
        MU, MV = np.asarray(self.M.mult(U)), np.asarray(self.M.mult(V))
        P = [MV[e].sum() for e in self.e]
        c = [MU[e].sum() / m for e, m in zip(self.e, self.mass)]
        E = 0.5 * float(V @ MV) + 0.5 * float(U @ np.asarray(self.K.mult(U)))
        return P, c, E, MV[self.t1].sum(), float(self.arm @ MV)


def node_map(lib_x, X):
    key = {(round(x, 7), round(y, 7)): i for i, (x, y) in enumerate(zip(X[0, 0::2], X[1, 0::2]))}
    return np.array([2 * key[(round(x, 7), round(y, 7))] for x, y in lib_x])


def run(nd, case):
    """The library (slave 1, master 2; and slave 2, master 1) and GetFEM (biased, unbiased):
    histories (steps+1, 6) t, P1, P2, c1, c2, F1, E per code, and max |dU| per GetFEM run."""
    lib = Library(nd, case)
    lib_swap = Library(nd, case, MASTER, SLAVE)
    m = getfem_mesh(case)
    mf = gf.MeshFem(m, 2)
    mf.set_classical_fem(1)
    mim = gf.MeshIm(m, gf.Integ("IM_TRIANGLE(2)"))
    meas = Measures(case, mf, mim)
    case.M = meas.M
    at = node_map(lib.x, meas.X)
    n = mf.nbdof()

    def mapped(W):
        out = np.zeros(n)
        out[at], out[at + 1] = W[:, 0], W[:, 1]
        return out

    U0, V0 = (mapped(w) for w in lib.state())
    runs = {"lib": lib, "lib21": lib_swap,
            "biased": GetFEM(case, m, lib.gamma0, False, U0, V0),
            "unbiased": GetFEM(case, m, lib.gamma0, True, U0, V0)}
    hist = {k: [] for k in runs}
    dU = {k: 0.0 for k in runs}
    dUt = {k: [] for k in runs}
    Umax = 0.0
    seconds = {k: 0.0 for k in runs}
    applied = []
    states = {}
    for k, r in runs.items():
        U, V = (mapped(w) for w in r.state()) if k.startswith("lib") else (r.U, r.V)
        P, c, E, Q, Lm = meas(U, V)
        hist[k].append([0.0, P[0], P[1], c[0], c[1], 0.0, E, Q, Lm])
    for s in range(case.steps):
        for k, r in runs.items():
            t0 = time.perf_counter()
            f = r.step()
            seconds[k] += time.perf_counter() - t0
            if k == "lib":
                applied.append(f)
            U, V = (mapped(w) for w in r.state()) if k.startswith("lib") else (r.U, r.V)
            states[k] = U
            P, c, E, Q, Lm = meas(U, V)
            F = (P[0] - hist[k][-1][1]) / case.tau
            hist[k].append([(s + 1) * case.tau, P[0], P[1], c[0], c[1], F, E, Q, Lm])
        Umax = max(Umax, float(np.abs(states["lib"]).max()))
        for k in runs:
            d = np.abs(states[k] - states["lib"])
            dU[k] = max(dU[k], float(d.max()))
            dUt[k].append((float(d[case.axis::2].max()), float(d[1 - case.axis::2].max())))
    h = {k: np.array(v) for k, v in hist.items()}
    # the library's own resultant (sum_q w_q phi_q/gamma_q) against (P1^{n+1} - P1^n)/tau
    check = float(np.abs(np.abs(h["lib"][1:, 5]) - np.array(applied)).max())
    newton = {k: (r.newton if hasattr(r, "newton") else int(r.p.scalar(nd.ND_NEWTON_ITERATIONS_TOTAL)))
              for k, r in runs.items()}
    return dict(h=h, dU=dU, dUt={k: np.array(v) for k, v in dUt.items()}, Umax=Umax, seconds=seconds,
                check=check, gamma0=lib.gamma0, newton=newton,
                dofs=n, points=lib.p.contact_point_count)


COLS = ((5, "F1"), (1, "P1"), (3, "c1"), (6, "E"))
CSV_CASES = ("bars N=16", "bars~ N=16", "disks h=4", "disks h=2")  # (the CSV's histories: these cases)
CSV_COLS = (1, 3, 5, 6, 7, 8)  # P1, c1, F1, E, Q1, L1


def compare(a, b):
    """max_n |a - b| / max_n |a| for the contact resultant, body 1's momentum and centre, the energy."""
    return [float(np.abs(a[:, c] - b[:, c]).max() / np.abs(a[:, c]).max()) for c, _ in COLS]


def summary(h):
    """first and last step with a contact force, body 1's final velocity (P1/m1 ~ P1/P1(0) v0)."""
    on = np.nonzero(np.abs(h[:, 5]) > 1e-6 * np.abs(h[:, 5]).max())[0]
    return (h[on[0], 0], h[on[-1], 0]) if on.size else (0, 0), h[-1, 1] / h[0, 1]


def main(argv):
    if len(argv) not in (2, 3):
        sys.stderr.write(__doc__)
        return 2
    gf.util_trace_level(0)
    gf.util_warning_level(0)
    nd = library(argv[1])
    quick = len(argv) == 3 and argv[2] == "quick"
    Ns = (8, 16) if quick else (8, 16, 32, 64)
    cases = [bars(N, False, 0.1) for N in Ns] + [bars(N, True, 0.1) for N in Ns]
    if not quick:
        cases += [bars(8, False, 0.01), bars(16, False, 0.01), bars(8, False, 0.001), bars(8, True, 0.01),
                  disks(4, 0.05), disks(2, 0.05)]
    rows, csv = [], []
    for case in cases:
        t0 = time.perf_counter()
        r = run(nd, case)
        h = r["h"]
        rows.append((case, r))
        drift = {k: float(np.abs(v[:, 1] + v[:, 2] - v[0, 1] - v[0, 2]).max()) for k, v in h.items()}
        print("%-18s dofs %5d  gamma0 %.4g  %.1f s  (lib applied-force check %.1e)"
              % (case.name, r["dofs"], r["gamma0"], time.perf_counter() - t0, r["check"]), flush=True)
        for k in ("lib21", "biased", "unbiased"):
            d = compare(h["lib"], h[k])
            print("   lib vs %-8s " % k + " ".join("%s %.2e" % (n, x) for (_, n), x in zip(COLS, d))
                  + "  max|dU|/max|U| %.2e  drift %.1e" % (r["dU"][k] / r["Umax"], drift[k]), flush=True)
        if case.name in CSV_CASES:
            for i in range(len(h["lib"])):
                csv.append("%s,%.6g,%s" % (case.name, h["lib"][i][0], ",".join(
                    "%.7g" % h[k][i][c] for k in ("lib", "lib21", "biased", "unbiased") for c in CSV_COLS)))
    write(rows, csv)
    return 0


def write(rows, csv):
    L = []
    L.append("bench/getfem_pairs.py: library master/slave (Theta = 0, slave = region 1) against GetFEM 5.4's")
    L.append("Nitsche large-sliding raytracing brick (biased: slave 1, master 2; unbiased: both, weight 1/2),")
    L.append("same mesh, gamma = gamma0 h_K, implicit Euler, Newton rtol %g. Relative differences" % RTOL)
    L.append("max_n |lib - other| / max_n |lib| of: F1 the contact resultant on body 1, P1 its momentum,")
    L.append("c1 its centre displacement, E = 1/2 V'MV + 1/2 U'KU; dU = max |U_lib - U_other| / max |U_lib|.")
    L.append("lib21: the library with the roles swapped (slave 2, master 1): master/slave's own bias.")
    L.append("")
    L.append("|dPtot| = max_n |P1 + P2 - P1(0) - P2(0)| / |P1(0)|; Q1, L1: max_n of body 1's transverse momentum "
             "and angular")
    L.append("momentum about its centre of mass, / |P1(0)| (L1 also / the body's length 1 or radius 20); t_on, t_off:")
    L.append("first and last step with a contact force > 1e-6 of its largest; rebound: P1(end)/P1(0) "
             "(the disks still touch at t = 12).")
    L.append("")
    L.append("%-18s %5s %5s %-9s %9s %9s %9s %9s %9s %8s %8s %8s %6s %6s %8s" % (
        "case", "h", "steps", "other", "F1", "P1", "c1", "E", "dU", "|dPtot|", "Q1", "L1", "t_on", "t_off",
        "rebound"))
    T = ["", "timing: seconds in the steps of the whole run (the same process, one after the other at every",
         "step); Newton iterations in total; dofs; gamma0 (the library's automatic value at Theta = 0); check:",
         "max_n | |(P1^{n+1} - P1^n)/tau| - ND_CONTACT_FORCE_APPLIED | / max |F1| (the resultant taken from the",
         "momentum against the library's sum_q w_q phi_q/gamma_q: equal on the flat faces; on the disks the",
         "library's sums the normal magnitudes, not their y components)",
         "%-18s %8s %8s %8s %8s %8s %8s %6s %6s %6s %5s %9s %8s" % (
             "case", "lib", "biased", "unbiased", "lib21", "gf_b/lib", "gf_u/lib", "its", "its_b", "its_u",
             "dofs", "gamma0", "check")]
    for case, r in rows:
        h = r["h"]
        for k in ("lib", "lib21", "biased", "unbiased"):
            v = h[k]
            drift = float(np.abs(v[:, 1] + v[:, 2] - v[0, 1] - v[0, 2]).max())
            (on, off), vend = summary(v)
            P0 = abs(v[0, 1])
            length = 20.0 if case.msh else 1.0
            q, l = np.abs(v[:, 7]).max() / P0, np.abs(v[:, 8]).max() / (P0 * length)
            drift /= P0
            if k == "lib":
                L.append("%-18s %5.3g %5d %-9s %9s %9s %9s %9s %9s %8.1e %8.1e %8.1e %6.3f %6.3f %8.5f"
                         % (case.name, case.h, case.steps, k, "", "", "", "", "", drift, q, l, on, off, vend))
            else:
                d = compare(h["lib"], v)
                L.append("%-18s %5s %5s %-9s %9.2e %9.2e %9.2e %9.2e %9.2e %8.1e %8.1e %8.1e %6.3f %6.3f %8.5f"
                         % ("", "", "", k, d[0], d[1], d[2], d[3], r["dU"][k] / r["Umax"], drift, q, l, on, off,
                            vend))
        s = r["seconds"]
        nw = r["newton"]
        T.append("%-18s %8.3f %8.3f %8.3f %8.3f %8.0f %8.0f %6d %6d %6d %5d %9.4g %8.1e" % (
            case.name, s["lib"], s["biased"], s["unbiased"], s["lib21"], s["biased"] / s["lib"],
            s["unbiased"] / s["lib"], nw["lib"], nw["biased"], nw["unbiased"], r["dofs"], r["gamma0"],
            r["check"] / np.abs(h["lib"][:, 5]).max()))
    text = "\n".join(L + T)
    print(text)
    out = os.path.join(HERE, "results")
    with open(os.path.join(out, "getfem_pairs.txt"), "w") as f:
        f.write(text + "\n")
    with open(os.path.join(out, "getfem_pairs.csv"), "w") as f:
        f.write("case,t," + ",".join("%s_%s" % (q, k) for k in ("lib", "lib21", "biased", "unbiased")
                                     for q in ("P1", "c1", "F1", "E", "Q1", "L1")) + "\n")
        f.write("\n".join(csv) + "\n")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
