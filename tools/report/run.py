#!/usr/bin/python3
"""Runs the work-precision study of the report (make report / make report-quick).

Every run is a separate process of build/bar1d (the 1D bar against its exact
solution), build/disk_study (the 2D disk against its finest run, in triangles and in
quadrilaterals; the 3D ball in tetrahedra and hexahedra against one reference) or
tools/report/getfem_bar.py (the bar with GetFEM), each writing CSV rows; this
script only decides what to run, runs it on --jobs workers and collects the
rows into OUT/data/*.csv. tools/report/make_report.py turns them into the
plots and REPORT.md.

Plans: --full (the report: NX = 20..2560) and --quick (CI: NX = 20..160).
"""
import argparse
import concurrent.futures as cf
import os
import platform
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# (label, bar1d scheme arguments, explicit)
SCHEMES = [
    ("theta(0.5)", ["theta", "--theta-param", "0.5"], False),
    ("theta(1)", ["theta", "--theta-param", "1"], False),
    ("newmark(0.25,0.5)", ["newmark", "--beta", "0.25", "--gamma", "0.5"], False),
    ("newmark(0.5,1)", ["newmark", "--beta", "0.5", "--gamma", "1"], False),
    ("hybrid", ["hybrid"], False),
    ("galpha(0.8)", ["galpha", "--rho-inf", "0.8"], False),
    ("galpha(0.5)", ["galpha", "--rho-inf", "0.5"], False),
    ("newmark(0,0.5)", ["newmark", "--beta", "0", "--gamma", "0.5", "--lumped", "1"], True),
]
SCHEME_ARGS = {label: args for label, args, _ in SCHEMES}
GAMMA0 = 0.2  # the bar's usual value (docs/design.md §7), paper convention
TAU_OVER_H = 0.5  # implicit schemes: tau = h/2 (wave speed 1: CFL number 1/2 per cell)
EXPLICIT_TAU_OVER_DX = 0.25  # explicit Newmark, lumped: tau = dx/4, dx = h/degree the node spacing


def plan(quick):
    if quick:
        return dict(nx=[20, 40, 80, 160], nx_t12_max=160, tau_ladder_nx=160, tau_ladder_k=4, repeat=3,
                    getfem_nx=[20, 40, 80], disk="quick", pressure_nx=[20, 40, 80, 160], pressure_repeat=1)
    return dict(nx=[20, 40, 80, 160, 320, 640, 1280, 2560], nx_t12_max=640, tau_ladder_nx=1280,
                tau_ladder_k=6, repeat=3, getfem_nx=[20, 40, 80, 160, 320], disk="full",
                pressure_nx=[20, 40, 80, 160, 320, 640], pressure_repeat=3)


def bar_argv(build, scheme_args, degree, Theta, nx, tau, T, repeat, row, study, at=None):
    """One bar1d run appending its summary row(s) to row."""
    argv = [os.path.join(build, "bar1d")] + scheme_args + [
        "--degree", str(degree), "--Theta", str(Theta), "--gamma0", str(GAMMA0), "--nx", str(nx),
        "--tau", repr(tau), "--T", str(T), "--quiet", "--repeat", str(repeat), "--row", row, "--study", study]
    return argv + (["--at", str(at)] if at else [])


def bar_jobs(build, p, rows_dir):
    """(cost estimate, argv) of every bar1d run."""
    jobs = []

    def add(study, scheme_args, degree, Theta, nx, tau, T, at, repeat=None):
        row = os.path.join(rows_dir, "bar_%05d.csv" % len(jobs))
        argv = bar_argv(build, scheme_args, degree, Theta, nx, tau, T, repeat or p["repeat"], row, study, at)
        jobs.append((T / tau * nx * degree, argv))

    # the mesh ladder, tau tied to h; T = 12 runs also summarize at T = 3
    for label, args, explicit in SCHEMES:
        for degree in (1, 2):
            for Theta in (1, 0, -1):
                for nx in p["nx"]:
                    h = 1.0 / nx
                    tau = EXPLICIT_TAU_OVER_DX * h / degree if explicit else TAU_OVER_H * h
                    if nx <= p["nx_t12_max"]:
                        add("h-ladder", args, degree, Theta, nx, tau, 12, 3)
                    else:
                        add("h-ladder", args, degree, Theta, nx, tau, 3, None)
    # the time-step ladder at a fixed fine mesh (Theta = 1): implicit schemes
    # from tau = h/2 up, the explicit one from its safe step down
    nx = p["tau_ladder_nx"]
    h = 1.0 / nx
    for label, args, explicit in SCHEMES:
        for degree in (1, 2):
            for k in range(p["tau_ladder_k"]):
                if explicit:
                    if k >= 3:
                        continue
                    tau = EXPLICIT_TAU_OVER_DX * h / degree / 2 ** k
                else:
                    tau = TAU_OVER_H * h * 2 ** k
                add("tau-ladder", args, degree, 1, nx, tau, 3, None)
    jobs += pressure_jobs(build, p, rows_dir, "bar_p")
    return jobs


def pressure_jobs(build, p, rows_dir, prefix="pressure_"):
    """The contact pressure (issue 16): with and without mass redistribution,
    lambda at t^n or the pressure the step applied; Theta = 1, T = 3. The
    explicit scheme (lumped) without redistribution at its usual tau = dx/4;
    with it (the massless contact node found from its static equilibrium each
    step) at tau = h/2 like the implicit schemes and at tau = h (CFL 1, where
    the P1 interior stencil is exact at the nodes; the critical-step guard off,
    its estimate being a little below the exact step h/cos(pi/2NX)) and at
    tau = 0.9 h (the guard on) for P1, and at dx/4 for P2 (tau = h/2 is above P2's critical step, about 0.41 h)."""
    jobs = []

    def add(args, degree, nx, tau):
        row = os.path.join(rows_dir, "%s%05d.csv" % (prefix, len(jobs)))
        argv = bar_argv(build, args, degree, 1, nx, tau, 3, p["pressure_repeat"], row, "pressure")
        jobs.append((3 / tau * nx * degree, argv))

    for label, args, explicit in SCHEMES:
        for degree in (1, 2):
            for red in (0, 1):
                for pressure in ("end", "applied"):
                    a = args + ["--redistribute", str(red), "--pressure", pressure]
                    if not explicit:
                        steps = [(TAU_OVER_H, [])]
                    elif not red or degree == 2:
                        steps = [(EXPLICIT_TAU_OVER_DX / degree, [])]
                    else:
                        # 0.9 h: below the critical step with its guard on, the jump
                        # times off the time grid (how much of CFL 1's accuracy stays)
                        steps = [(TAU_OVER_H, []), (0.9, []), (1.0, ["--critical-guard", "0"])]
                    for tau_over_h, extra in steps:
                        for nx in p["pressure_nx"]:
                            add(a + extra, degree, nx, tau_over_h / nx)
    return jobs


def merge_rows(rows_dir, prefix, out, study):
    """Replaces the rows of `study` in the CSV file out by the new ones."""
    new = os.path.join(rows_dir, "_new.csv")
    n = concat(rows_dir, prefix, new)
    with open(new) as fh:
        new_lines = fh.read().splitlines()
    if not os.path.exists(out):
        os.replace(new, out)
        return n
    with open(out) as fh:
        old = fh.read().splitlines()
    header = old[0] if old else new_lines[0]
    col = header.split(",").index("study")
    kept = [l for l in old[1:] if l.strip() and l.split(",")[col] != study]
    with open(out, "w") as fh:
        fh.write("".join(l + "\n" for l in [header] + kept + new_lines[1:]))
    return n


def run_one(argv):
    t0 = time.time()
    r = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return argv, r.returncode, r.stdout, r.stderr, time.time() - t0


def run_all(jobs, n_workers, log):
    """Runs the jobs, longest first, on n_workers processes at a time."""
    jobs = sorted(jobs, key=lambda j: -j[0])
    failures = 0
    with cf.ThreadPoolExecutor(max_workers=n_workers) as ex:
        for argv, rc, out, err, wall in ex.map(run_one, [a for _, a in jobs]):
            short = " ".join(os.path.basename(a) if i == 0 else a for i, a in enumerate(argv))
            log.write("%.2fs rc=%d %s\n%s%s" % (wall, rc, short, out if rc not in (0, 1) else "", err))
            # bar1d exits 1 when a step fails (an explicit step beyond its
            # critical step, say): that row is kept with its error as status
            if rc not in (0, 1) or (rc == 1 and "failed" not in err):
                failures += 1
                sys.stderr.write("run failed (%d): %s\n%s" % (rc, short, err))
    return failures


def concat(rows_dir, prefix, out):
    files = sorted(f for f in os.listdir(rows_dir) if f.startswith(prefix) and f.endswith(".csv"))
    header, lines = None, []
    for f in files:
        with open(os.path.join(rows_dir, f)) as fh:
            content = fh.read().splitlines()
        if not content:
            continue
        header = header or content[0]
        lines += [l for l in content[1:] if l.strip()]
    with open(out, "w") as fh:
        if header:
            fh.write(header + "\n")
        fh.write("".join(l + "\n" for l in lines))
    return len(lines)


def machine():
    cpu = platform.processor() or "unknown"
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    mem = ""
    try:
        with open("/proc/meminfo") as fh:
            mem = "%.0f GiB" % (int(fh.readline().split()[1]) / 2 ** 20)
    except (OSError, ValueError, IndexError):
        pass
    return "%s, %d cores, %s, %s" % (cpu, os.cpu_count() or 0, mem, platform.platform())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "report"))
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--quick", action="store_true", help="the CI plan (NX = 20..160, about a minute)")
    g.add_argument("--full", action="store_true", help="the report's plan (NX = 20..2560, default)")
    ap.add_argument("--jobs", type=int, default=2, help="runs at a time (default 2)")
    ap.add_argument("--only", choices=["bar", "pressure", "getfem", "disk", "ball", "energy"], action="append",
                    help="run only these parts (repeatable); default all. pressure: the bar's pressure study "
                         "alone (part of bar), its rows replacing those of bar.csv in OUT/data. pressure, disk and ball "
                         "alone keep OUT/data's other files (their log goes to runs_pressure.log, "
                         "runs_disk.log or runs_ball.log, machine.txt gains a line)")
    a = ap.parse_args()
    # one thread per run: the runs are small, and two of them share the machine
    os.environ["OPENBLAS_NUM_THREADS"] = "1"
    os.environ["OMP_NUM_THREADS"] = "1"
    p = plan(a.quick)
    parts = a.only or ["bar", "getfem", "disk", "ball", "energy"]
    data = os.path.join(a.out, "data")
    os.makedirs(data, exist_ok=True)
    t_start = time.time()
    failures = 0
    # a re-run of the pressure or the disk study alone into an existing data
    # directory: its own log; the other parts' log, machine and date stay
    alone = set(parts) <= {"pressure", "disk", "ball"}
    log_name = "runs_%s.log" % "_".join(sorted(set(parts))) if alone else "runs.log"
    with tempfile.TemporaryDirectory() as rows, open(os.path.join(data, log_name), "w") as log:
        if "bar" in parts:
            t0 = time.time()
            failures += run_all(bar_jobs(a.build, p, rows), a.jobs, log)
            n = concat(rows, "bar_", os.path.join(data, "bar.csv"))
            print("bar: %d rows in %.0f s" % (n, time.time() - t0), flush=True)
        elif "pressure" in parts:  # the pressure study alone: its rows replace those in bar.csv
            t0 = time.time()
            failures += run_all(pressure_jobs(a.build, p, rows), a.jobs, log)
            n = merge_rows(rows, "pressure_", os.path.join(data, "bar.csv"), "pressure")
            print("pressure: %d rows in %.0f s" % (n, time.time() - t0), flush=True)
        if "energy" in parts:  # energy histories, P1, NX = 80, T = 12, Theta = 1
            t0 = time.time()
            jobs = []
            for label, name in (("theta(0.5)", "theta_half"), ("newmark(0.25,0.5)", "newmark"), ("hybrid", "hybrid")):
                csv = os.path.join(data, "energy_%s.csv" % name)
                jobs.append((1, [os.path.join(a.build, "bar1d")] + SCHEME_ARGS[label] +
                             ["--degree", "1", "--nx", "80", "--T", "12", "--Theta", "1", "--gamma0", str(GAMMA0),
                              "--quiet", "--csv", csv]))
            failures += run_all(jobs, a.jobs, log)
            print("energy histories in %.0f s" % (time.time() - t0), flush=True)
        if "getfem" in parts:
            t0 = time.time()
            out = os.path.join(data, "getfem.csv")
            if os.path.exists(out):
                os.remove(out)
            argv = ["/usr/bin/python3", os.path.join(ROOT, "tools", "report", "getfem_bar.py"),
                    "--lib", os.path.join(a.build, "tools", "report", "libbar1d_exact.so"),
                    "--nx", ",".join(map(str, p["getfem_nx"])), "--degree", "1,2", "--Theta", "1",
                    "--gamma0", str(GAMMA0), "--beta", "0.25", "--gamma", "0.5", "--T", "3",
                    "--tau-over-h", str(TAU_OVER_H), "--repeat", str(p["repeat"]), "--csv", out]
            failures += run_all([(1, argv)], 1, log)
            # our runs of the same discretisations, one at a time right after
            # GetFEM's, so that both codes are timed under the same conditions
            jobs = []
            for degree in (1, 2):
                for nx in p["getfem_nx"]:
                    row = os.path.join(rows, "pair_%05d.csv" % len(jobs))
                    jobs.append((1, bar_argv(a.build, SCHEME_ARGS["newmark(0.25,0.5)"], degree, 1, nx, TAU_OVER_H / nx, 3,
                                             p["repeat"], row, "getfem-pair")))
            failures += run_all(jobs, 1, log)
            concat(rows, "pair_", os.path.join(data, "getfem_pair.csv"))
            print("getfem and its pairs in %.0f s" % (time.time() - t0), flush=True)
        if "disk" in parts:
            t0 = time.time()
            argv = [os.path.join(a.build, "disk_study"), "--plan", p["disk"], "--out", data,
                    "--repeat", str(p["repeat"])]
            failures += run_all([(1, argv), (1, argv + ["--cells", "quadrilateral"])], 1, log)
            print("disk in %.0f s" % (time.time() - t0), flush=True)
        if "ball" in parts:  # one process (the reference needs 2.6 GB); each run timed once (P1 h = 1: 4 min)
            t0 = time.time()
            failures += run_all([(1, [os.path.join(a.build, "disk_study"), "--plan", p["disk"], "--out", data,
                                      "--repeat", "1", "--body", "ball"])], 1, log)
            print("ball in %.0f s" % (time.time() - t0), flush=True)
    if alone:  # the other parts' machine and date stay; this re-run is recorded beside them
        with open(os.path.join(data, "machine.txt"), "a") as fh:
            fh.write("%s study re-run (--only %s): %s, %s, plan %s, jobs %d, wall time %.0f s\n" %
                     (" and ".join(sorted(set(parts))), " --only ".join(sorted(set(parts))), machine(), time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "quick" if a.quick else "full",
                      a.jobs, time.time() - t_start))
    else:
        with open(os.path.join(data, "machine.txt"), "w") as fh:
            fh.write("machine: %s\ndate: %s\nplan: %s\njobs: %d\nwall time of the runs: %.0f s\n" %
                     (machine(), time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "quick" if a.quick else "full",
                      a.jobs, time.time() - t_start))
    print("runs done in %.0f s (%d failed)" % (time.time() - t_start, failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
