#!/usr/bin/python3
"""python_bar: the 1D bar of docs/design.md §7 through the Python module, against
the C example.

usage: test_bar.py --bar1d BAR1D [--twin BAR_TWIN] [--workdir DIR]

1. BAR1D --quiet --csv writes t, u(0), v(0), contact stress, E, E_Theta per
   time level with printf's %.10g. The same bar driven from Python must give
   the same rows: each Python value printed with '%.10g' (Python's own
   correctly rounded conversion, as glibc's printf) must be the CSV's text,
   so the parsed values agree to 1e-14 relative (in fact exactly). The CSV
   carries 10 significant digits only; hence also:
2. (with --twin, the C twin of the Fortran test) u and v at every node and
   every time level, at full precision: bitwise identical to Python's.
3. The error path, double close, the monitor, the generated constants.

Prints "N passed, M failed"; exit status 1 when a check failed.
"""

import argparse
import csv
import os
import subprocess
import tempfile
import sys

import numpy as np

import ndcheck
import nitschedyn as nd
from ndcheck import check, finish

ndcheck.verbose = True  # (this test lists its checks)




CLAMPED, CONTACT = 1, 2


def make_bar(nx=40, degree=1, tau=None):
    """The calls of examples/bar1d.c, in the same order."""
    tau = 0.5 / nx if tau is None else tau
    with nd.Mesh.interval(nx, 0.0, 1.0) as m:
        m.mark_boundary_box(CLAMPED, [0.5], [1.5])
        m.mark_boundary_box(CONTACT, [-0.5], [0.5])
        p = nd.Problem(m, degree)  # the problem keeps its own copy of the mesh
    p.set_material(1.0, 0.0, 1.0)
    p.set_dirichlet(CLAMPED)
    p.set_contact_plane(CONTACT, [0.0], [1.0])
    p.set_nitsche(1.0, 0.2)
    p.set_scheme(nd.ND_SCHEME_HYBRID)
    p.set_mass_lumping(False)
    p.set_timestep(tau)
    x = p.node_coordinates()[:, 0]
    p.set_initial_state(0.5 * (1 - x), np.zeros_like(x))
    return p, x


def run_bar(nx=40, degree=1, T=3.0):
    """Rows (t, u(0), v(0), stress, E, E_Theta) and the u, v histories."""
    tau = 0.5 / nx
    steps = int(round(T / tau))
    p, x = make_bar(nx, degree, tau)
    i0 = int(np.argmin(x))  # the node at x = 0
    rows, us, vs = [], [], []
    with p:
        for n in range(steps + 1):
            if n > 0:
                if p.step() != nd.ND_OK:
                    raise RuntimeError("unexpected ND_MONITOR_STOP")
            u = p.field(nd.ND_FIELD_DISPLACEMENT)[:, 0]
            v = p.field(nd.ND_FIELD_VELOCITY)[:, 0]
            lam = p.contact_pressure()[0]
            rows.append((n * tau, u[i0], v[i0], lam, p.scalar(nd.ND_ENERGY_MECHANICAL),
                         p.scalar(nd.ND_ENERGY_AUGMENTED)))
            us.append(u)
            vs.append(v)
    return rows, np.array(us), np.array(vs)


def compare_with_csv(bar1d, workdir, rows):
    path = os.path.join(workdir, "bar1d.csv")
    subprocess.run([bar1d, "--quiet", "--csv", path], check=True, stdout=subprocess.DEVNULL)
    with open(path, newline="") as f:
        table = list(csv.reader(f))
    check(table[0] == ["t", "u(0)", "v(0)", "contact_stress", "E", "E_Theta"], "the CSV header")
    table = table[1:]
    check(len(table) == len(rows), "the CSV has %d time levels, Python %d" % (len(table), len(rows)))
    mismatched_text = 0
    max_rel = [0.0] * 6
    for crow, prow in zip(table, rows):
        for j, (c, value) in enumerate(zip(crow, prow)):
            mine = "%.10g" % (value + 0.0)
            if mine != c:
                mismatched_text += 1
            a, b = float(mine), float(c)
            if a != b:
                max_rel[j] = max(max_rel[j], abs(a - b) / max(abs(a), abs(b)))
    print("  max relative difference per column (t, u(0), v(0), stress, E, E_Theta): "
          + ", ".join("%.1e" % r for r in max_rel))
    check(max(max_rel) <= 1e-14, "u(0), v(0), stress, E, E_Theta histories agree with bar1d --csv to 1e-14")
    check(mismatched_text == 0, "every value printed with %%.10g is the CSV's text (%d differ)" % mismatched_text)


def compare_with_twin(twin, workdir, us, vs):
    path = os.path.join(workdir, "bar_twin.bin")
    subprocess.run([twin, path, "40", "1"], check=True, stdout=subprocess.DEVNULL)
    raw = np.fromfile(path, dtype=np.int64, count=2)
    n, levels = int(raw[0]), int(raw[1])
    data = np.fromfile(path, dtype=np.float64, offset=16).reshape(levels, 2, n)
    check((levels, n) == us.shape, "the twin's history has %d levels of %d nodes" % (levels, n))
    uc, vc = data[:, 0, :], data[:, 1, :]
    same = np.count_nonzero(uc.view(np.int64) == us.view(np.int64)) + \
        np.count_nonzero(vc.view(np.int64) == vs.view(np.int64))
    total = uc.size + vc.size
    diff = max(np.max(np.abs(uc - us)), np.max(np.abs(vc - vs)))
    print("  full histories: %d of %d values bitwise identical, max |Python - C| = %.1e" % (same, total, diff))
    check(same == total, "u and v at every node and level are bitwise identical to the C twin's")


def test_errors():
    p, _ = make_bar(10)
    try:
        p.set_timestep(-1.0)
        check(False, "set_timestep(-1) raises nd.Error")
    except nd.Error as e:
        check(True, "set_timestep(-1) raises nd.Error")
        print("  " + str(e))
        check(e.code == nd.ND_ERR_TIMESTEP and e.name == "ND_ERR_TIMESTEP", "with code ND_ERR_TIMESTEP")
        check(e.message.startswith("nd_problem_set_timestep:"), "and the message of nd_last_error()")
        check(e.message == nd.last_error(), "which nd.last_error() still returns")
    check(nd.lib.nd_problem_set_timestep(p.handle, -1.0) == nd.ND_ERR_TIMESTEP,
          "the raw C call returns ND_ERR_TIMESTEP")
    try:
        p.set_initial_state(np.zeros(3))
        check(False, "a wrong array length raises ValueError")
    except ValueError:
        check(True, "a wrong array length raises ValueError (before reaching C)")
    p.close()
    p.close()
    check(not p.handle, "close() twice is harmless and leaves a NULL handle")
    try:
        p.step()
        check(False, "step() on a closed problem raises ND_ERR_NULL")
    except nd.Error as e:
        check(e.code == nd.ND_ERR_NULL, "step() on a closed problem raises ND_ERR_NULL")


def test_monitor():
    p, _ = make_bar(10)
    calls = []
    p.set_monitor(lambda prob: calls.append(prob.scalar(nd.ND_STEP_INDEX)) or len(calls) == 5)
    statuses = [p.step() for _ in range(5)]
    check(statuses == [nd.ND_OK] * 4 + [nd.ND_MONITOR_STOP], "the monitor runs once per step and stops at the 5th")
    check(calls == [1.0, 2.0, 3.0, 4.0, 5.0], "and sees the problem after each accepted step")

    def boom(prob):
        raise RuntimeError("from the monitor")
    p.set_monitor(boom)
    try:
        p.step()
        check(False, "an exception in the monitor reaches step()'s caller")
    except RuntimeError:
        check(p.scalar(nd.ND_STEP_INDEX) == 6, "an exception in the monitor reaches step()'s caller; step kept")
    p.set_monitor(None)
    check(p.step() == nd.ND_OK and len(calls) == 5, "set_monitor(None) removes it")
    p.close()


def test_constants():
    check(nd.version()[0] == nd.ND_VERSION_MAJOR, "nd.version() agrees with ND_VERSION_MAJOR")
    check(nd.get_blas_threads() == 1, "nd.get_blas_threads(): default 1")
    nd.set_blas_threads(2)
    check(nd.get_blas_threads() == 2, "nd.set_blas_threads(2) round-trips")
    try:
        nd.set_blas_threads(-1)
        check(False, "nd.set_blas_threads(-1) raises")
    except nd.Error as e:
        check(e.code == nd.ND_ERR_VALUE and nd.get_blas_threads() == 2,
              "nd.set_blas_threads(-1) raises ND_ERR_VALUE, the setting unchanged")
    nd.set_blas_threads(1)
    bad = [name for name, (value, text) in nd.STATUS.items() if nd.strerror(value) != text]
    check(not bad, "nd_strerror(code) is the header's text for every generated status code %s" % bad)
    check(nd.ND_ERR_FORMAT == -24 and len(nd.STATUS) >= 25, "the status list is complete")


def test_checkpoint():
    """save_state/load_state from Python: the resumed run is bitwise the uninterrupted one."""
    p, x = make_bar(20, 2)
    with p:
        for _ in range(30):
            p.step()
        blob = p.save_state()
        for _ in range(20):
            p.step()
        u_ref = p.field(nd.ND_FIELD_DISPLACEMENT).copy()
        own, nodes = p.field_owned(nd.ND_FIELD_DISPLACEMENT)
        check(np.array_equal(nodes, np.arange(p.node_count)) and np.array_equal(own, u_ref),
              "without a communicator the process owns every node (Python)")
        check(np.array_equal(p.field_gathered(nd.ND_FIELD_DISPLACEMENT, 0), u_ref),
              "without a communicator the field gathered on rank 0 is the field (Python)")
        try:
            p.field_gathered(nd.ND_FIELD_DISPLACEMENT, 1)
            check(False, "rank 1 of 1 is refused (Python)")
        except nd.Error as e:
            check(e.code == nd.ND_ERR_VALUE, "rank 1 of 1: ND_ERR_VALUE (Python)")
        c = p.field(nd.ND_FIELD_CONTACT_FORCE)
        check(abs(c.sum() - p.scalar(nd.ND_CONTACT_FORCE)) <= 1e-13 * abs(c).sum(),
              "the nodal contact forces sum to ND_CONTACT_FORCE (Python)")
        r = p.field(nd.ND_FIELD_REACTION)[:, 0]
        check(np.all(r[x != 1.0] == 0) and np.any(r[x == 1.0] != 0), "reactions on the clamped DOF only (Python)")
        check(p.scalar(nd.ND_WORK_OBSTACLE) == 0, "a fixed plane does no work (Python)")
        p.load_state(blob)
        for _ in range(20):
            p.step()
        check(np.array_equal(p.field(nd.ND_FIELD_DISPLACEMENT), u_ref), "resumed run bitwise equal (Python)")
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "state.ndck")
            p.load_state(blob)
            p.save_state_file(path)
            with open(path, "rb") as f:
                check(f.read() == blob, "the checkpoint file holds the save_state() block (Python)")
            for _ in range(3):
                p.step()
            p.load_state_file(path)
            for _ in range(20):
                p.step()
            check(np.array_equal(p.field(nd.ND_FIELD_DISPLACEMENT), u_ref), "resumed from a file bitwise (Python)")
            try:
                p.load_state_file(os.path.join(d, "missing.ndck"))
                check(False, "a missing checkpoint file is refused")
            except nd.Error as e:
                check(e.name == "ND_ERR_IO", "a missing checkpoint file is refused with ND_ERR_IO")
        bad = bytearray(blob)
        bad[len(bad) // 2] ^= 0xFF
        try:
            p.load_state(bytes(bad))
            check(False, "a corrupted checkpoint is refused")
        except nd.Error as e:
            check(e.name == "ND_ERR_FORMAT", "a corrupted checkpoint is refused with ND_ERR_FORMAT")
        w = p.scalar(nd.ND_WORK)
        p.set_state(u=0.9 * u_ref)
        check(p.scalar(nd.ND_WORK) == w, "set_state keeps the work")
        p.set_guard(nd.ND_GUARD_ENERGY, 3.0)
        p.step()


def test_pressure_applied():
    """Mass redistribution and the applied pressure: the hybrid's E_Theta does
    not grow (M stays symmetric positive semi-definite), the pressures are <= 0,
    and before the first step the applied pressure is lambda_q."""
    p, _ = make_bar(20, 2, 0.025)
    with p:
        p.set_mass_redistribution(True)
        check(np.array_equal(p.contact_pressure_applied(), p.contact_pressure()), "applied = lambda at t = 0")
        E = p.scalar(nd.ND_ENERGY_AUGMENTED)
        grew, positive = False, False
        for _ in range(120):
            p.step()
            E1 = p.scalar(nd.ND_ENERGY_AUGMENTED)
            grew = grew or E1 > E + 1e-13
            E = E1
            positive = positive or bool((p.contact_pressure_applied() > 0).any())
        check(not grew, "E_Theta non-increasing with mass redistribution")
        check(not positive, "applied pressure <= 0")
        check(p.scalar(nd.ND_CONTACT_FORCE_APPLIED) >= 0, "ND_CONTACT_FORCE_APPLIED >= 0")


def test_prescribed_motion():
    """A bar pushed at v from t = 0 into a wall: with the lumped P1 central
    difference at Courant number 1 the nodal values are the d'Alembert
    solution's, so the reaction is rho c v until the reflection returns and
    the contact force 2 rho c v once the wave has reached the wall
    (tests/test_prescribed_motion.c derives both); the nodal form gives the
    region form's bits."""
    n_cells, v = 20, 0.01
    runs = []
    for nodal in (False, True):
        with nd.Mesh.interval(n_cells, 0.0, 1.0) as m:
            m.mark_boundary_box(1, [-0.1], [0.1])
            m.mark_boundary_box(2, [0.9], [1.1])
            p = nd.Problem(m, 1)
        with p:
            p.set_material(1.0, 0.0, 1.0)
            p.set_dirichlet(1)
            p.set_contact_plane(2, [1.0], [-1.0])
            p.set_nitsche(1.0, 0.5)
            p.set_mass_lumping(1)
            p.set_scheme(nd.ND_SCHEME_NEWMARK, [0.0, 0.5])
            p.set_timestep(1.0 / n_cells)
            p.set_guard(nd.ND_GUARD_CRITICAL_TIMESTEP, 0)
            v0 = np.zeros((p.node_count, 1))
            v0[0, 0] = v
            p.set_initial_state(v0=v0)
            reactions, forces = [], []
            for k in range(0, 2 * n_cells):
                d = v * k / n_cells
                if nodal:
                    p.set_dirichlet_nodal(np.full((p.node_count, 1), d))
                else:
                    p.set_dirichlet_value(1, [d])
                if k == 0:
                    continue
                p.step()
                reactions.append(p.field(nd.ND_FIELD_REACTION)[0, 0])
                forces.append(p.scalar(nd.ND_CONTACT_FORCE))
            runs.append((reactions, forces, p.scalar(nd.ND_WORK_PRESCRIBED)))
    reactions, forces, work = runs[0]
    check(all(abs(r - v) <= 1e-12 * v for r in reactions), "pushed bar: reaction rho c v (Python)")
    check(all(abs(f - 2 * v) <= 1e-12 * v for f in forces[n_cells:]), "pushed bar: contact force 2 rho c v (Python)")
    check(work > 0 and runs[1] == runs[0], "the nodal form gives the region form's bits (Python)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bar1d", required=True)
    ap.add_argument("--twin")
    ap.add_argument("--workdir", default=".")
    args = ap.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    print("nitschedyn %s from %s" % (nd.__version__, nd.lib._name))

    rows, us, vs = run_bar()
    compare_with_csv(args.bar1d, args.workdir, rows)
    if args.twin:
        compare_with_twin(args.twin, args.workdir, us, vs)
    test_errors()
    test_monitor()
    test_constants()
    test_checkpoint()
    test_pressure_applied()
    test_prescribed_motion()
    return finish()


if __name__ == "__main__":
    sys.exit(main())
