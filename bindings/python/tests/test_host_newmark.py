#!/usr/bin/python3
"""python_host_newmark: the Python twin of examples/host_newmark.f90 and
tests/test_host_newmark.c, through the ctypes layer ``nitschedyn.lib`` with
plain lists (numpy is not needed: the host is a legacy code with its own
arrays).

A free block (1 x 0.25, P1) dropped onto a plane, Newmark(1/4, 1/2), then
the hybrid scheme: the host takes M, K, K_Theta - K and F once
(nd_problem_get_matrix, nd_problem_get_load), runs its own loop and
semi-smooth Newton with the contact term of nd_problem_contact_residual and
nd_problem_contact_tangent (Newmark) or of their step form from its own U^n,
nd_problem_contact_step_residual and nd_problem_contact_step_tangent (the
hybrid scheme, kappa = 2), and each step's displacement is within
    (|G_h(U_host)| + |G_h(U_lib)|) / lambda_min(A)
of nd_step's (A = c M + K_Theta, the host's step map G_h strongly monotone
for Theta = 1: its law nondecreasing in P_q, the hybrid Phi_q for a fixed
P_q^n too; G_h(U_lib) holds every difference of history; lambda_min bounded
below by a Cholesky factorization of A - mu I). Also: nd_problem_get_cells, nd_problem_get_dof_map,
nd_problem_contact_values (the state's values are nd_get_scalar's) and the
momenta.

Prints "N passed, M failed"; exit status 1 when a check failed.
"""

import ctypes
import math
import sys

import nitschedyn as nd
from ndcheck import check, finish

lib = nd.lib
i64, dbl, cint = ctypes.c_int64, ctypes.c_double, ctypes.c_int
RTOL, TAU, BETA, GAMMA = 1e-10, 0.01, 0.25, 0.5



def call(status):
    if status != nd.ND_OK:
        raise RuntimeError(lib.nd_last_error().decode())


def darray(n, values=None):
    a = (dbl * max(n, 1))()
    if values is not None:
        for i, v in enumerate(values):
            a[i] = v
    return a


def scene(hybrid):
    m, p = ctypes.c_void_p(), ctypes.c_void_p()
    call(lib.nd_mesh_create_rectangle(4, 1, darray(2, [0, 0.002]), darray(2, [1, 0.252]), ctypes.byref(m)))
    call(lib.nd_mesh_mark_boundary_box(m, 1, darray(2, [-1, -1]), darray(2, [2, 0.0021])))
    call(lib.nd_problem_create(m, 1, ctypes.byref(p)))
    call(lib.nd_mesh_destroy(ctypes.byref(m)))
    call(lib.nd_problem_set_material(p, 1.0, 0.3, 1.0))
    call(lib.nd_problem_set_contact_plane(p, 1, darray(2, [0, 0]), darray(2, [0, 1])))
    call(lib.nd_problem_set_nitsche(p, 1.0, 0.0))
    call(lib.nd_problem_set_body_force(p, darray(2, [0.05, -1])))
    if hybrid:
        call(lib.nd_problem_set_scheme(p, nd.ND_SCHEME_HYBRID, None))
    else:
        call(lib.nd_problem_set_scheme(p, nd.ND_SCHEME_NEWMARK, darray(2, [BETA, GAMMA])))
    call(lib.nd_problem_set_timestep(p, TAU))
    nn = i64()
    call(lib.nd_problem_get_node_count(p, ctypes.byref(nn)))
    x = darray(2 * nn.value)
    call(lib.nd_problem_get_node_coordinates(p, nn, x))
    v0 = darray(2 * nn.value)
    for j in range(nn.value):  # falling, sliding, spinning and stretching a little
        v0[2 * j] = 0.2 - 0.3 * x[2 * j + 1] + 0.1 * x[2 * j] ** 2
        v0[2 * j + 1] = -0.5 + 0.3 * (x[2 * j] - 0.5)
    call(lib.nd_problem_set_initial_state(p, nn, None, v0))
    return p, nn.value


def dense(p, which):
    n, nnz = i64(), i64()
    call(lib.nd_problem_get_matrix(p, which, ctypes.byref(n), ctypes.byref(nnz), None, None, None))
    ptr, col, val = (i64 * (n.value + 1))(), (i64 * nnz.value)(), darray(nnz.value)
    call(lib.nd_problem_get_matrix(p, which, ctypes.byref(n), ctypes.byref(nnz), ptr, col, val))
    D = [[0.0] * n.value for _ in range(n.value)]
    for i in range(n.value):
        for k in range(ptr[i], ptr[i + 1]):
            D[i][col[k]] += val[k]
    return D


def matvec(A, x):
    return [sum(a * b for a, b in zip(row, x)) for row in A]


def norm(x):
    return math.sqrt(sum(v * v for v in x))


def solve(A, b):
    """A^{-1} b, Gaussian elimination with partial pivoting."""
    n = len(b)
    a = [row[:] for row in A]
    x = list(b)
    for k in range(n):
        piv = max(range(k, n), key=lambda i: abs(a[i][k]))
        a[k], a[piv] = a[piv], a[k]
        x[k], x[piv] = x[piv], x[k]
        for i in range(k + 1, n):
            f = a[i][k] / a[k][k]
            if f != 0:
                ak = a[k]
                ai = a[i]
                for j in range(k, n):
                    ai[j] -= f * ak[j]
                x[i] -= f * x[k]
    for i in range(n - 1, -1, -1):
        x[i] = (x[i] - sum(a[i][j] * x[j] for j in range(i + 1, n))) / a[i][i]
    return x


def factors(A, mu):
    n = len(A)
    L = [[0.0] * n for _ in range(n)]
    for i in range(n):
        for j in range(i + 1):
            s = A[i][j] - (mu if i == j else 0) - sum(L[i][k] * L[j][k] for k in range(j))
            if i == j:
                if not s > 0:
                    return False
                L[i][i] = math.sqrt(s)
            else:
                L[i][j] = s / L[j][j]
    return True


def lambda_min_lower(A):
    x = [1 + 0.1 * (i % 7) for i in range(len(A))]
    q = 0
    for _ in range(40):
        s = norm(x)
        x = [v / s for v in x]
        y = solve(A, x)
        q = 1 / sum(a * b for a, b in zip(x, y))
        x = y
    mu = 0.999 * q
    while not factors(A, mu):
        mu *= 0.5
    return mu


def main(hybrid):
    p, nn = scene(hybrid)
    M, K, NT = dense(p, nd.ND_MATRIX_MASS), dense(p, nd.ND_MATRIX_STIFFNESS), dense(p, nd.ND_MATRIX_NITSCHE)
    n = len(M)
    c, kappa = (4 / (TAU * TAU), 2) if hybrid else (1 / (BETA * TAU * TAU), 1)
    KT = [[K[i][j] + NT[i][j] for j in range(n)] for i in range(n)]
    A = [[c * M[i][j] + KT[i][j] for j in range(n)] for i in range(n)]
    F = darray(n)
    call(lib.nd_problem_get_load(p, n, F))
    F = list(F)[:n]
    node, comp = (i64 * n)(), (cint * n)()
    call(lib.nd_problem_get_dof_map(p, n, node, comp))
    check(n == 2 * nn, "every DOF free (no Dirichlet region): %d of %d" % (n, 2 * nn))
    # the cells: 3 nodes each, every node in some cell
    ncells, npc = i64(), cint()
    call(lib.nd_problem_get_cells(p, ctypes.byref(ncells), ctypes.byref(npc), None))
    cells = (i64 * (ncells.value * npc.value))()
    call(lib.nd_problem_get_cells(p, ctypes.byref(ncells), ctypes.byref(npc), cells))
    check(npc.value == 3 and ncells.value == 8 and set(cells) == set(range(nn)), "the cells")
    # the lumped masses keep the mass (rho |Omega| = 0.25 per component)
    lumped = dense(p, nd.ND_MATRIX_LUMPED_MASS)
    for comp_k in range(2):
        s = sum(lumped[i][i] for i in range(n) if comp[i] == comp_k)
        check(abs(s - 0.25) <= 4 * n * sys.float_info.epsilon * 0.25, "lumped mass %d: %r" % (comp_k, s))

    def field(which):
        full = darray(2 * nn)
        call(lib.nd_get_field(p, which, nn, full))
        return [full[2 * node[i] + comp[i]] for i in range(n)]

    def contact(u, un=None):
        """N(u); with un (the host's U^n) the step form, the scheme's rule over the step"""
        N = darray(n)
        if un is None:
            call(lib.nd_problem_contact_residual(p, n, darray(n, u), N))
        else:
            call(lib.nd_problem_contact_step_residual(p, n, darray(n, u), darray(n, un), N))
        return list(N)[:n]

    tnnz = i64()
    call(lib.nd_problem_contact_tangent(p, n, None, ctypes.byref(tnnz), None, None, None))
    tptr, tcol, tval = (i64 * (n + 1))(), (i64 * tnnz.value)(), darray(tnnz.value)
    lam = lambda_min_lower(A)

    U, V = field(nd.ND_FIELD_DISPLACEMENT), field(nd.ND_FIELD_VELOCITY)
    N0 = contact(U)
    Acc = solve(M, [F[i] - kt - N0[i] for i, kt in enumerate(matvec(KT, U))])
    if hybrid:  # it carries no acceleration: the predictor U + tau V
        Acc = [0.0] * n
    worst = worst_bound = 0.0
    in_contact = 0
    for step in range(30):
        if hybrid:  # 2 F^{n+1/2} - K_Theta U^n + M (c U^n + 4/tau V^n)
            KU = matvec(KT, U)
            r = [2 * F[i] - KU[i] + v for i, v in enumerate(matvec(M, [c * U[i] + 4 / TAU * V[i] for i in range(n)]))]
        else:
            mix = [c * U[i] + V[i] / (BETA * TAU) + (0.5 / BETA - 1) * Acc[i] for i in range(n)]
            r = [F[i] + v for i, v in enumerate(matvec(M, mix))]
        Un = U if hybrid else None
        U1 = [U[i] + TAU * V[i] + 0.5 * TAU * TAU * Acc[i] for i in range(n)]
        last = None
        for it in range(51):
            if it == 50:
                raise RuntimeError("the host's Newton did not converge")
            N = contact(U1, Un)
            G = [g + kappa * N[i] - r[i] for i, g in enumerate(matvec(A, U1))]
            gh = norm(G)
            if hybrid:  # the step form's Jacobian in U1
                call(lib.nd_problem_contact_step_tangent(p, n, darray(n, U1), darray(n, U), ctypes.byref(tnnz), tptr,
                                                         tcol, tval))
            else:
                call(lib.nd_problem_contact_tangent(p, n, darray(n, U1), ctypes.byref(tnnz), tptr, tcol, tval))
            now = list(tval)[:tnnz.value]
            if last == now and gh <= RTOL * (norm(r) + c * norm(matvec(M, U1))):
                break
            last = now
            T = [row[:] for row in A]
            for i in range(n):
                for k in range(tptr[i], tptr[i + 1]):
                    T[i][tcol[k]] += kappa * tval[k]
            dU = solve(T, [-g for g in G])
            U1 = [U1[i] + dU[i] for i in range(n)]
        if hybrid:
            V1, A1 = [2 * (U1[i] - U[i]) / TAU - V[i] for i in range(n)], [0.0] * n
        else:
            A1 = [c * (U1[i] - U[i]) - V[i] / (BETA * TAU) - (0.5 / BETA - 1) * Acc[i] for i in range(n)]
            V1 = [V[i] + TAU * ((1 - GAMMA) * Acc[i] + GAMMA * A1[i]) for i in range(n)]
        call(lib.nd_step(p))
        Ulib = field(nd.ND_FIELD_DISPLACEMENT)
        Nl = contact(Ulib, Un)  # the host's equation (its r, its U^n) at U_lib
        gl = norm([g + kappa * Nl[i] - r[i] for i, g in enumerate(matvec(A, Ulib))])
        bound = (gh + gl) / lam
        diff = norm([U1[i] - Ulib[i] for i in range(n)])
        check(diff <= bound, "step %d: |U_host - U_lib| = %g > bound %g" % (step, diff, bound))
        worst = max(worst, max(abs(U1[i] - Ulib[i]) for i in range(n)))
        worst_bound = max(worst_bound, bound)
        # the contact values at the state's U are nd_get_scalar's
        vals = darray(4)
        call(lib.nd_problem_contact_values(p, n, darray(n, Ulib), 4, vals))
        keys = [nd.ND_CONTACT_FORCE, nd.ND_ACTIVE_POINTS, nd.ND_ENERGY_NITSCHE, nd.ND_MAX_PENETRATION]
        for k, key in enumerate(keys):
            x = dbl()
            call(lib.nd_get_scalar(p, key, ctypes.byref(x)))
            check(vals[k] == x.value, "step %d value %d: %r, nd_get_scalar %r" % (step, k, vals[k], x.value))
        in_contact += vals[1] > 0
        U, V, Acc = U1, V1, A1
    check(in_contact >= 3, "the block touches the plane (%d steps)" % in_contact)
    # the momentum: sum of M V per component (no clamped rows here)
    MV = matvec(M, field(nd.ND_FIELD_VELOCITY))
    for k in range(2):
        x = dbl()
        call(lib.nd_get_scalar(p, nd.ND_MOMENTUM_X + k, ctypes.byref(x)))
        mine = sum(MV[i] for i in range(n) if comp[i] == k)
        check(abs(x.value - mine) <= 4 * n * sys.float_info.epsilon * sum(abs(v) for v in MV),
              "momentum %d: %r, host %r" % (k, x.value, mine))
    call(lib.nd_problem_destroy(ctypes.byref(p)))
    print("host_newmark (Python%s): 30 steps (%d in contact), max |U_host - U_lib| = %.3g, bound %.3g"
          % (", hybrid" if hybrid else "", in_contact, worst, worst_bound))


main(False)
main(True)
sys.exit(finish())
