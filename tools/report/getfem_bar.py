#!/usr/bin/python3
"""The 1D bar of docs/design.md §7 solved by GetFEM, measured by our own norm code.

GetFEM (python3-getfem) does the finite element work: mesh, P1/P2 Lagrange
space, assembly of mass and stiffness, the Nitsche contact term (GetFEM's
add_Nitsche_contact_with_rigid_obstacle_brick) and the semi-smooth Newton
solve of every time step (Model.solve). This script only runs the Newmark
recursion around GetFEM's model, and measures the result with the error
norms of examples/bar1d_exact.c (through ctypes, build/tools/report/
libbar1d_exact.so), sampled exactly as examples/bar1d.c samples our library:
every time level t_n = n tau, trapezoidal weights in time.

The problem: Omega = (0,1), rho = E = 1, u(1) = 0, rigid obstacle at x = 0
(gap 0, contact normal n = -1, so u_n = -u(0), sigma_n(u) = u_x(0)),
u0 = (1-x)/2, v0 = 0, no load. Nitsche in the paper's convention:
gamma = gamma0 h, P_gamma(u) = u_n - gamma sigma_n(u),
  (rho u'', v) + a(u, v) - Theta gamma sigma_n(u) sigma_n(v)
                 + (1/gamma) [P_gamma(u)]_+ (v_n - Theta gamma sigma_n(v)) = 0.

Parameter convention. GetFEM's Nitsche brick builds its term with the
augmentation parameter r = gamma0_getfem / element_size, i.e. its gamma is
element_size / gamma0_getfem. The paper's gamma is gamma0 * h. So this script
passes gamma0_getfem = 1 / gamma0 (paper); the CSV reports the paper's value.
--check-brick verifies, at random states, that the residual and the tangent
matrix GetFEM assembles equal the paper's formula above to round-off.

Newmark (beta, gamma), consistent mass, fixed step tau; per step GetFEM solves
  (c M + K_Theta) U + N(U) = M [c U^n + V^n/(beta tau) + (1/(2 beta) - 1) A^n]
with c = 1/(beta tau^2): a mass brick with coefficient c plus an explicit
right-hand side brick, updated every step. Initial acceleration:
M A^0 = -K_Theta U^0 - N(U^0), the full Nitsche residual of GetFEM's model
at U^0 (mass and right-hand side bricks disabled), solved by GetFEM.

Newton stopping. Model.solve (GetFEM 5.4.2, default line search) runs
GetFEM's Newton_with_step_control, which stops when ||G||_1 / eln <= max_res,
where eln (GetFEM's "approximate external load norm") is 1 for this model:
an absolute residual, unreachable for P2 on fine meshes if fixed. So each
step passes max_res = rtol * (||r||_1 + ||c M U^n||_1), r the right-hand side
above: the relative rule of our library (||G|| <= 1e-10 (||r|| + ||cMU||)),
in GetFEM's 1-norm; rtol = --newton-rtol, default 1e-12 (its round-off floor
is near 1e-16 here; 1e-10 gives the same results and iteration counts).
Newton iterations per step are what Model.solve returns.

Linear solver: --lsolver auto (GetFEM's choice; MUMPS in Debian's build).
'superlu' crashes (segmentation fault) in Debian's python3-getfem 5.4.2.

Usage (from the repository root, after `make all`):
  /usr/bin/python3 tools/report/getfem_bar.py \
      --lib build/tools/report/libbar1d_exact.so --nx 20,40,80 --degree 1,2 \
      --Theta 1 --gamma0 0.2 --beta 0.25 --gamma 0.5 --T 3 --tau-over-h 0.5 \
      --repeat 3 --csv out.csv
"""

import argparse
import csv as csvmod
import ctypes
import os
import statistics
import sys
import time

import numpy as np
import getfem as gf

CSV_COLUMNS = ("code,study,scheme,degree,Theta,gamma0,lumped,nx,tau,T,steps,setup_s,loop_s,repeats,"
               "newton_its,energy_drift,e_linf_l2_u,e_linf_h1_u,e_linf_l2_v,e_l2_l2_u,e_l2_h1_u,"
               "e_l2_l2_v,e_l2_stress,status").split(",")
N_NORMS = 7
CONTACT, CLAMPED = 1, 2  # mesh regions


# ---- our norm code (examples/bar1d_exact.h) through ctypes -----------------

class Phase(ctypes.Structure):
    _fields_ = [("k", ctypes.c_int), ("r", ctypes.c_double)]


class Grid(ctypes.Structure):
    _fields_ = [("degree", ctypes.c_int), ("n_nodes", ctypes.c_int64), ("n_cells", ctypes.c_int64),
                ("x", ctypes.POINTER(ctypes.c_double)), ("id", ctypes.POINTER(ctypes.c_int64))]


class SpaceNorms(ctypes.Structure):
    _fields_ = [("err", ctypes.c_double * 3), ("ref", ctypes.c_double * 3)]


class NormAcc(ctypes.Structure):
    _fields_ = [("err", ctypes.c_double * N_NORMS), ("ref", ctypes.c_double * N_NORMS)]


def load_norm_lib(path):
    lib = ctypes.CDLL(os.path.abspath(path))
    dp = ctypes.POINTER(ctypes.c_double)
    lib.phase_at.argtypes = [ctypes.c_double]
    lib.phase_at.restype = Phase
    lib.exact_stress.argtypes = [Phase]
    lib.exact_stress.restype = ctypes.c_double
    lib.grid_init.argtypes = [ctypes.POINTER(Grid), ctypes.c_int, ctypes.c_int64, dp, ctypes.c_int64]
    lib.grid_init.restype = ctypes.c_int
    lib.grid_free.argtypes = [ctypes.POINTER(Grid)]
    lib.grid_free.restype = None
    lib.norms_at.argtypes = [ctypes.POINTER(Grid), dp, dp, Phase]
    lib.norms_at.restype = SpaceNorms
    lib.acc_add.argtypes = [ctypes.POINTER(NormAcc), ctypes.POINTER(SpaceNorms), ctypes.c_double, ctypes.c_double,
                            ctypes.c_double]
    lib.acc_add.restype = None
    lib.acc_relative.argtypes = [ctypes.POINTER(NormAcc), ctypes.c_int]
    lib.acc_relative.restype = ctypes.c_double
    return lib


def as_dp(a):
    return a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


# ---- the GetFEM model --------------------------------------------------------

class Bar:
    """GetFEM's discretisation of the bar and its Newmark recursion."""

    def __init__(self, nx, degree, Theta, gamma0, beta, gamma_nm, tau, rtol, max_iter, lsolver):
        self.nx, self.degree, self.Theta, self.tau = nx, degree, Theta, tau
        self.beta, self.gamma_nm = beta, gamma_nm
        self.h = 1.0 / nx
        self.gamma = gamma0 * self.h  # paper convention
        self.c = 1.0 / (beta * tau * tau)
        self.rtol = rtol
        self.solve_opts = ["max_iter", max_iter]
        if lsolver != "auto":
            self.solve_opts += ["lsolver", lsolver]

        m = gf.Mesh("regular simplices", np.linspace(0.0, 1.0, nx + 1))
        self.mf = gf.MeshFem(m, 1)
        self.mf.set_fem(gf.Fem("FEM_PK(1,%d)" % degree))
        self.mim = gf.MeshIm(m, gf.Integ("IM_GAUSS1D(%d)" % max(4, 2 * degree)))  # exact for M and K
        faces = m.outer_faces()
        normals = m.normal_of_faces(faces)[0]
        m.set_region(CONTACT, faces[:, normals < 0])  # x = 0, outward normal -1
        m.set_region(CLAMPED, faces[:, normals > 0])  # x = 1
        self.x = np.asarray(self.mf.basic_dof_nodes()[0], dtype=float).copy()
        n = self.x.size
        if n != nx * degree + 1 or self.mf.nbdof() != n:
            raise RuntimeError("unexpected DOF count %d" % n)

        md = gf.Model("real")
        md.add_fem_variable("u", self.mf)
        md.add_Laplacian_brick(self.mim, "u")  # E = 1: sigma = u_x
        md.add_initialized_data("c", [self.c])
        self.i_mass = md.add_mass_brick(self.mim, "u", "c")  # c M, rho = 1
        self.i_rhs = md.add_explicit_rhs("u", np.zeros(n))
        md.add_Dirichlet_condition_with_simplification("u", CLAMPED)
        # obstacle: signed distance to the plane x = 0 (its gradient gives the
        # contact normal -grad/|grad| = -1, the gap at x = 0 is 0)
        md.add_initialized_fem_data("obstacle", self.mf, self.x.copy())
        md.add_initialized_data("gamma0_getfem", [1.0 / gamma0])  # GetFEM: gamma = h / gamma0_getfem
        neumann = md.Neumann_term("u", CONTACT)  # Grad_u.Normal = sigma n
        self.i_contact = md.add_Nitsche_contact_with_rigid_obstacle_brick(
            self.mim, "u", neumann, "obstacle", "gamma0_getfem", CONTACT, Theta)
        self.md = md

        # Matrices for the Newmark right-hand side and the energies, and the
        # rows a (a.U = u(0)) and s (s.U = u_x(0) in the first cell).
        self.M = gf.asm_mass_matrix(self.mim, self.mf)
        self.K = gf.asm_generic(self.mim, 2, "Grad_Test2_u.Grad_Test_u", -1, md)
        self.a_row = np.asarray(gf.asm_generic(self.mim, 1, "Test_u", CONTACT, md), dtype=float).ravel()
        self.s_row = np.asarray(gf.asm_generic(self.mim, 1, "Grad_Test_u", CONTACT, md), dtype=float).ravel()
        self.clamped = np.asarray(self.mf.basic_dof_on_region(CLAMPED), dtype=int)

        self.U = 0.5 * (1.0 - self.x)
        self.U[self.clamped] = 0.0
        self.V = np.zeros(n)
        md.set_variable("u", self.U)
        self.A = self.initial_acceleration()

    def initial_acceleration(self):
        """M A0 = -K_Theta U0 - N(U0): GetFEM's residual at U0 without mass and rhs."""
        md = self.md
        md.disable_bricks([self.i_mass, self.i_rhs])
        md.assembly("build_rhs")
        F = np.array(md.rhs(), dtype=float)  # GetFEM's rhs is minus the residual
        md.enable_bricks([self.i_mass, self.i_rhs])
        F[self.clamped] = 0.0
        ma = gf.Model("real")
        ma.add_fem_variable("a", self.mf)
        ma.add_mass_brick(self.mim, "a")
        ma.add_explicit_rhs("a", F)
        ma.add_Dirichlet_condition_with_simplification("a", CLAMPED)
        ma.solve()
        return np.array(ma.variable("a"), dtype=float)

    def step(self):
        """One Newmark step; returns the Newton iterations GetFEM reports."""
        b, tau = self.beta, self.tau
        w = self.c * self.U + self.V / (b * tau) + (0.5 / b - 1.0) * self.A
        r = np.asarray(self.M.mult(w))
        self.md.set_private_rhs(self.i_rhs, r)
        # GetFEM's max_res is an absolute bound on ||G||_1 (its external load
        # norm is 1 for this model): make it relative, as in our library.
        scale = np.abs(r).sum() + self.c * np.abs(np.asarray(self.M.mult(self.U))).sum()
        res = self.md.solve("max_res", self.rtol * scale, *self.solve_opts)
        its, converged = (res[0], res[1]) if isinstance(res, (tuple, list)) else (res, 1)
        if not converged:
            raise RuntimeError("Newton did not converge")
        Un = np.array(self.md.variable("u"), dtype=float)
        An = self.c * (Un - self.U) - self.V / (b * tau) - (0.5 / b - 1.0) * self.A
        self.V = self.V + tau * ((1.0 - self.gamma_nm) * self.A + self.gamma_nm * An)
        self.U, self.A = Un, An
        return int(its)

    def monitors(self):
        """Contact pressure lambda = -[P]_+/gamma at x = 0, E and E_Theta."""
        un = -float(self.a_row @ self.U)
        sn = float(self.s_row @ self.U)
        pp = max(un - self.gamma * sn, 0.0)
        lam = -pp / self.gamma
        E = 0.5 * float(self.V @ np.asarray(self.M.mult(self.V))) \
            + 0.5 * float(self.U @ np.asarray(self.K.mult(self.U)))
        R = 0.5 * (self.gamma * sn * sn - pp * pp / self.gamma)
        return lam, E, E - self.Theta * R

    def check_brick(self, seed=1):
        """Largest differences between GetFEM's Nitsche residual/tangent and the
        paper's formula (gamma = gamma0 h), over states with and without contact."""
        md, Kd = self.md, self.K.full()
        a, s, g, TH = self.a_row, self.s_row, self.gamma, self.Theta
        rng = np.random.default_rng(seed)
        md.disable_bricks([self.i_mass, self.i_rhs])
        worst_r = worst_t = 0.0
        active = 0
        for k in range(6):
            U = (0.5 if k % 2 else -0.5) * (1 - self.x) + 0.05 * rng.standard_normal(self.x.size)
            U[self.clamped] = 0.0
            md.set_variable("u", U)
            md.assembly()
            R = -np.array(md.rhs(), dtype=float)
            T = md.tangent_matrix().full()
            un, sn = -(a @ U), s @ U
            P = un - g * sn
            active += P > 0
            Rf = Kd @ U - TH * g * sn * s + max(P, 0.0) / g * (-a - TH * g * s)
            Tf = Kd - TH * g * np.outer(s, s) + (P > 0) / g * np.outer(-a - TH * g * s, -a - g * s)
            free = np.ones(self.x.size, dtype=bool)
            free[self.clamped] = False
            scale_r = np.abs(Rf[free]).max()
            scale_t = np.abs(Tf[np.ix_(free, free)]).max()
            worst_r = max(worst_r, np.abs(R - Rf)[free].max() / scale_r)
            worst_t = max(worst_t, np.abs(T - Tf)[np.ix_(free, free)].max() / scale_t)
        md.enable_bricks([self.i_mass, self.i_rhs])
        md.set_variable("u", self.U)
        return worst_r, worst_t, active


# ---- one run -------------------------------------------------------------------

def run_once(args, lib, nx, degree, evaluate, trace=None):
    tau = args.tau_over_h / nx
    steps = int(round(args.T / tau))
    t0 = time.perf_counter()
    bar = Bar(nx, degree, args.Theta, args.gamma0, args.beta, args.gamma, tau, args.newton_rtol,
              args.newton_max_iter, args.lsolver)
    t_setup = time.perf_counter() - t0

    out = {"steps": steps, "tau": tau, "setup_s": t_setup}
    grid = acc = None
    if evaluate:
        grid = Grid()
        if lib.grid_init(ctypes.byref(grid), degree, nx, as_dp(bar.x), bar.x.size) != 0:
            raise RuntimeError("grid_init failed")
        acc = NormAcc()
        E0 = ET0 = None
        drift = 0.0

    def sample(n):
        nonlocal E0, ET0, drift
        t = n * tau
        ph = lib.phase_at(t)
        U = np.ascontiguousarray(bar.U)
        V = np.ascontiguousarray(bar.V)
        s = lib.norms_at(ctypes.byref(grid), as_dp(U), as_dp(V), ph)
        sigma = lib.exact_stress(ph)
        lam, E, ET = bar.monitors()
        w = 0.5 * tau if (n == 0 or n == steps) else tau
        lib.acc_add(ctypes.byref(acc), ctypes.byref(s), lam - sigma, sigma, w)
        if n == 0:
            E0, ET0 = E, ET
        drift = max(drift, abs(ET - ET0) / E0)
        if trace:
            i0 = int(np.argmin(bar.x))  # the node at x = 0
            trace.write("%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n" % (t, bar.U[i0], bar.V[i0], lam, E, ET))

    newton = 0
    t_loop = 0.0
    try:
        if evaluate:
            sample(0)
        for n in range(1, steps + 1):
            t0 = time.perf_counter()
            try:
                newton += bar.step()
            except (RuntimeError, ValueError) as e:
                raise RuntimeError("step %d: %s" % (n, str(e).strip().splitlines()[-1][:80]))
            t_loop += time.perf_counter() - t0
            if evaluate:
                sample(n)
    finally:
        if grid is not None:
            lib.grid_free(ctypes.byref(grid))
    out["loop_s"] = t_loop
    out["newton_its"] = newton
    if evaluate:
        out["energy_drift"] = drift
        out["errors"] = [lib.acc_relative(ctypes.byref(acc), i) for i in range(N_NORMS)]
    return out


def run_case(args, lib, nx, degree):
    trace = None
    if args.trace_prefix:  # the per-level file of examples/bar1d --csv, same format
        trace = open("%s_P%d_nx%d.csv" % (args.trace_prefix, degree, nx), "w")
        trace.write("t,u(0),v(0),contact_stress,E,E_Theta\n")
    try:
        first = run_once(args, lib, nx, degree, evaluate=True, trace=trace)
    finally:
        if trace:
            trace.close()
    setups, loops = [first["setup_s"]], [first["loop_s"]]
    for _ in range(args.repeat - 1):
        r = run_once(args, lib, nx, degree, evaluate=False)
        setups.append(r["setup_s"])
        loops.append(r["loop_s"])
    first["setup_s"] = statistics.median(setups)
    first["loop_s"] = statistics.median(loops)
    return first


# ---- command line and CSV --------------------------------------------------------

def int_list(s):
    vals = [int(v) for v in s.split(",") if v.strip()]
    if not vals or min(vals) < 1:
        raise argparse.ArgumentTypeError("expected a comma list of positive integers")
    return vals


def fmt(v):
    return "%.10g" % v


def main(argv=None):
    p = argparse.ArgumentParser(description="The 1D bar (docs/design.md §7) solved by GetFEM, measured with our norms.")
    p.add_argument("--lib", required=True, help="path of libbar1d_exact.so")
    p.add_argument("--nx", type=int_list, default=[20, 40, 80], help="comma list of cell counts")
    p.add_argument("--degree", type=int_list, default=[1, 2], help="comma list of degrees (1, 2)")
    p.add_argument("--Theta", type=float, default=1.0)
    p.add_argument("--gamma0", type=float, default=0.2, help="Nitsche gamma0, paper convention (gamma = gamma0 h)")
    p.add_argument("--beta", type=float, default=0.25)
    p.add_argument("--gamma", type=float, default=0.5, help="Newmark gamma")
    p.add_argument("--T", type=float, default=3.0)
    p.add_argument("--tau-over-h", type=float, default=0.5)
    p.add_argument("--repeat", type=int, default=1)
    p.add_argument("--csv", default=None, help="append one row per run to this file")
    p.add_argument("--newton-rtol", type=float, default=1e-12,
                   help="Newton stops at ||G||_1 <= rtol (||r||_1 + ||c M U^n||_1) (default 1e-12)")
    p.add_argument("--newton-max-iter", type=int, default=50)
    p.add_argument("--lsolver", default="auto",
                   help="GetFEM linear solver: auto (default; MUMPS in Debian's build), mumps, dense_lu, ...")
    p.add_argument("--trace-prefix", default=None,
                   help="also write PREFIX_P<degree>_nx<nx>.csv: t,u(0),v(0),contact_stress,E,E_Theta per time "
                        "level (first repetition), the format of examples/bar1d --csv")
    p.add_argument("--check-brick", action="store_true",
                   help="compare GetFEM's Nitsche residual/tangent with the paper's formula and exit")
    args = p.parse_args(argv)
    if any(d not in (1, 2) for d in args.degree):
        p.error("--degree must be 1 or 2")
    if args.repeat < 1 or args.gamma0 <= 0 or args.beta <= 0 or args.T <= 0 or args.tau_over_h <= 0:
        p.error("--repeat, --gamma0, --beta, --T and --tau-over-h must be positive")
    if any(int(round(args.T * nx / args.tau_over_h)) < 1 for nx in args.nx):
        p.error("T/tau rounds to zero steps")

    gf.util_trace_level(0)
    gf.util_warning_level(0)

    if args.check_brick:
        for degree in args.degree:
            for nx in args.nx:
                bar = Bar(nx, degree, args.Theta, args.gamma0, args.beta, args.gamma, args.tau_over_h / nx,
                          args.newton_rtol, args.newton_max_iter, args.lsolver)
                r, t, act = bar.check_brick()
                print("check-brick P%d nx=%d Theta=%g gamma0=%g: max rel. diff residual %.2e tangent %.2e "
                      "(%d of 6 states in contact)" % (degree, nx, args.Theta, args.gamma0, r, t, act))
        return 0

    lib = load_norm_lib(args.lib)
    scheme = "newmark(%g,%g)" % (args.beta, args.gamma)
    csv = writer = None
    if args.csv:
        new = not os.path.exists(args.csv) or os.path.getsize(args.csv) == 0
        csv = open(args.csv, "a", newline="")
        # RFC 4180: the scheme field "newmark(0.25,0.5)" holds a comma, so it is quoted
        writer = csvmod.writer(csv, lineterminator="\n")
        if new:
            writer.writerow(CSV_COLUMNS)
    status_all = 0
    try:
        for degree in args.degree:
            for nx in args.nx:
                tau = args.tau_over_h / nx
                row = {"code": "getfem", "study": "getfem", "scheme": scheme, "degree": str(degree),
                       "Theta": fmt(args.Theta), "gamma0": fmt(args.gamma0), "lumped": "0", "nx": str(nx),
                       "tau": fmt(tau), "T": fmt(args.T), "steps": str(int(round(args.T / tau))),
                       "repeats": str(args.repeat)}
                try:
                    r = run_case(args, lib, nx, degree)
                    row.update({"setup_s": fmt(r["setup_s"]), "loop_s": fmt(r["loop_s"]),
                                "newton_its": str(r["newton_its"]), "energy_drift": fmt(r["energy_drift"]),
                                "status": "ok"})
                    for name, e in zip(CSV_COLUMNS[16:23], r["errors"]):
                        row[name] = fmt(e)
                    print("getfem P%d nx=%d Theta=%g: setup %.4f s loop %.4f s (%.4f ms/step) newton %.3f/step "
                          "drift %.3e errors %s" % (degree, nx, args.Theta, r["setup_s"], r["loop_s"],
                                                    1e3 * r["loop_s"] / r["steps"], r["newton_its"] / r["steps"],
                                                    r["energy_drift"], " ".join("%.6e" % e for e in r["errors"])))
                except Exception as e:  # one failed run must not stop the sweep
                    status_all = 1
                    msg = " ".join(str(e).split()).replace(",", ";")[:120] or type(e).__name__
                    row["status"] = "error: " + msg
                    print("getfem P%d nx=%d Theta=%g: FAILED %s" % (degree, nx, args.Theta, msg))
                if csv:
                    writer.writerow([row.get(c, "") for c in CSV_COLUMNS])
                    csv.flush()
                sys.stdout.flush()
    finally:
        if csv:
            csv.close()
    return status_all


if __name__ == "__main__":
    sys.exit(main())
