#!/usr/bin/python3
"""The stability suite (make stability / make stability-quick).

Runs stability_case (one process per run, --jobs at a time) over a matrix of
stiff and extreme cases: the 1D bar, a free 16x4 rectangle and the disk,
P1/P2, the schemes hybrid, Newmark(1/4,1/2), theta = 1, generalized-alpha
(rho_inf 0.8) and explicit Newmark with lumped mass, Theta = 1, 0, -1, and
gamma0 E from 1e-8 to 1e4, all with the library's default guards. Each run is
classified by stability_case on its own measurement (see its header):
completed, refused at setup, stopped at a step by a guard or a failure, or a
silent failure (ND_OK on a step whose energy or penetration was past the
limits). Every run a guard stops during the steps (ND_ERR_ENERGY_GROWTH,
ND_ERR_PENETRATION) is run again with those guards off and judged on that
rerun: justified when it then fails, gains energy or sinks, a false alarm
otherwise (column rerun_unguarded; stability_case's header). Every run
Newton stops (ND_ERR_NEWTON) is run again with adaptive time steps (column
rerun_adaptive): mended when it then reaches T. Writes
OUT/data/stability.csv and OUT/STABILITY.md, generated from the CSV only.
Exit status 1 when any run is a silent failure or a false alarm.

Besides that matrix (class base), the classes of issue 57 (class_plan; the
class in the CSV's first column, the report's per-class table): 3d (the
ball), material (steel in SI units, rubber nu = 0.49, 0.4999), speed (10x,
100x), timestep (tau 1e-2x to 1e2x, implicit schemes), moving_plane,
static_load, sliver (flat contact cells), long (1e5 steps; full plan only);
and with --random N --seed S, N cases drawn with random.Random(S) (class
random; random_plan), so that the suite is not a fixed list to tune
against. make stability passes a fresh seed from the time unless
STABILITY_SEED is given and prints it; the quick plan (--quick, a test of
make check) stays fixed.
"""
import argparse
import collections
import concurrent.futures as cf
import csv
import io
import os
import platform
import random
import subprocess
import sys
import time

HEAD = ["class", "scene", "degree", "scheme", "Theta", "gamma0E", "options", "tau", "steps", "outcome", "code", "step",
        "energy_growth", "max_penetration_over_h", "late", "newton_per_step", "wall_s", "theory", "message"]
# the rerun's verdict, after the driver's columns
CSV_HEAD = HEAD + ["rerun_unguarded", "rerun_adaptive"]
# the wall time an adaptive rerun gets (the slow part: friction at tiny gamma0)
ADAPTIVE_SECONDS = 60
GUARD_CODES = ("ND_ERR_ENERGY_GROWTH", "ND_ERR_PENETRATION")
GAMMA0E = ["1e-8", "1e-6", "1e-4", "1e-2", "1", "1e2", "1e4"]


SCHEMES = ("hybrid", "newmark", "theta1", "galpha", "explicit", "hybrid_damped", "explicit_damped",
           "hybrid_friction", "newmark_friction", "explicit_friction", "hybrid_layered", "newmark_layered",
           "explicit_layered")
IMPLICIT = ("hybrid", "newmark", "theta1", "galpha")
# the classes of issue 57, in the report's order (random: run.py --random)
CLASSES = ("base", "3d", "material", "speed", "timestep", "moving_plane", "static_load", "sliver", "critical",
           "two_bodies", "long", "random")


def base_plan(quick):
    if quick:
        return [("base", sc, 1, s, th, g, ()) for sc in ("bar", "rect")
                for s in ("hybrid", "newmark", "explicit", "hybrid_damped", "explicit_damped", "hybrid_friction",
                          "explicit_friction", "hybrid_layered", "explicit_layered")
                for th in ("1", "-1") for g in ("1e-4", "1", "1e4") if applies(sc, s)]
    return [("base", sc, d, s, th, g, ()) for sc in ("bar", "rect", "disk") for d in (1, 2)
            for s in SCHEMES for th in ("1", "0", "-1") for g in GAMMA0E if applies(sc, s)]


def class_plan(quick):
    """The extreme classes (stability_case's header: scenes ball, sliver, rest;
    options mat=, speed=, tau=, plane=moving, steps=)."""
    if quick:  # (a few, fast: well under a second in all)
        return [("material", "bar", 1, "hybrid", "1", "1e-4", ("mat=steel",)),
                ("speed", "rect", 1, "explicit", "1", "1", ("speed=100",)),
                ("moving_plane", "rect", 1, "hybrid", "1", "1e-4", ("plane=moving",)),
                ("static_load", "rest", 1, "hybrid", "1", "1e-4", ()),
                ("sliver", "sliver", 1, "hybrid", "-1", "1", ()),
                ("two_bodies", "pair", 1, "hybrid", "1", "0", ()),
                ("two_bodies", "pair", 1, "hybrid_friction", "1", "0", ())]
    c = []
    four = ("hybrid", "newmark", "galpha", "explicit")
    # (a) the 3D ball, P1 (P2: about 2 minutes a run)
    c += [("3d", "ball", 1, s, th, g, ()) for s in ("hybrid", "newmark", "explicit")
          for th in ("1", "-1") for g in ("1e-4", "1", "1e4")]
    # (b) steel in SI units, rubber nearly incompressible
    c += [("material", sc, d, s, th, g, (m,)) for m, scenes in (("mat=steel", ("bar", "rect")),
                                                                 ("mat=rubber", ("rect", "disk")),
                                                                 ("mat=rubber4999", ("rect", "disk")))
          for sc in scenes for d in (1, 2) for s in four for th in ("1", "0", "-1")
          for g in ("1e-4", "1e-2", "1", "1e4")]
    # (c) impact speeds 10 and 100 times the default
    c += [("speed", sc, d, s, th, g, ("speed=%s" % f,)) for f in (10, 100) for sc in ("bar", "rect", "disk")
          for d in (1, 2) for s in four for th in ("1", "-1") for g in ("1e-4", "1", "1e4")]
    # (d) time steps 1e-2 to 1e2 times the default, implicit schemes
    c += [("timestep", sc, d, s, th, g, ("tau=%s" % f,)) for f in ("0.01", "0.1", "10", "100")
          for sc in ("bar", "rect", "disk") for d in (1, 2) for s in IMPLICIT for th in ("1", "-1")
          for g in ("1e-4", "1", "1e4")]
    # (e) the moving plane
    c += [("moving_plane", sc, d, s, th, g, ("plane=moving",)) for sc in ("bar", "rect", "disk") for d in (1, 2)
          for s in four + ("hybrid_friction",) for th in ("1", "0", "-1") for g in ("1e-4", "1e-2", "1", "1e4")
          if applies(sc, s)]
    # (f) a static load: at rest on the plane under gravity, 10^4 steps
    c += [("static_load", "rest", d, s, th, g, ()) for d in (1, 2)
          for s in ("hybrid", "newmark", "galpha", "explicit", "hybrid_damped", "hybrid_friction")
          for th in ("1", "0", "-1") for g in GAMMA0E]
    # (g) flat and sliver contact cells (aspect 1e-3)
    c += [("sliver", "sliver", d, s, th, g, ()) for d in (1, 2)
          for s in ("hybrid", "newmark", "theta1", "galpha", "explicit", "explicit_damped", "hybrid_friction")
          for th in ("1", "0", "-1") for g in GAMMA0E]
    # (i) explicit steps around the library's critical-step estimate, with
    # switching contact: below it a run must be stable or stopped within a
    # step; above it a refusal must be of a run that really blows up
    c += [("critical", sc, d, "explicit", th, g, ("tau_c=%s" % f,))
          for sc, d in (("bar", 1), ("bar", 2), ("rect", 1), ("rect", 2), ("disk", 1), ("ball", 1))
          for th in ("1", "0", "-1") for g in ("0", "1e-2", "1")
          for f in ("0.5", "0.9", "0.99", "1", "1.01", "1.05", "1.2", "1.5")]
    # (j) two deformable bodies: two disks meeting (nd_problem_set_contact_pair)
    c += [("two_bodies", "pair", d, s, th, g, ()) for d in (1, 2)
          for s in ("hybrid", "newmark", "theta1", "galpha", "explicit", "hybrid_friction", "newmark_friction",
                    "explicit_friction") for th in ("1", "0", "-1")
          for g in ("0", "1e-4", "1e-2", "1", "1e4")]
    # (h) 10^5 steps of the bar
    c += [("long", "bar", d, s, th, g, ("steps=100000",)) for d in (1, 2) for s in ("hybrid", "newmark", "galpha")
          for th in ("1", "-1") for g in ("1e-4", "1e-2")]
    return c


def random_plan(n, seed):
    """n cases drawn with random.Random(seed): scene, degree, scheme, Theta (one
    of 1, 0, -1 or uniform), gamma0 E (log-uniform in [1e-8, 1e4], or 0: the
    library's automatic value), material, speed factor, tau factor, a moving
    plane."""
    r = random.Random(seed)
    cases = []
    while len(cases) < n:
        sc = r.choice(("bar", "rect", "disk", "sliver", "rest") * 6 + ("ball",))
        d = 1 if sc == "ball" else r.choice((1, 2))
        s = r.choice(SCHEMES)
        if not applies(sc, s):
            continue
        th = r.choice(("1", "0", "-1")) if r.random() < 0.75 else "%.3f" % r.uniform(-1, 1)
        g = "0" if r.random() < 0.1 else "%.3g" % 10 ** r.uniform(-8, 4)
        opts = []
        mats = ["default", "rubber", "rubber4999"] + (["steel"] if sc in ("bar", "rect", "sliver") else [])
        m = r.choice(mats)
        if m != "default":
            opts.append("mat=" + m)
        if sc != "rest" and r.random() < 2 / 3:
            opts.append("speed=%.3g" % 10 ** r.uniform(-1, 2))
        if r.random() < 2 / 3:
            # (explicit: around the critical step; the rest and the ball: at most 4e4 steps)
            lo = -1 if s.startswith("explicit") else {"rest": -0.6, "ball": -0.3}.get(sc, -2)
            opts.append("tau=%.3g" % 10 ** r.uniform(lo, 0.3 if s.startswith("explicit") else 2))
        if sc != "rest" and r.random() < 0.2:
            opts.append("plane=moving")
        cases.append(("random", sc, d, s, th, g, tuple(opts)))
    return cases


def plan(quick, n_random=0, seed=0):
    return base_plan(quick) + class_plan(quick) + (random_plan(n_random, seed) if n_random else [])


def applies(scene, scheme):
    """Friction needs a tangent plane (2D: not the bar); two materials the
    generated meshes (the bar, the rectangle, the block's variants)."""
    return not (scene == "bar" and "_friction" in scheme) and not (scene in ("disk", "ball") and "_layered" in scheme)


def args(row_or_case):
    if isinstance(row_or_case, dict):
        r = row_or_case
        opts = [] if r["options"] in ("", "-") else r["options"].split(" ")
        return [r["scene"], str(r["degree"]), r["scheme"], r["Theta"], r["gamma0E"]], opts + ["class=" + r["class"]]
    cls, sc, d, s, th, g, opts = row_or_case
    return [sc, str(d), s, th, g], list(opts) + ["class=" + cls]


def call(exe, meshes, what, mode=None, timeout=600):
    head, tail = args(what)
    return subprocess.run([exe] + head + [meshes] + ([mode] if mode else []) + tail, capture_output=True, text=True,
                          timeout=timeout)


def run_one(exe, meshes, case):
    cls, sc, d, s, th, g, opts = case
    try:
        r = call(exe, meshes, case)
        err = r.stderr.strip() if r.returncode != 0 else None
    except subprocess.TimeoutExpired:
        err = "timeout (600 s)"
    if err is not None:
        return dict(zip(HEAD, [cls, sc, d, s, th, g, " ".join(opts) or "-", "", "", "error", "", "", "", "", "", "",
                               "", "-", err]))
    return next(csv.DictReader(io.StringIO(r.stdout), fieldnames=HEAD))


def critical_refusal(row):
    """A set-up refused by the critical-step check (ND_GUARD_CRITICAL_TIMESTEP)."""
    return row["outcome"] == "refused_at_setup" and row["code"] == "ND_ERR_UNSTABLE" and "critical" in row["message"]


def judge(exe, meshes, row):
    """Reruns a run a guard stopped with the guards of the steps off: 'justified: ...' when
    the rerun fails, gains energy (E/(E^0 + max W) > 1.05: a body that creates no energy has
    E <= E^0 + W; or the balance out of contact rises by more than 5 % of the energy in
    motion; or the balance with min(E, E_Theta) does, at any state: stability_case's
    contact_gain) or sinks (deeper than 4 eps* min(h, L/8)),
    'false_alarm: ...' otherwise."""
    if not (row["outcome"] == "stopped_at_step" and row["code"] in GUARD_CODES) and not critical_refusal(row):
        return ""
    try:
        r = call(exe, meshes, row, "unguarded")
    except subprocess.TimeoutExpired:
        return "error: timeout (600 s)"
    if r.returncode != 0:
        return "error: " + r.stderr.strip()[:80]
    outcome, code, step, growth, gain, pen, cgain = r.stdout.strip().split(",")
    why = []
    if outcome == "stopped_at_step":
        why.append("fails (%s at step %s)" % (code, step))
    if float(growth) > 1.05 or float(gain) > 0.05 or float(cgain) > 0.05:
        why.append("gains (E/(E0 + max W) %s, balance out of contact +%s, in contact +%s)" % (growth, gain, cgain))
    if float(pen) > 4:
        why.append("sinks (%s x the penetration limit)" % pen)
    return ("justified: " if why else "false_alarm: ") + ("; ".join(why) if why else
                                                          "growth %s, balance +%s, in contact +%s, penetration %s" %
                                                          (growth, gain, cgain, pen))


def adapt(exe, meshes, row):
    """Reruns a run Newton stopped with adaptive time steps (the guards on):
    'completed: N steps, R rejected', or what stopped it."""
    if row["outcome"] != "stopped_at_step" or row["code"] != "ND_ERR_NEWTON":
        return ""
    try:
        r = call(exe, meshes, row, "adaptive", timeout=ADAPTIVE_SECONDS)
    except subprocess.TimeoutExpired:
        return "timeout: not at T within %d s" % ADAPTIVE_SECONDS
    if r.returncode != 0:
        return "error: " + r.stderr.strip()[:80]
    outcome, code, steps, rejected = r.stdout.strip().split(",")
    if outcome == "completed":
        return "completed: %s steps, %s rejected" % (steps, rejected)
    return "%s: %s after %s steps" % (outcome, code, steps)


def table(head, rows):
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"


def class_table(rows):
    """Per class: runs, completed, refused at setup, stopped by a guard and
    justified by the rerun without the guards, false alarms, stopped otherwise
    (Newton, ...; of them completed with adaptive steps), silent failures."""
    out = []
    for c in [c for c in CLASSES if any(r["class"] == c for r in rows)]:
        rs = [r for r in rows if r["class"] == c]
        guard = [r for r in rs if r.get("rerun_unguarded")]
        other = [r for r in rs if r["outcome"] == "stopped_at_step" and not r.get("rerun_unguarded")]
        out.append([c, len(rs), sum(r["outcome"] == "completed" for r in rs),
                    sum(r["outcome"] == "refused_at_setup" and not r.get("rerun_unguarded") for r in rs),
                    sum(r["rerun_unguarded"].startswith("justified") for r in guard),
                    sum(not r["rerun_unguarded"].startswith("justified") for r in guard),
                    "%d (%d)" % (len(other), sum(r.get("rerun_adaptive", "").startswith("completed") for r in other)),
                    sum(r["outcome"] in ("silent_failure", "error") for r in rs) +
                    sum(r.get("rerun_adaptive", "").startswith("silent") for r in rs)])
    tot = ["**all**"] + [sum(int(str(x).split()[0]) for x in col) for col in list(zip(*out))[1:]]
    tot[6] = "%d (%d)" % (tot[6], sum(int(r[6].split("(")[1][:-1]) for r in out))
    return table(["class", "runs", "completed", "refused at setup", "guard refusals, justified", "false alarms",
                  "stopped otherwise (adaptive rerun completed)", "silent"], out + [tot])


def opt(r):
    return "" if r["options"] in ("", "-") else r["options"]


def report(rows, out, seconds, quick, seed=None, n_random=0):
    by = collections.Counter(r["outcome"] for r in rows)
    codes = collections.Counter((r["outcome"], r["code"]) for r in rows if r["outcome"] != "completed")
    silent = [r for r in rows if r["outcome"] in ("silent_failure", "error")]
    late = [r for r in rows if r["outcome"] == "stopped_at_step" and r["late"] not in ("", "0")]
    md = ["# Stability on stiff and extreme cases\n",
          "Generated by `tools/stability/run.py%s` from `data/stability.csv`; never edited by hand.\n" %
          (" --quick" if quick else (" --random %d --seed %s" % (n_random, seed) if n_random else "")),
          "Machine: %s, %d cores, %s; %s. %d runs in %.0f s.\n" % (
              platform.machine(), os.cpu_count(), platform.platform(), time.strftime("%Y-%m-%d"), len(rows), seconds),
          "Every run uses the library's default guards (`nd_problem_set_guard(3)`). A run is a **silent "
          "failure** when `nd_step` returned ND_OK on a step whose mechanical energy (plus the damping's "
          "dissipation, in the `_damped` runs: Rayleigh alpha = 0.05, beta = 0.1 tau; and friction's, in the "
          "`_friction` runs: Coulomb F = 0.3; `_layered`: half the cells 4 times as stiff and twice as dense) exceeded twice the energy "
          "put in (E^0 + max W), became non-finite, or whose deepest contact point sank more than "
          "4 eps* min(h, L/8) (eps* = sqrt(2 (E^0 + max W) / int E dx), the strain of the energy put in; L = "
          "|Omega|/|Gamma_C|, the body's length across its contact region: the penetration guard's default, "
          "invariant under a change of units), as measured by the driver itself "
          "(`tools/stability/stability_case.c`), and the run completed all the same.\n",
          "## Per class\n",
          "The classes of issue 57 (`class` in the CSV; the scenes and options in `tools/stability/stability_case.c`'s "
          "header): base (bar, rect, disk: every scheme, Θ, γ0 E), 3d (the ball, P1), material (steel in SI "
          "units, rubber ν = 0.49 and 0.4999), speed (impact 10 and 100 times the default), timestep (τ 1e-2 to "
          "1e2 times the default, implicit schemes), moving_plane, static_load (at rest on the plane under "
          "gravity, 10^4 steps), sliver (contact cells 1e-3 as high as wide), critical (the explicit scheme at "
          "0.5 to 1.5 times the library's critical-step estimate: bar P1/P2, rect P1/P2, disk, ball), two_bodies "
          "(two disks meeting, a contact pair: every scheme, Θ, γ0 E), long (10^5 "
          "steps of the bar)%s. Refused at setup: by the set-up's checks other than the critical step. Guard "
          "refusals, justified / false alarms: stopped by ND_ERR_ENERGY_GROWTH or ND_ERR_PENETRATION, or refused "
          "at setup by the critical-step check (ND_ERR_UNSTABLE), and judged by "
          "the rerun without the guards (below); stopped otherwise: Newton and the other codes, in brackets those "
          "the rerun with adaptive steps completed; silent: silent failures (an adaptive rerun completed past the "
          "limits counts too) and errors of the driver.\n" % (
              (", random (%d cases drawn with `random.Random(%s)`: scene, degree, scheme, Θ, γ0 E log-uniform in "
               "[1e-8, 1e4] or 0 the automatic value, material, speed, τ, a moving plane; replay with `make "
               "stability STABILITY_SEED=%s`)" % (n_random, seed, seed)) if n_random else ""),
          class_table(rows),
          "## Outcomes\n",
          table(["outcome", "runs"], sorted(by.items())),
          "**Silent failures: %d of %d runs.**\n" % (len(silent), len(rows)),
          "Runs stopped by a guard only after accepting steps past those limits: %d, at most %s steps late, "
          "the largest energy growth then %s.\n" % (len(late), max((int(r["late"]) for r in late), default=0),
                                         max((float(r["energy_growth"]) for r in late), default=0)),
          "## Refusals and stops, by code\n",
          table(["outcome", "code", "runs"], [[o, c, n] for (o, c), n in sorted(codes.items())]),
          "## The theory's verdict\n",
          "Hybrid scheme, Θ = 1: E_Θ + D − W − W_geometry never increases (part 2 of the paper, D the damping's "
          "dissipation with friction's, docs/design.md §10.5 and §10.2; loads only on the disk; W_geometry what "
          "a contact pair's re-pairing puts in, §10.3). ",
          ]
    hyb = [r for r in rows if r["theory"] != "-"]
    md.append("Of %d such runs that reached a step, %d held and %d violated it%s.\n" % (
        len(hyb), sum(r["theory"] == "held" for r in hyb), sum(r["theory"] == "violated" for r in hyb),
        "" if not any(r["theory"] == "violated" for r in hyb) else " (listed below)"))
    viol = [r for r in hyb if r["theory"] == "violated"]
    if viol:
        md.append(table(["scene", "P", "Θ", "γ0 E", "outcome", "code"],
                        [[r["scene"], r["degree"], r["Theta"], r["gamma0E"], r["outcome"], r["code"]] for r in viol]))
    judged = [r for r in rows if r.get("rerun_unguarded")]
    alarms = [r for r in judged if not r["rerun_unguarded"].startswith("justified")]
    md.append("\n## Refusals judged by a rerun without the guards\n")
    md.append("Each run stopped by ND_ERR_ENERGY_GROWTH or ND_ERR_PENETRATION, or refused at setup by the "
              "critical-step check, is run again with the energy, energy-balance and penetration guards and the "
              "critical-step check off. Justified: the rerun then fails, gains energy "
              "(E/(E^0 + max W) > 1.05, or the balance E_Θ − W − W_obstacle − W_prescribed − W_geometry + D rises, at "
              "a state without an active point, by more than 5 %% of the energy in motion above its lowest value "
              "at such a state before, or, with min(E, E_Θ) for E_Θ, at any state above that lowest value: a gain "
              "in contact) or sinks (deeper than 4 ε* min(h, L/8)). **%d refusals judged, %d justified, "
              "%d false alarms.**\n" % (len(judged), len(judged) - len(alarms), len(alarms)))
    if alarms:
        md.append(table(["class", "scene", "P", "scheme", "Θ", "γ0 E", "options", "code", "step", "rerun"],
                        [[r["class"], r["scene"], r["degree"], r["scheme"], r["Theta"], r["gamma0E"], opt(r),
                          r["code"], r["step"],
                          r["rerun_unguarded"]] for r in alarms]))
    newton = [r for r in rows if r.get("rerun_adaptive")]
    mended = [r for r in newton if r["rerun_adaptive"].startswith("completed")]
    md.append("\n## Newton failures rerun with adaptive time steps\n")
    md.append("Each run stopped by ND_ERR_NEWTON at its fixed step is run again with adaptive steps "
              "(`nd_problem_set_adaptive_timestep(3)`: tolerance 1e-2, tau_min = 1e-4 tau, tau_max = tau; the "
              "guards on; at most %d s of wall time). **%d Newton failures, %d completed with adaptive steps.**\n" % (ADAPTIVE_SECONDS, len(newton), len(mended)))
    if newton:
        md.append(table(["class", "scene", "P", "scheme", "Θ", "γ0 E", "options", "step", "adaptive rerun"],
                        [[r["class"], r["scene"], r["degree"], r["scheme"], r["Theta"], r["gamma0E"], opt(r), r["step"],
                          r["rerun_adaptive"]] for r in newton]))
    base = [r for r in rows if r["class"] == "base"]
    md.append("\n## Per scheme and γ0 E: what happened (class base)\n")
    md.append("Cells: C completed, R refused at setup, S stopped by a guard or failure during the run, "
              "X silent failure; one letter per (scene, degree, Θ) in the order of the rows of the CSV.\n")
    letters = {"completed": "C", "refused_at_setup": "R", "stopped_at_step": "S", "silent_failure": "X", "error": "E"}
    schemes = sorted({r["scheme"] for r in base})
    gs = sorted({r["gamma0E"] for r in base}, key=float)
    grid = []
    for s in schemes:
        line = [s]
        for g in gs:
            line.append("".join(letters[r["outcome"]] for r in base if r["scheme"] == s and r["gamma0E"] == g))
        grid.append(line)
    md.append(table(["scheme"] + ["γ0 E = %s" % g for g in gs], grid))
    if silent:
        md.append("\n## Silent failures\n")
        md.append(table(["class", "scene", "P", "scheme", "Θ", "γ0 E", "options", "energy growth", "penetration / h",
                         "code", "message"],
                        [[r["class"], r["scene"], r["degree"], r["scheme"], r["Theta"], r["gamma0E"], opt(r),
                          r["energy_growth"], r["max_penetration_over_h"], r["code"], r["message"][:80]]
                         for r in silent]))
    md.append("\n## Every run\n")
    md.append("The columns of `data/stability.csv`: the case, the outcome, the status code and the step it came at, "
              "the largest E/(E^0 + max W) and penetration/h seen on accepted steps, Newton iterations per step, "
              "wall time, and the message of a refusal.\n")
    open(os.path.join(out, "STABILITY.md"), "w").write("\n".join(md))


def main():
    a = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    a.add_argument("--quick", action="store_true")
    a.add_argument("--build", default="build")
    a.add_argument("--meshes", default="examples/meshes")
    a.add_argument("--out", default="report")
    a.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    a.add_argument("--random", type=int, default=0, metavar="N", help="N cases drawn at random (besides the plan)")
    a.add_argument("--seed", default=None, help="the seed of --random (default: from the time)")
    a.add_argument("--only-random", action="store_true", help="the random cases alone (to replay a seed quickly)")
    a.add_argument("--class", dest="classes", action="append", choices=CLASSES, metavar="NAME",
                   help="run only the cases of this class (repeatable; %s)" % ", ".join(CLASSES))
    o = a.parse_args()
    if o.random and o.seed is None:
        o.seed = time.strftime("%Y%m%d%H%M%S", time.gmtime())
    if o.random:
        print("stability: %d random cases, seed %s (replay: run.py --random %d --seed %s)" % (o.random, o.seed,
                                                                                             o.random, o.seed))
    exe = os.path.join(o.build, "tools", "stability", "stability_case")
    os.makedirs(os.path.join(o.out, "data"), exist_ok=True)
    env_threads = os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # one process per core
    cases = random_plan(o.random, o.seed) if o.only_random else plan(o.quick, o.random, o.seed)
    if o.classes:
        cases = [c for c in cases if c[0] in o.classes]
    t0 = time.time()
    with cf.ThreadPoolExecutor(o.jobs) as pool:
        rows = list(pool.map(lambda c: run_one(exe, o.meshes, c), cases))
        verdicts = list(pool.map(lambda r: judge(exe, o.meshes, r), rows))
        adapted = list(pool.map(lambda r: adapt(exe, o.meshes, r), rows))
    for r, v, a in zip(rows, verdicts, adapted):
        r["rerun_unguarded"], r["rerun_adaptive"] = v, a
    seconds = time.time() - t0
    with open(os.path.join(o.out, "data", "stability.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_HEAD)
        w.writeheader()
        w.writerows(rows)
    report(rows, o.out, seconds, o.quick, o.seed, o.random)
    by = collections.Counter(r["outcome"] for r in rows)
    silent = by["silent_failure"] + by["error"]
    alarms = sum(1 for r in rows if r["rerun_unguarded"] and not r["rerun_unguarded"].startswith("justified"))
    print("%d refusals rerun without the guards: %d false alarms" % (sum(1 for r in rows if r["rerun_unguarded"]),
                                                                    alarms))
    print("%d runs in %.0f s (OPENBLAS_NUM_THREADS=%s): %s" % (len(rows), seconds, env_threads,
                                                              ", ".join("%s %d" % kv for kv in sorted(by.items()))))
    newton = [r["rerun_adaptive"] for r in rows if r["rerun_adaptive"]]
    print("%d Newton failures rerun with adaptive steps: %d completed" %
          (len(newton), sum(a.startswith("completed") for a in newton)))
    # (an adaptive rerun that completes past the limits is a silent failure too)
    silent += sum(a.startswith("silent") for a in newton)
    print("%d passed, %d failed" % (len(rows) - silent, silent))
    if o.random:
        print("seed %s" % o.seed)
    return 1 if silent or alarms else 0


if __name__ == "__main__":
    sys.exit(main())
