#!/usr/bin/python3
"""The disk (2D) and ball (3D) of docs/design.md §7 solved by GetFEM, for bench/run.sh
(simplices, or quadrilaterals and hexahedra: examples/meshes/disk_quad, ball_hex).

GetFEM (Debian's python3-getfem) does the finite element work: the Gmsh mesh,
the P1/P2 Lagrange space, elasticity and mass bricks, its Nitsche contact
brick (add_Nitsche_contact_with_rigid_obstacle_brick) and the semi-smooth
Newton solve of every step (Model.solve). This script runs the Newmark(1/4,
1/2) recursion around the model, as tools/report/getfem_bar.py does in 1D, and
writes the same per-step history as bench/disk_bench (t, E, contact force,
Newton iterations, step time) and one CSV row of costs.

Matching our formulation (docs/design.md §1-2):
- gamma. GetFEM's brick uses gamma = element_size / gamma0_getfem, with its
  own element_size (not the diameter); ours is gamma0 h_K with h_K the longest
  edge of the bulk cell. gamma0_getfem is given per cell (a P0 field) as
  element_size_K / (gamma0 h_K), so that both gammas are equal cell by cell.
- sigma_n. GetFEM's frictionless brick has the consistency term
  -Theta gamma G . D_u G[v] with the whole Neumann vector G, and projects only
  the normal part: with the usual G = sigma(u) N (N the body's normal) it adds
  a tangential term -Theta gamma G_t . D_u G_t[v] that the paper's
  formulation (and ours) does not have, and its normal stress is
  (sigma(u) N) . n, not n . sigma(u) n (N differs from the obstacle's n on the
  curved boundary). So the Neumann term given to the brick is
  G = (n . sigma(u) n) n: then GetFEM's terms are exactly docs/design.md §1's.
- The obstacle: the signed distance y (2D) or z (3D), n = -e_y or -e_z.
- Quadrature: IM_TRIANGLE(2p) / IM_TETRAHEDRON(2 or 5), whose face rules are
  exact for the polynomial parts, as ours; the points differ in 3D (the
  integrand [P]_+ is not polynomial), a difference of the discretization size.
  Quadrilaterals and hexahedra (GT_QK from the mesh, FEM_QK(dim, p) by
  set_classical_fem): IM_GAUSS_PARALLELEPIPED(dim, k), our rules: k = 2p for
  K, 2p + dim - 1 for M, 2p + dim - 2 for the contact (its facets' rule).
- Newton stops when ||G||_1 <= rtol (||r||_1 + ||c M U^n||_1) (GetFEM's max_res
  is absolute otherwise), rtol = 1e-10 as in our library.
- Initial acceleration: U0 = 0, no contact (gap 5) and K_Theta U0 = 0, so
  M A0 = F = M g: A0 = g exactly.

Friction (bench/friction_getfem.sh): with F > 0 and an initial velocity vx
along x, the brick takes Coulomb's coefficient F with the whole stress vector
G = sigma(u) N and the slip u - wt, wt = U^n (alpha = 1): docs/design.md
§10.2's weak form term for term but for the slip reference (ours is the
return-mapped s; bench/getfem_friction.py measures that difference).

usage: getfem_drop.py MESH.msh DIM DEGREE TAU T HISTORY.csv [F VX]
       getfem_drop.py --check-brick MESH.msh DIM DEGREE   (the brick against docs/design.md §1)
Prints one CSV row (--header for the header). The mesh is converted to Gmsh's
format 2.2 (GetFEM 5.4's reader) with gmsh in a temporary directory.
"""

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import getfem as gf

HEADER = ("dim,mesh,degree,unknowns,steps,blas_threads,setup_s,loop_s,free_median_ms,impact_median_ms,"
          "contact_median_ms,newton_per_contact_step,peak_rss_mb")
CONTACT = 1  # the contact region of examples/meshes/*.geo
LAMBDA = MU = 20.0
GAMMA0 = 1e-3  # paper convention, gamma = gamma0 h_K
THETA = 1.0
BETA, GAMMA_NM = 0.25, 0.5
RTOL = 1e-10


def load_mesh(path, dim):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "m22.msh")
        subprocess.run(["gmsh", "-0", path, "-format", "msh22", "-o", out, "-v", "0"], check=True,
                       stdout=subprocess.DEVNULL)
        m = gf.Mesh("import", "gmsh", out)
    if m.dim() != dim:
        raise RuntimeError("GetFEM read a %dD mesh from %s" % (m.dim(), path))
    return m


def cell_diameters(m):
    """Longest edge of every cell (our h_K), indexed by convex id."""
    cvids = m.cvid()
    pids, idx = m.pid_from_cvid(cvids)
    P = m.pts()
    h = np.zeros(int(cvids.max()) + 1)
    for k, cv in enumerate(cvids):
        x = P[:, pids[idx[k]:idx[k + 1]]]
        h[cv] = max(np.linalg.norm(x[:, i] - x[:, j]) for i in range(x.shape[1]) for j in range(i))
    return h


def gamma0_field(m, mim, gamma0):
    """(mf0, gamma0_getfem): a P0 field with GetFEM's gamma = element_size /
    gamma0_getfem equal to ours, gamma0 h_K, cell by cell."""
    mf0 = gf.MeshFem(m, 1)
    mf0.set_classical_discontinuous_fem(0)
    aux = gf.Model("real")
    aux.add_fem_variable("e", mf0)
    es = np.asarray(gf.asm_generic(mim, 1, "element_size*Test_e", -1, aux), dtype=float)
    vol = np.asarray(gf.asm_generic(mim, 1, "Test_e", -1, aux), dtype=float)
    hK = cell_diameters(m)
    g0 = np.zeros(mf0.nbdof())
    for cv in m.cvid():
        dof = mf0.basic_dof_from_cv(cv)[0]
        g0[dof] = (es[dof] / vol[dof]) / (gamma0 * hK[cv])
    return mf0, g0


class Drop:
    def __init__(self, mesh, dim, degree, tau, friction=0.0, vx=0.0):
        self.dim, self.tau = dim, tau
        self.c = 1.0 / (BETA * tau * tau)
        m = load_mesh(mesh, dim)
        self.mf = gf.MeshFem(m, dim)
        self.mf.set_classical_fem(degree)
        # exact for degree 2p (GetFEM has no IM_TETRAHEDRON(4): 5 for P2 in 3D); on
        # quadrilaterals and hexahedra (GT_QK, FEM_QK) our Gauss tensor rules
        # (src/assembly/bulk.cpp, src/fem/facet.cpp), exact a variable to degree
        # 2p (K), 2p + dim - 1 (M) and, on the facets, 2p + dim - 2 (contact)
        if "QK" in m.geotrans()[0].char():
            cube = lambda k: gf.MeshIm(m, gf.Integ("IM_GAUSS_PARALLELEPIPED(%d,%d)" % (dim, k)))
            self.mim_k, self.mim = cube(2 * degree), cube(2 * degree + dim - 1)
            self.mim_c = cube(2 * degree + dim - 2)
        else:
            rule = "IM_TRIANGLE(%d)" % (2 * degree) if dim == 2 else "IM_TETRAHEDRON(%d)" % (2 if degree == 1 else 5)
            self.mim = self.mim_k = self.mim_c = gf.MeshIm(m, gf.Integ(rule))
        n = self.mf.nbdof()
        self.n = n

        mf0, g0 = gamma0_field(m, self.mim, GAMMA0)

        md = gf.Model("real")
        md.add_fem_variable("u", self.mf)
        md.add_initialized_data("lambda", [LAMBDA])
        md.add_initialized_data("mu", [MU])
        md.add_isotropic_linearized_elasticity_brick(self.mim_k, "u", "lambda", "mu")  # plane strain in 2D
        md.add_initialized_data("c", [self.c])
        md.add_mass_brick(self.mim, "u", "c")  # c M, rho = 1
        self.i_rhs = md.add_explicit_rhs("u", np.zeros(n))
        mfs = gf.MeshFem(m, 1)
        mfs.set_classical_fem(degree)
        md.add_initialized_fem_data("obstacle", mfs, np.asarray(mfs.basic_dof_nodes()[dim - 1], dtype=float))
        md.add_initialized_fem_data("gamma0_getfem", mf0, g0)
        nc = "[0;-1]" if dim == 2 else "[0;0;-1]"
        self.nc = nc
        # sigma_n n: the normal part only (see the docstring)
        self.sigma_n = "(((lambda*Trace(Grad_u)*Id(%d) + mu*(Grad_u + Grad_u')) * %s).%s)" % (dim, nc, nc)
        self.friction = friction
        if friction > 0:
            md.add_initialized_data("F", [friction])
            md.add_initialized_fem_data("wt", self.mf, np.zeros(n))
            stress = "((lambda*Trace(Grad_u)*Id(%d) + mu*(Grad_u + Grad_u'))*%s)" % (dim, nc)
            # GetFEM 5.4 writes the slip as "((" + alpha + ")*(u-(wt))", one
            # parenthesis short: alpha = "1)" closes it (bench/getfem_friction.py)
            md.add_Nitsche_contact_with_rigid_obstacle_brick(self.mim_c, "u", stress, "obstacle", "gamma0_getfem",
                                                             CONTACT, THETA, "F", "1)", "wt")
        else:
            neumann = "(%s*%s)" % (self.sigma_n, nc)
            md.add_Nitsche_contact_with_rigid_obstacle_brick(self.mim_c, "u", neumann, "obstacle", "gamma0_getfem",
                                                             CONTACT, THETA)
        self.md = md

        self.M = gf.asm_mass_matrix(self.mim, self.mf)
        self.K = gf.asm_generic(self.mim_k, 2, "lambda*Div_Test_u*Div_Test2_u + 2*mu*Sym(Grad_Test_u):Sym(Grad_Test2_u)",
                                -1, md)
        g = np.zeros(n)
        g[dim - 1::dim] = -0.1  # body force (0, -0.1) or (0, 0, -0.1), components interleaved
        self.g = g
        self.U = np.zeros(n)
        self.V = np.zeros(n)
        self.V[0::dim] = vx
        self.A = g.copy()

    def step(self):
        b, tau = BETA, self.tau
        w = self.c * self.U + self.V / (b * tau) + (0.5 / b - 1.0) * self.A + self.g
        r = np.asarray(self.M.mult(w))
        self.md.set_private_rhs(self.i_rhs, r)
        scale = np.abs(r).sum() + self.c * np.abs(np.asarray(self.M.mult(self.U))).sum()
        res = self.md.solve("max_res", RTOL * scale, "max_iter", 50)
        its, converged = (res[0], res[1]) if isinstance(res, (tuple, list)) else (res, 1)
        if not converged:
            raise RuntimeError("Newton did not converge")
        Un = np.array(self.md.variable("u"), dtype=float)
        An = self.c * (Un - self.U) - self.V / (b * tau) - (0.5 / b - 1.0) * self.A
        self.V = self.V + tau * ((1.0 - GAMMA_NM) * self.A + GAMMA_NM * An)
        self.U, self.A = Un, An
        if self.friction > 0:
            self.md.set_variable("wt", Un)
        return int(its)

    def energy(self):
        return 0.5 * float(self.V @ np.asarray(self.M.mult(self.V))) + 0.5 * float(self.U @ np.asarray(self.K.mult(self.U)))

    def contact_force(self):
        """sum_q w_q [P_q]_+ / gamma_q, P = u.n - g0 - gamma n.sigma(u)n (our ND_CONTACT_FORCE)."""
        G = "(element_size/gamma0_getfem)"
        expr = "pos_part(u.%s - obstacle - %s*%s)/%s" % (self.nc, G, self.sigma_n, G)
        return float(gf.asm_generic(self.mim_c, 0, expr, CONTACT, self.md))


def check_brick(mesh, dim, degree):
    """GetFEM's contact residual (the whole model's minus elasticity and mass)
    against docs/design.md §1's Nitsche terms assembled by GWFL, at a state pushed
    into the plane with random noise; prints the largest relative difference."""
    d = Drop(mesh, dim, degree, 0.05)
    U = np.random.default_rng(1).standard_normal(d.n) * 0.3
    U[dim - 1::dim] -= 7.0  # 2 into the plane at the bottom: part of the boundary in contact
    d.md.set_variable("u", U)
    d.md.assembly("build_rhs")
    R = -np.array(d.md.rhs()) - np.asarray(d.K.mult(U)) - d.c * np.asarray(d.M.mult(U))
    G = "(element_size/gamma0_getfem)"
    sv = "(((lambda*Trace(Grad_Test_u)*Id(%d) + mu*(Grad_Test_u + Grad_Test_u')) * %s).%s)" % (dim, d.nc, d.nc)
    P = "(u.%s - obstacle - %s*%s)" % (d.nc, G, d.sigma_n)
    expr = "-%g*%s*%s*%s + pos_part(%s)/%s*(Test_u.%s - %g*%s*%s)" % (THETA, G, d.sigma_n, sv, P, G, d.nc, THETA, G, sv)
    Rp = np.asarray(gf.asm_generic(d.mim_c, 1, expr, CONTACT, d.md))
    print("check-brick %s P%d: max |GetFEM - DESIGN| / max |DESIGN| = %.2e (contact force %.6g)"
          % (os.path.basename(mesh), degree, np.abs(R - Rp).max() / np.abs(Rp).max(), d.contact_force()))


def main(argv):
    if len(argv) == 2 and argv[1] == "--header":
        print(HEADER)
        return 0
    if len(argv) == 5 and argv[1] == "--check-brick":
        gf.util_trace_level(0)
        gf.util_warning_level(0)
        check_brick(argv[2], int(argv[3]), int(argv[4]))
        return 0
    if len(argv) not in (7, 9):
        sys.stderr.write(__doc__)
        return 2
    mesh, dim, degree, tau, T, hist = argv[1], int(argv[2]), int(argv[3]), float(argv[4]), float(argv[5]), argv[6]
    friction, vx = (float(argv[7]), float(argv[8])) if len(argv) == 9 else (0.0, 0.0)
    gf.util_trace_level(0)
    gf.util_warning_level(0)
    t0 = time.perf_counter()
    d = Drop(mesh, dim, degree, tau, friction, vx)
    setup = time.perf_counter() - t0
    steps = int(round(T / tau))
    free, impact, contact, newton_contact = [], [], [], 0
    loop = 0.0
    f_before = 0.0
    with open(hist, "w") as h:
        h.write("t,E,contact_force,newton,step_s\n%.10g,%.12g,%.12g,0,0\n" % (0.0, d.energy(), d.contact_force()))
        for k in range(steps):
            t1 = time.perf_counter()
            its = d.step()
            dt = time.perf_counter() - t1
            loop += dt
            f = d.contact_force()
            if k > 0:  # the first step assembles and factors: as disk_bench, not a median sample
                if f_before == 0 and f == 0:
                    free.append(dt)
                elif f_before == 0:
                    impact.append(dt)
                elif f > 0:
                    contact.append(dt)
                    newton_contact += its
            f_before = f
            h.write("%.10g,%.12g,%.12g,%d,%.9f\n" % ((k + 1) * tau, d.energy(), f, its, dt))
    med = lambda v: 1e3 * statistics.median(v) if v else 0.0
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print("%d,%s,%d,%d,%d,%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.4f,%.1f" % (
        dim, os.path.basename(mesh), degree, d.n, steps, os.environ.get("OPENBLAS_NUM_THREADS", "default"), setup,
        loop, med(free), med(impact), med(contact), newton_contact / len(contact) if contact else 0.0, rss))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
