#!/usr/bin/python3
"""Turns the CSV files of tools/report/run.py into plots and REPORT.md.

    make_report.py --data DIR --out OUTDIR

DIR holds bar.csv, getfem.csv, energy_*.csv, disk.csv, disk_force.csv and
machine.txt (any of them may be missing: the report then says that part was
not run). Rows whose status is not "ok" are listed as failed runs and left out
of fits and plots. The output depends on the CSV files only.
"""
import argparse
import csv
import math
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

SCHEMES = ["theta(0.5)", "theta(1)", "newmark(0.25,0.5)", "newmark(0.5,1)", "hybrid", "galpha(0.8)", "galpha(0.5)",
           "newmark(0,0.5)"]
MARKERS = ["o", "s", "^", "v", "D", "P", "X", "*"]
NORMS = [("e_linf_l2_u", "L∞(0,T;L²) u"), ("e_linf_h1_u", "L∞(0,T;H¹) u"), ("e_linf_l2_v", "L∞(0,T;L²) v"),
         ("e_l2_l2_u", "L²(0,T;L²) u"), ("e_l2_h1_u", "L²(0,T;H¹) u"), ("e_l2_l2_v", "L²(0,T;L²) v"),
         ("e_l2_stress", "L²(0,T) contact stress")]
NAME = dict(NORMS)
WP = [("e_l2_l2_u", "u_l2l2"), ("e_l2_l2_v", "v_l2l2"), ("e_l2_stress", "stress")]
TARGETS = [("e_l2_stress", "contact-stress", [1e-1, 5e-2, 2e-2, 1e-2]), ("e_l2_l2_u", "u L²L²", [1e-2, 1e-3, 1e-4]),
           ("e_l2_l2_v", "v L²L²", [1e-1, 5e-2, 2e-2])]
DISK_ERR = [("e_l2_u_t12", "u L² t=12"), ("e_energy_u_t12", "u energy t=12"), ("e_l2_u_t14", "u L² t=14"),
            ("e_energy_u_t14", "u energy t=14"), ("e_force_l2", "force L²(0,T)"),
            ("e_force_l2_red", "force L²(0,T) vs redistributed ref")]
TEXT = ["code", "study", "scheme", "status", "run", "pressure", "cells"]
PNGS = {"bar": ["bar_wp_%s_T%d.png" % (s, T) for T in (3, 12) for _, s in WP] +
        ["bar_wp_theta_T3.png", "bar_conv_T3.png", "bar_tau_ladder.png"],
        "energy": ["bar_energy.png"], "disk": ["disk_wp.png", "disk_force.png", "disk_force_conv.png"],
        "pressure": ["bar_pressure_conv.png", "bar_pressure_wp.png"]}


# ---------------------------------------------------------------- helpers
def fnum(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return math.nan


def read_csv(path):
    """Rows of a CSV file as dicts (numbers converted), or None if absent."""
    if not os.path.exists(path):
        return None
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    for r in rows:
        for k in list(r):
            if k not in TEXT:
                r[k] = fnum(r[k])
        r["status"] = (r.get("status") or "").strip()
    return rows


def g3(x):
    return "–" if x is None or not math.isfinite(x) else "%.3g" % x


def frate(x):
    return "–" if not math.isfinite(x) else "%.2f" % x


def ftime(s):
    if s is None or not math.isfinite(s):
        return "–"
    return "%.3g ms" % (1e3 * s) if s < 1 else "%.3g s" % s


def table(head, rows):
    out = ["| " + " | ".join(head) + " |", "|" + "|".join("---" for _ in head) + "|"]
    return "\n".join(out + ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]) + "\n"


def rank(scheme):
    return (SCHEMES.index(scheme), "") if scheme in SCHEMES else (len(SCHEMES), scheme)


def style(scheme, degree):
    i = SCHEMES.index(scheme) if scheme in SCHEMES else len(SCHEMES) + sum(map(ord, scheme)) % 3
    return dict(color="C%d" % i, marker=MARKERS[i % len(MARKERS)], ms=5, lw=1.4,
                ls="-" if degree == 1 else "--", mfc=None if degree == 1 else "none")


def label(r):
    return "%s P%d" % (r["scheme"], r["degree"])


def ok(r):
    return r["status"] == "ok"


def curves(rows, key=lambda r: (r["scheme"], int(r["degree"]))):
    """{key: rows sorted by nx}, keys in scheme order."""
    out = {}
    for r in rows:
        out.setdefault(key(r), []).append(r)
    return {k: sorted(out[k], key=lambda r: (r.get("nx", 0), -r.get("h", 0)))
            for k in sorted(out, key=lambda k: (rank(k[0]),) + tuple(k[1:]))}


def h_ladder(bar, T, Theta=1.0):
    return [r for r in bar or [] if ok(r) and r["study"] == "h-ladder" and r["T"] == T and r["Theta"] == Theta]


def rate(hs, es):
    """Least-squares slope of log(error) against log(h)."""
    pts = [(math.log(h), math.log(e)) for h, e in zip(hs, es) if h > 0 and e > 0 and math.isfinite(e)]
    if len(pts) < 2:
        return math.nan
    return float(np.polyfit([p[0] for p in pts], [p[1] for p in pts], 1)[0])


def plot_xy(ax, rows, x, y, **kw):
    pts = [(x(r), r[y]) for r in rows if x(r) > 0 and r[y] > 0 and math.isfinite(r[y])]
    if pts:
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], **kw)


def h_ticks(ax, nxs):
    """Ticks of an h axis at the mesh sizes of the data, labelled 1/NX."""
    nxs = sorted(set(int(n) for n in nxs))
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.set_xticks([1 / n for n in nxs], ["1/%d" % n for n in nxs], rotation=45 if len(nxs) > 5 else 0, fontsize=8)


def save(fig, out, name, written):
    fig.savefig(os.path.join(out, name), dpi=110)
    plt.close(fig)
    written.append(name)


# ---------------------------------------------------------------- plots
def plot_bar(bar, out, written):
    for T in (3, 12):
        cs = curves(h_ladder(bar, T))
        for key, short in WP if cs else []:
            fig, ax = plt.subplots(figsize=(9, 4.8))
            fig.subplots_adjust(left=0.11, right=0.74, bottom=0.11, top=0.93)
            for (s, d), rows in cs.items():
                plot_xy(ax, rows, lambda r: r["loop_s"], key, label=label(rows[0]), **style(s, d))
            ax.set(xlabel="time loop (s)", ylabel="relative error", title="bar, %s, Θ = 1, T = %d" % (NAME[key], T))
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8)
            save(fig, out, "bar_wp_%s_T%d.png" % (short, T), written)
    th = curves([r for r in bar if ok(r) and r["study"] == "h-ladder" and r["T"] == 3
                 and r["scheme"] in ("hybrid", "newmark(0.25,0.5)")],
                key=lambda r: (r["scheme"], int(r["degree"]), r["Theta"]))
    if th:
        fig, axs = plt.subplots(2, 2, figsize=(11, 8), sharex=True)
        fig.subplots_adjust(left=0.09, right=0.98, bottom=0.07, top=0.95, wspace=0.24, hspace=0.15)
        for i, key in enumerate(("e_l2_stress", "e_l2_l2_u")):
            for j, scheme in enumerate(("hybrid", "newmark(0.25,0.5)")):
                ax = axs[i, j]
                for (s, d, Th), rows in th.items():
                    if s == scheme:
                        plot_xy(ax, rows, lambda r: r["loop_s"], key, color={1: "C0", 0: "C1", -1: "C2"}.get(Th, "C3"),
                                ls="-" if d == 1 else "--", marker="o" if d == 1 else "s",
                                mfc=None if d == 1 else "none", label="Θ = %g, P%d" % (Th, d))
                ax.set(title="%s: %s" % (scheme, NAME[key]), ylabel="relative error")
                ax.grid(True, which="both", alpha=0.3)
                ax.legend(fontsize=7)
        for ax in axs[1]:
            ax.set_xlabel("time loop (s), T = 3")
        save(fig, out, "bar_wp_theta_T3.png", written)
    cs = curves(h_ladder(bar, 3))
    if cs:
        fig, axs = plt.subplots(2, 4, figsize=(16, 8))
        fig.subplots_adjust(left=0.05, right=0.99, bottom=0.1, top=0.95, wspace=0.24, hspace=0.4)
        for ax, (key, name) in zip(axs.flat, NORMS):
            for (s, d), rows in cs.items():
                plot_xy(ax, rows, lambda r: 1 / r["nx"], key, label=label(rows[0]), **style(s, d))
            ax.set(title=name, xlabel="h")
            h_ticks(ax, [r["nx"] for rows in cs.values() for r in rows])
            ax.grid(True, which="both", alpha=0.3)
        axs.flat[7].axis("off")
        axs.flat[7].legend(*axs.flat[0].get_legend_handles_labels(), loc="center", fontsize=9,
                           title="bar, Θ = 1, T = 3")
        save(fig, out, "bar_conv_T3.png", written)
    tl = curves([r for r in bar if ok(r) and r["study"] == "tau-ladder"])
    if tl:
        fig, axs = plt.subplots(1, 2, figsize=(14, 4.8))
        fig.subplots_adjust(left=0.07, right=0.82, bottom=0.11, top=0.93, wspace=0.22)
        for ax, key in zip(axs, ("e_l2_l2_u", "e_l2_stress")):
            for (s, d), rows in tl.items():
                plot_xy(ax, rows, lambda r: r["tau"], key, label=label(rows[0]), **style(s, d))
            nxs = sorted({int(r["nx"]) for rows in tl.values() for r in rows})
            ax.set(xlabel="τ", ylabel="relative error",
                   title="%s, NX = %s, Θ = 1, T = 3" % (NAME[key], ", ".join(map(str, nxs))))
            ax.grid(True, which="both", alpha=0.3)
        axs[1].legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8)
        save(fig, out, "bar_tau_ladder.png", written)


ELABEL = {"hybrid": "hybrid", "newmark": "Newmark(1/4,1/2)", "theta_half": "θ-scheme, θ = 1/2"}


def plot_energy(energy, out, written):
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(12, 7.5), sharex=True)
    fig.subplots_adjust(left=0.09, right=0.98, bottom=0.07, top=0.95, hspace=0.08)
    tmax = max(max(e["t"]) for e in energy.values())
    for ax in (a1, a2):
        for k in range(int(tmax // 3) + 1):
            if 3 * k + 1 < tmax:
                ax.axvspan(3 * k + 1, min(3 * k + 2, tmax), color="0.85", lw=0)
    looks = {"hybrid": dict(color="C4", lw=2.2), "newmark": dict(color="C2", lw=1.2),
             "theta_half": dict(color="k", lw=0.8, ls=":")}
    for name, e in energy.items():
        E0 = e["E"][0]
        a1.plot(e["t"], (e["E_Theta"] - e["E_Theta"][0]) / E0, label=ELABEL.get(name, name), **looks.get(name, {}))
    for z, name in enumerate(sorted(energy, key=lambda n: -list(looks).index(n) if n in looks else 1)):
        a2.plot(energy[name]["t"], energy[name]["contact_stress"], label=ELABEL.get(name, name), zorder=2 + z,
                **dict(looks.get(name, {}), lw=0.7, ls="-"))
    t = np.linspace(0, tmax, 4001)
    a2.plot(t, np.where(np.floor(t % 3) == 1, -0.5, 0.0), color="r", lw=1.5, ls="--", label="exact", zorder=10)
    a1.set(ylabel="(E_Θ(t) − E_Θ(0)) / E(0)", title="bar, P1, Θ = 1: energy and contact stress "
           "(grey: exact contact phases)")
    a2.set(xlabel="t", ylabel="contact stress at x = 0")
    for ax in (a1, a2):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="lower left")
    save(fig, out, "bar_energy.png", written)


def plot_disk(disk, force, out, written):
    cs = curves([r for r in disk or [] if ok(r)])
    if cs:
        keys = ["e_l2_u_t14", "e_energy_u_t14", "e_force_l2"]
        if any(math.isfinite(r.get("e_force_l2_red", math.nan)) for rs in cs.values() for r in rs):
            keys.append("e_force_l2_red")
        fig, axs = plt.subplots(1, len(keys), figsize=(5.2 * len(keys) + 1.4, 4.8))
        fig.subplots_adjust(left=0.05, right=0.88, bottom=0.11, top=0.93, wspace=0.28)
        for ax, key in zip(axs, keys):
            for (s, d), rows in cs.items():
                plot_xy(ax, rows, lambda r: r["loop_s"], key, label=label(rows[0]), **style(s, d))
            ax.set(xlabel="time loop (s)", ylabel="error relative to the reference run", title=dict(DISK_ERR)[key])
            ax.grid(True, which="both", alpha=0.3)
        axs[-1].legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8)
        save(fig, out, "disk_wp.png", written)
    succ = disk_successive(disk)
    if any(len(v) >= 1 for v in succ.values()):
        fig, axs = plt.subplots(1, 2, figsize=(13, 4.8))
        fig.subplots_adjust(left=0.07, right=0.8, bottom=0.11, top=0.93, wspace=0.25)
        for (s, d), pts in succ.items():
            if pts:
                axs[0].loglog([p[0] for p in pts], [p[1] for p in pts], label="%s P%d" % (s, d), **style(s, d))
        axs[0].set(xlabel="h (the finer mesh of the pair)", ylabel="‖F_2h − F_h‖ / ‖F_h‖ in L²(0,T)",
                   title="disk: successive differences of the force history")
        for (s, d), rows in cs.items():
            plot_xy(axs[1], rows, lambda r: r["h"], "e_force_l2_red", label=label(rows[0]), **style(s, d))
        axs[1].set(xlabel="h", ylabel="relative error", title="force L²(0,T) vs the redistributed reference")
        for ax in axs:
            ax.grid(True, which="both", alpha=0.3)
        axs[1].legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8)
        save(fig, out, "disk_force_conv.png", written)
    if force:
        runs = {}
        for r in force:
            runs.setdefault(r["run"], ([], []))
            runs[r["run"]][0].append(r["t"])
            runs[r["run"]][1].append(r["force"])
        fig, ax = plt.subplots(figsize=(12, 5))
        fig.subplots_adjust(left=0.07, right=0.74, bottom=0.1, top=0.93)
        # labels look like "hybrid P2 h=1": one colour map per scheme, darker for later (finer) runs, P2 dashed
        maps = {"hybrid": plt.cm.Purples, "newmark(0.25,0.5)": plt.cm.Greens, "hybrid+redistributed": plt.cm.Oranges,
                "explicit+redistributed": plt.cm.Blues}
        family = {}
        for name in runs:
            family.setdefault(name.split(" ")[0], []).append(name)
        for i, (name, (t, f)) in enumerate(runs.items()):
            ref = "reference" in name
            fam = family[name.split(" ")[0]]
            cmap = maps.get(name.split(" ")[0], plt.cm.Oranges)
            ax.plot(t, f, label=name, color=("navy" if "redistributed" in name else "k") if ref else cmap(0.35 + 0.6 * fam.index(name) / max(len(fam) - 1, 1)),
                    lw=2.5 if ref else 1.0, ls="--" if " P2 " in name + " " and not ref else "-", zorder=3 if ref else 2)
        ax.set(xlabel="t", ylabel="contact force", title="disk: contact force histories")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=7)
        save(fig, out, "disk_force.png", written)


# ---------------------------------------------------------------- report sections
def sec_setup(bar, energy, disk, machine):
    md = ["## Setup\n"]
    if machine:
        md.append("Machine: %s. Date of the runs: %s (plan: %s). Runs went %s at a time; wall time of the runs: %s." % (
            machine.get("machine", "?"), machine.get("date", "?"), machine.get("plan", "?"), machine.get("jobs", "?"),
            machine.get("wall time of the runs", "?")))
    else:
        md.append("machine.txt is missing: machine, date and number of parallel runs unknown.")
    reps = sorted({int(r["repeats"]) for r in bar or [] if math.isfinite(r["repeats"])})
    md[-1] += (" Timings are medians of %s runs of each case; the loop time counts the `nd_step` calls only, "
              "the setup time is reported separately.\n" % ("/".join(map(str, reps)) or "`repeats`"))
    if bar:
        hl = [r for r in bar if r["study"] == "h-ladder"]
        g0 = sorted({r["gamma0"] for r in bar})
        t12 = [r["nx"] for r in hl if r["T"] == 12]
        md.append("**1D bar** (docs/design.md §7: exact solution of period 3, contact for t mod 3 in [1, 2], contact stress "
                  "−1/2). γ0 = %s (paper convention: γ0 has units of 1/stress), Θ ∈ {%s}. The *h-ladder* uses "
                  "NX = %s with τ tied to h (table); T = 12 runs exist up to NX = %s, larger NX run to T = 3 only. "
                  "Errors are relative, in the seven norms of docs/design.md §7: %s. Newton its are totals over the run; "
                  "the energy drift is max|E_Θ − E_Θ(0) − W| / E(0).\n" % (
                      ", ".join(map(g3, g0)), ", ".join(sorted({"%g" % r["Theta"] for r in bar}, key=float)),
                      ", ".join(str(int(n)) for n in sorted({r["nx"] for r in hl})),
                      int(max(t12)) if t12 else "– (none)", "; ".join(n for _, n in NORMS)))
        rows = []
        for s, d in curves(hl):
            rs = [r for r in hl if r["scheme"] == s and r["degree"] == d]
            rows.append([s, "P%d" % d, "yes" if rs[0]["lumped"] else "no",
                         ", ".join(sorted({g3(r["tau"] * r["nx"]) for r in rs})),
                         ", ".join(sorted({g3(r["tau"] * r["nx"] * d) for r in rs}))])
        md.append(table(["scheme", "degree", "lumped mass", "τ/h", "τ/dx (dx = h/degree)"], rows))
        tl = [r for r in bar if r["study"] == "tau-ladder"]
        if tl:
            md.append("\nThe *τ-ladder* keeps NX = %s, Θ = %s, T = %s and varies τ (τ/h from %s to %s).\n" % (
                ", ".join(str(int(n)) for n in sorted({r["nx"] for r in tl})),
                ", ".join(sorted({"%g" % r["Theta"] for r in tl})), ", ".join(sorted({"%g" % r["T"] for r in tl})),
                g3(min(r["tau"] * r["nx"] for r in tl)), g3(max(r["tau"] * r["nx"] for r in tl))))
    if energy:
        e = next(iter(energy.values()))
        dt = e["t"][1] - e["t"][0] if len(e["t"]) > 1 else math.nan
        md.append("\nThe **energy histories** are P1, NX = 80, Θ = 1, γ0 = 0.2 (as set by run.py), τ = %s, T = %s.\n"
                  % (g3(dt), g3(e["t"][-1])))
    if disk:
        md.append("\n**2D disk** (docs/design.md §7: radius 20, gap 5, λ = μ = 20, gravity 0.1, impact at t = 10). Errors are "
                  "relative to the finest run (status `reference`, the hybrid P2), not to an exact solution: displacement at "
                  "t = 12 and t = 14 in L² and in the energy norm, and the L²(0,T) error of the contact force; the "
                  "contact force also against the explicit redistributed P2 reference and, with no reference, as "
                  "successive differences between meshes. "
                  "h = %s, T = %s.\n" % (", ".join(g3(h) for h in sorted({r["h"] for r in disk}, reverse=True)),
                                         ", ".join(sorted({g3(r["T"]) for r in disk}))))
    return md


def rates_table(bar):
    md = ["## Observed convergence rates (bar, Θ = 1)\n",
          "Least-squares slope of log(error) against log(h) over the finest (at most) 4 successful points of each "
          "curve of the h-ladder; the fit range is given per row.\n"]
    rows = []
    for T in (3, 12):
        for (s, d), rs in curves(h_ladder(bar, T)).items():
            fit = rs[-4:]
            rows.append([s, "P%d" % d, T, "NX %d–%d" % (fit[0]["nx"], fit[-1]["nx"])] +
                        [frate(rate([1 / r["nx"] for r in fit], [r[k] for r in fit])) for k, _ in NORMS])
    md.append(table(["scheme", "P", "T", "fit range"] + [n for _, n in NORMS], rows) if rows else "No data.\n")
    return md


def wp_rows(rows, extra=()):
    out = []
    for r in rows:
        its = r["newton_its"] / r["steps"] if r["steps"] else math.nan
        out.append([r["scheme"], "P%d" % r["degree"]] + [f(r) for f in extra] +
                   [int(r["nx"]), g3(r["tau"]), int(r["steps"]), ftime(r["loop_s"]), g3(its),
                    g3(r["e_l2_l2_u"]), g3(r["e_l2_l2_v"]), g3(r["e_l2_stress"]), g3(r["energy_drift"])])
    return out


WP_HEAD = ["NX", "τ", "steps", "loop", "Newton its/step", "u L²L²", "v L²L²", "stress L²", "energy drift"]


def sec_wp(bar, data_rel):
    md = ["## Work–precision (bar, Θ = 1)\n"]
    for T in (3, 12):
        if h_ladder(bar, T):
            md.append("T = %d:\n\n" % T + "".join("![bar %s T=%d](bar_wp_%s_T%d.png)\n" % (s, T, s, T) for _, s in WP))
    rows = []
    for rs in curves(h_ladder(bar, 3)).values():
        rows += wp_rows(rs[-4:])
    md.append("The finest 4 runs of each curve (all runs: `%s/bar.csv`):\n" % data_rel)
    md.append(table(["scheme", "P"] + WP_HEAD, rows))
    md.append("\n### Θ = 1, 0, −1 (T = 3, finest NX)\n\n![Theta comparison](bar_wp_theta_T3.png)\n")
    rows = []
    for (s, d, Th), rs in curves([r for r in bar if ok(r) and r["study"] == "h-ladder" and r["T"] == 3 and
                                  r["scheme"] in ("hybrid", "newmark(0.25,0.5)")],
                                 key=lambda r: (r["scheme"], int(r["degree"]), -r["Theta"])).items():
        rows += wp_rows(rs[-1:], [lambda r: "%g" % r["Theta"]])
    md.append(table(["scheme", "P", "Θ"] + WP_HEAD, rows))
    md.append("\n## Convergence in h (Θ = 1, T = 3)\n\n![convergence](bar_conv_T3.png)\n")
    return md


def sec_cheapest(bar):
    md = ["## Cheapest choice for a target error\n",
          "Among all successful h-ladder runs (every scheme, degree and Θ) whose error is at most the target, the "
          "one with the smallest loop time. Loop times of the T = 3 rows of T = 12 runs count the steps up to t = 3.\n"]
    concl = []
    for T in (3, 12):
        runs = [r for r in bar if ok(r) and r["study"] == "h-ladder" and r["T"] == T]
        if not runs:
            continue
        nxmax = int(max(r["nx"] for r in runs))
        rows = []
        for key, name, targets in TARGETS:
            reached, missed = None, None
            for tgt in targets:
                good = [r for r in runs if r[key] <= tgt]
                if not good:
                    rows.append([name, g3(tgt), "not reached by any run up to NX = %d" % nxmax] + ["–"] * 6)
                    missed = tgt
                    break
                b = min(good, key=lambda r: (r["loop_s"], rank(r["scheme"]), r["degree"], r["nx"]))
                rows.append([name, g3(tgt), "%s P%d, Θ = %g, NX = %d" % (b["scheme"], b["degree"], b["Theta"], b["nx"]),
                             ftime(b["loop_s"]), g3(b[key]), g3(b["e_l2_l2_u"]), g3(b["e_l2_l2_v"]),
                             g3(b["e_l2_stress"]), g3(b["energy_drift"])])
                reached = (tgt, b)
            if T == 3:
                concl += conclusion(bar, runs, key, name, reached, missed, nxmax)
        md.append("\n### T = %d\n\n" % T)
        md.append(table(["measure", "target", "cheapest run", "loop", "its error", "u L²L²", "v L²L²", "stress L²",
                         "energy drift"], rows))
    md.append("\n**Conclusion** (T = 3; T = 12 in the second table). " +
              (" ".join(concl) or "No successful h-ladder run at T = 3.") + "\n")
    return md


def conclusion(bar, runs, key, name, reached, missed, nxmax):
    """Sentences on the smallest target reached and the first one missed."""
    out = []
    if reached:
        tgt, b = reached
        out.append("For a %s error of %s (T = 3) the cheapest run is %s P%d, Θ = %g, NX = %d (%s; its energy drift is "
                   "%s)." % (name, g3(tgt), b["scheme"], b["degree"], b["Theta"], b["nx"], ftime(b["loop_s"]),
                             g3(b["energy_drift"])))
    if missed:
        best = min((r for r in runs if math.isfinite(r[key])), key=lambda r: r[key])
        rs = sorted((rate([1 / r["nx"] for r in c[-4:]], [r[key] for r in c[-4:]]), "%s P%d" % k)
                    for k, c in curves(h_ladder(bar, 3)).items())
        rs = [x for x in rs if math.isfinite(x[0])]
        out.append("No run reaches a %s error of %s up to NX = %d: the smallest is %s (%s P%d, Θ = %g, NX = %d)%s." % (
            name, g3(missed), nxmax, g3(best[key]), best["scheme"], best["degree"], best["Theta"], best["nx"],
            "; at Θ = 1 its observed rate in h (finest 4 NX) ranges from %.2f (%s) to %.2f (%s)" % (
                rs[0] + rs[-1]) if rs else ""))
    return out


def sec_tau(bar):
    md = ["## Time-step ladder (Θ = 1, T = 3)\n"]
    tl = curves([r for r in bar if ok(r) and r["study"] == "tau-ladder"])
    if not tl:
        return md + ["The τ-ladder was not run (or all its runs failed).\n"]
    md.append("![tau ladder](bar_tau_ladder.png)\n")
    rows, srows, notes, sl_u = [], [], [], {}
    for (s, d), rs in tl.items():
        rs = sorted(rs, key=lambda r: r["tau"])
        rows += wp_rows(rs, [lambda r: g3(r["tau"] * r["nx"])])
        sl = [rate([r["tau"] for r in rs], [r[k] for r in rs]) for k in ("e_l2_l2_u", "e_l2_l2_v", "e_l2_stress")]
        srows.append([s, "P%d" % d, "%s–%s" % (g3(rs[0]["tau"]), g3(rs[-1]["tau"]))] + [frate(x) for x in sl])
        if math.isfinite(sl[0]):
            sl_u["%s P%d" % (s, d)] = sl[0]
        for x, n in zip(sl, ("u L²L²", "v L²L²", "stress")):
            if x < -0.3:
                notes.append("%s P%d: the %s error grows as τ decreases (slope %.2f)" % (s, d, n, x))
    md.append(table(["scheme", "P", "τ/h"] + WP_HEAD, rows))
    md.append("\nSlopes of log(error) against log(τ) over the whole ladder:\n\n")
    md.append(table(["scheme", "P", "τ range", "u L²L²", "v L²L²", "stress L²"], srows))
    if not sl_u:
        return md + ["\n"]
    flat = [k for k, v in sl_u.items() if abs(v) < 0.3]
    steep = [k for k, v in sl_u.items() if v >= 0.8]
    lo, hi = min(sl_u, key=sl_u.get), max(sl_u, key=sl_u.get)
    md.append("\nThe slopes of the u L²L² error in τ range from %.2f (%s) to %.2f (%s). It falls with τ at a slope ≥ 0.8 "
              "for %s, and hardly changes (|slope| < 0.3) for %s." % (
                  sl_u[lo], lo, sl_u[hi], hi, ", ".join(steep) or "no scheme",
                  ", ".join(flat) or "no scheme"))
    if notes:
        md[-1] += " " + "; ".join(notes) + "."
    return md + ["\n"]


def sec_energy(bar, energy):
    md = ["## Energy\n"]
    t12 = [r for r in bar or [] if ok(r) and r["study"] == "h-ladder" and r["T"] == 12 and r["Theta"] == 1]
    if t12:
        rows = [rs[-1] for rs in curves(t12).values()]
        md.append("Maximum energy drift max|E_Θ − E_Θ(0) − W|/E(0) over T = 12, Θ = 1, finest NX:\n\n")
        md.append(table(["scheme", "P", "NX", "energy drift"],
                        [[r["scheme"], "P%d" % r["degree"], int(r["nx"]), g3(r["energy_drift"])] for r in rows]))
        fin = [r for r in rows if math.isfinite(r["energy_drift"])] or rows
        lo, hi = min(fin, key=lambda r: r["energy_drift"]), max(fin, key=lambda r: r["energy_drift"])
        md.append("\nThe smallest drift is %s (%s), the largest %s (%s).\n" % (
            g3(lo["energy_drift"]), label(lo), g3(hi["energy_drift"]), label(hi)))
    if not energy:
        return md + ["The energy histories were not run.\n"]
    md.append("\n![energy](bar_energy.png)\n\n")
    rows, sent = [], []
    for name, e in energy.items():
        E0 = e["E"][0]
        d = np.diff(e["E_Theta"]) / E0
        i = int(np.argmax(d))
        rows.append([name, g3(np.max(np.abs(e["E_Theta"] - e["E_Theta"][0])) / E0), g3(max(d.max(), 0)),
                     g3(e["t"][i + 1]) if d.max() > 0 else "–", g3(np.max(np.abs(e["E"] - E0)) / E0)])
        sent.append("%s: E_Θ %s" % (name, "never increases by more than 1e-9 E(0) between time levels" if d.max() <
                                    1e-9 else "increases by up to %s E(0) in one step (at t = %s, t mod 3 = %s)" % (
                                        g3(d.max()), g3(e["t"][i + 1]), g3(e["t"][i + 1] % 3))))
    md.append(table(["history", "max \\|E_Θ − E_Θ(0)\\|/E(0)", "largest one-step increase of E_Θ / E(0)", "at t",
                     "max \\|E − E(0)\\|/E(0)"], rows))
    md.append("\n" + "; ".join(sent) + ".")
    md[-1] = md[-1].replace("theta_half", "θ = 1/2")
    if "newmark" in energy and "theta_half" in energy and len(energy["newmark"]["t"]) == len(energy["theta_half"]["t"]):
        diff = max(np.max(np.abs(energy["newmark"][k] - energy["theta_half"][k])) for k in ("E_Theta", "contact_stress"))
        md[-1] += (" The Newmark and θ = 1/2 histories differ by at most %s (E_Θ and contact stress)." % g3(diff))
    return md + ["\n"]


def sec_getfem(bar, getfem, pairs):
    md = ["## Side by side with GetFEM\n"]
    if getfem is None:
        return md + ["GetFEM was not run (no getfem.csv).\n"]
    # our runs of the same cases made right after GetFEM's in the same run
    # (getfem_pair.csv); the h-ladder rows when those are missing
    source = pairs if pairs else [r for r in h_ladder(bar, 3) if r["scheme"] == "newmark(0.25,0.5)"]
    mine = {(int(r["degree"]), int(r["nx"])): r for r in source if ok(r) and r["Theta"] == 1}
    rows, worst_all = [], 0.0
    for g in sorted((g for g in getfem if ok(g)), key=lambda g: (g["degree"], g["nx"])):
        n = mine.get((int(g["degree"]), int(g["nx"])))
        if n is None:
            continue
        rel = [(abs(n[k] - g[k]) / max(abs(n[k]), abs(g[k])) if max(abs(n[k]), abs(g[k])) > 0 else 0.0, nm)
               for k, nm in NORMS]
        worst = max(rel)
        worst_all = max(worst_all, worst[0])
        its = lambda r: g3(r["newton_its"] / r["steps"]) if r.get("newton_its") is not None else "–"
        rows.append(["P%d" % g["degree"], int(g["nx"]), g3(n["e_l2_l2_u"]), g3(g["e_l2_l2_u"]), g3(n["e_l2_l2_v"]),
                     g3(g["e_l2_l2_v"]), g3(n["e_l2_stress"]), g3(g["e_l2_stress"]), its(n), its(g),
                     ftime(n["loop_s"]), ftime(g["loop_s"]), g3(g["loop_s"] / n["loop_s"]), ftime(n["setup_s"]),
                     ftime(g["setup_s"]), "%s (%s)" % (g3(worst[0]), worst[1])])
    md.append("The same bar, the same discretisation: Newmark (1/4, 1/2), consistent mass, Θ = 1, γ0 = 0.2 in the paper's "
              "convention (passed to GetFEM as its inverse, 1/γ0, since GetFEM's Nitsche brick takes γ0/h), τ = h/2, "
              "T = 3, both codes' errors measured by the same C code (`examples/bar1d_exact.c`, loaded by "
              "`tools/report/getfem_bar.py` through ctypes). nitschedyn (nd) rows: %s. Loop = the time steps only, "
              "median of the repeated runs. The last column is the largest relative difference of the seven errors, "
              "|nd − gf| / max(nd, gf).\n\n" % ("runs of the same cases made right after GetFEM's in the same "
                                                 "`run.py` call (data/getfem_pair.csv)" if pairs else
                                                 "the h-ladder"))
    md.append(table(["P", "NX", "u L²L² nd", "u L²L² gf", "v L²L² nd", "v L²L² gf", "stress nd", "stress gf",
                     "Newton/step nd", "Newton/step gf", "loop nd", "loop gf", "gf/nd loop", "setup nd", "setup gf",
                     "max rel. diff"], rows) if rows else "No GetFEM run has a matching nitschedyn run.\n")
    if rows:
        ratios = [float(r[12]) for r in rows]
        if worst_all < 1e-6:
            md.append("\nThe errors agree to %s relative at worst: the two codes solve the same discrete problem, "
                      "and what differs is where each Newton method stops — nitschedyn when ‖G‖ ≤ 1e-10 (‖r‖ + ‖cMU‖) "
                      "and the active set did not change in the last iteration (or the update is at round-off), "
                      "GetFEM (as driven here) when the ℓ¹ norm of its residual is below 1e-12 (‖r‖₁ + ‖cMUⁿ‖₁), on "
                      "the residual alone, hence its slightly lower iteration count. GetFEM's loop is %s–%s times "
                      "slower: every Newton iteration re-assembles the residual and the tangent through its generic "
                      "weak-form assembly and factorizes anew (MUMPS), whereas nitschedyn factorizes c M + K_Θ once "
                      "and, while no contact point is active, a step is one solve with that factor.\n"
                      % (g3(worst_all), g3(min(ratios)), g3(max(ratios))))
        else:
            md.append("\n**The errors differ by up to %s relative, beyond the Newton tolerances: the two runs do "
                      "not solve the same discrete problem.** See the rows above.\n" % g3(worst_all))
    return md


def disk_successive(disk):
    """{(scheme, degree): [(h, ||F_2h - F_h|| / ||F_h||)] by decreasing h}, the runs and the redistributed
    reference (d_force_coarser: against the same curve's run on the mesh twice as coarse)."""
    out = {}
    for r in disk or []:
        if r["status"] in ("ok", "reference"):
            d = r.get("d_force_coarser", math.nan)
            if math.isfinite(d):
                out.setdefault((r["scheme"], int(r["degree"])), []).append((r["h"], d))
    return {k: sorted(out[k], key=lambda p: -p[0]) for k in sorted(out, key=lambda k: (rank(k[0]), k[1]))}


def last_pair(pts):
    """The rate of the last halving when there are more than two differences."""
    if len(pts) < 3:
        return ""
    return " (last halving %s)" % frate(math.log2(pts[-2][1] / pts[-1][1]))


CONVERGE_RATE = 0.25  # successive differences falling at least like h^0.25 at every halving: "converging"


def verdict(pts):
    """(word, rate) for successive differences [(h, d)]: converge / do not converge, least-squares rate."""
    if len(pts) < 2:
        return "undecided (one difference only)", math.nan
    ratios = [a[1] / b[1] for a, b in zip(pts, pts[1:])]
    r = rate([p[0] for p in pts], [p[1] for p in pts])
    if all(q >= 2 ** CONVERGE_RATE for q in ratios):
        return "converge", r
    if all(q > 1 for q in ratios):
        return "decrease too slowly to show convergence", r
    return "do not converge", r


def sec_disk_convergence(disk):
    md = []
    succ = disk_successive(disk)
    if not succ:
        return md
    hs = sorted({p[0] for v in succ.values() for p in v}, reverse=True)
    rows = []
    for (s, d), pts in succ.items():
        by_h = dict(pts)
        ratios = ["%.2f" % (a[1] / b[1]) for a, b in zip(pts, pts[1:])]
        rows.append([s, "P%d" % d] + [g3(by_h.get(h, math.nan)) for h in hs] +
                    [", ".join(ratios) or "–", frate(rate([p[0] for p in pts], [p[1] for p in pts]))])
    md.append("\n**Convergence of the contact-force history without a reference.** The successive differences "
              "‖F_2h − F_h‖ / ‖F_h‖ in L²(0,T) of each curve (F_h the run on mesh h; histories on different time "
              "grids compared at the coarser step's times, the finer one interpolated linearly in time), their "
              "ratios (coarser pair over finer pair; 2^p for a rate p) and the observed rate (slope of "
              "log(difference) against log(h), h the finer mesh of each pair). The explicit redistributed P2 "
              "includes its reference run (one mesh finer) as the last pair. \n\n")
    md.append(table(["scheme", "P"] + ["%s→%s" % (g3(2 * h), g3(h)) for h in hs] + ["ratios", "rate"], rows))
    red = {k: v for k, v in succ.items() if "redistributed" in k[0]}
    if red:
        verdicts = {k: verdict(v) for k, v in red.items()}
        words = {w for w, _ in verdicts.values()}
        refs = [r for r in disk if r["status"] == "reference" and "redistributed" in r["scheme"]]
        err = curves([r for r in disk if ok(r) and "redistributed" in r["scheme"]
                      and math.isfinite(r.get("e_force_l2_red", math.nan))])
        heads = {"converge": "The redistributed contact-force histories converge under refinement",
                 "do not converge": "The redistributed contact-force histories do not converge under refinement"}
        w = words.pop() if len(words) == 1 else None
        head = "**%s**" % (heads.get(w) or (
            "The redistributed contact-force histories decrease under refinement, but too slowly to show convergence"
            if w and w.startswith("decrease") else
            "Whether the redistributed contact-force histories converge under refinement is not decided by this "
            "plan (one successive difference per curve)" if w else
            "The redistributed contact-force histories do not all converge under refinement"))
        md.append("\n%s (criterion: every successive difference at most 2^−%g of the one before, i.e. an observed "
                  "rate of at least %g at each halving of h): %s." % (
                      head, CONVERGE_RATE, CONVERGE_RATE,
                      "; ".join("%s P%d: %s, differences %s (h = %s), rate %s" % (
                          s, d, w, ", ".join(g3(p[1]) for p in red[(s, d)]),
                          ", ".join(g3(p[0]) for p in red[(s, d)]), frate(r) + last_pair(red[(s, d)]))
                          for (s, d), (w, r) in verdicts.items())))
        md[-1] += (" These rest on %s meshes per curve (h = %s), so the rates are observed, not asymptotic." % (
            "/".join(sorted({str(len(v) + 1) for v in red.values()})), ", ".join(g3(h) for h in [2 * hs[0]] + hs)))
        plain = {k: verdict(v) for k, v in succ.items() if "redistributed" not in k[0]}
        if plain:
            md[-1] += " Without redistribution (the force at tⁿ): %s." % "; ".join(
                "%s P%d %s (rate %s)" % (s, d, w, frate(r)) for (s, d), (w, r) in plain.items())
        if refs and err:
            ref = refs[0]
            md[-1] += (" Against the redistributed reference (%s P%d, h = %s, τ = %s) the force errors are %s." % (
                ref["scheme"], ref["degree"], g3(ref["h"]), g3(ref["tau"]),
                "; ".join("%s P%d %s (h = %s, rate %s)" % (
                    s, d, ", ".join(g3(r["e_force_l2_red"]) for r in rs), ", ".join(g3(r["h"]) for r in rs),
                    frate(rate([r["h"] for r in rs], [r["e_force_l2_red"] for r in rs])))
                    for (s, d), rs in err.items())))
        md[-1] += "\n"
    return md


def sec_disk(disk, force, machine=None):
    md = ["## 2D disk\n"]
    if disk is None:
        return md + ["The disk study was not run (no disk.csv).\n"]
    rerun = [v for k, v in (machine or {}).items() if k.startswith("disk study re-run")]
    if rerun:
        md.append("This part was re-run alone (run.py --only disk): %s.\n" % rerun[-1])
    md.append(("![disk work-precision](disk_wp.png)\n\n" if any(ok(r) for r in disk) else "") +
              ("![disk force](disk_force.png)\n\n" if force else "No force histories (disk_force.csv missing).\n\n") +
              ("![disk force convergence](disk_force_conv.png)\n\n" if disk_successive(disk) else ""))
    rows = []
    for rs in curves([r for r in disk if r["status"] in ("ok", "reference")]).values():
        for r in rs:
            rows.append([r["code"], r["scheme"], "P%d" % r["degree"], g3(r["h"]), int(r["unknowns"]), g3(r["tau"]),
                         int(r["steps"]), ftime(r["setup_s"]), ftime(r["loop_s"]),
                         g3(r["newton_its"] / r["steps"] if r["steps"] else math.nan)] +
                        [g3(r.get(k)) for k, _ in DISK_ERR] + [g3(r.get("d_force_coarser")), r["status"]])
    md.append(table(["code", "scheme", "P", "h", "unknowns", "τ", "steps", "setup", "loop", "Newton its/step"] +
                    [n for _, n in DISK_ERR] + ["‖F_2h − F_h‖/‖F_h‖", "status"], rows))
    rows = []
    for (s, d), rs in curves([r for r in disk if ok(r)]).items():
        if len(rs) >= 2:
            rows.append([s, "P%d" % d, "h %s–%s" % (g3(rs[0]["h"]), g3(rs[-1]["h"]))] +
                        [frate(rate([r["h"] for r in rs], [r.get(k, math.nan) for r in rs])) for k, _ in DISK_ERR])
    md.append("\nRates: slope of log(error) against log(h) over all non-reference runs of each curve:\n\n")
    md.append(table(["scheme", "P", "fit range"] + [n for _, n in DISK_ERR], rows) if rows else
              "Fewer than 2 non-reference runs per curve: no rates.\n")
    red = curves([r for r in disk if ok(r) and r["scheme"] == "hybrid+redistributed"])
    if red:
        md.append("\nThe `hybrid+redistributed` runs (issue 16) use mass redistribution and record the force the "
                  "step applied (ND_CONTACT_FORCE_APPLIED); their errors are against the same reference (without "
                  "redistribution, the force at tⁿ), so they include the difference of the two mass matrices (the column "
                  "*force L²(0,T) vs redistributed ref* and the successive differences below do not). Their "
                  "force errors against the hybrid reference under refinement: %s; without redistribution (hybrid): %s.\n" % (
                      "; ".join("P%d %s" % (d, ", ".join(g3(r["e_force_l2"]) for r in rs)) for (s, d), rs in red.items()),
                      "; ".join("P%d %s" % (d, ", ".join(g3(r["e_force_l2"]) for r in rs))
                                for (s, d), rs in curves([r for r in disk if ok(r) and r["scheme"] == "hybrid"]).items())))
    ex = [r for r in disk if r["scheme"] == "explicit+redistributed" and r["status"] in ("ok", "reference")]
    if ex:
        md.append("\nThe `explicit+redistributed` runs (issue 16) are the central difference (Newmark β = 0, γ = ½, "
                  "lumped mass) with mass redistribution, the massless contact DOFs solved from their static "
                  "equilibrium each step, and the force the step applied (ND_CONTACT_FORCE_APPLIED; for this scheme "
                  "the force at tⁿ); τ = 2/⌈2/(0.9 τ_c)⌉ with τ_c from `nd_problem_estimate_critical_timestep` "
                  "(with the redistributed lumped mass; the snapshot times 12, 14 and T are multiples of τ; the setup time "
                  "includes the estimate): %s. "
                  "The column *force L²(0,T) vs redistributed ref* compares every run's force with the "
                  "explicit redistributed P2 reference (status `reference`), a model with the same (redistributed) "
                  "mass up to the lumping; the other error columns are against the hybrid reference.\n" % "; ".join(
                      "P%d h = %s: τ_c = %s, τ = %s" % (r["degree"], g3(r["h"]), g3(r.get("tau_c")), g3(r["tau"]))
                      for r in sorted(ex, key=lambda r: (r["degree"], -r["h"]))))
    md += sec_disk_convergence(disk)
    return md


QUAD_ERR = DISK_ERR[:5]  # (no redistributed reference on quadrilaterals)


def sec_disk_quad(quad, disk):
    """The disk in quadrilaterals (Q1, Q2, hybrid) against its own finest run, its rates beside the
    triangles' (hybrid P1, P2 of disk.csv), and the triangles' reference against the quadrilaterals'."""
    md = ["## 2D disk in quadrilaterals\n"]
    if quad is None:
        return md + ["The quadrilateral disk study was not run (no disk_quad.csv).\n"]
    md.append("The same disk and scene meshed in quadrilaterals (`examples/meshes/disk_quad.geo`, a transfinite "
              "O-grid; h the size of the cells on the circle), Q1 and Q2, the hybrid scheme, τ = h/40, against its own "
              "reference (Q2 on the finest quadrilateral mesh, half its step), errors measured as in the triangles' "
              "study (`disk_study --cells quadrilateral`).\n\n")
    rows = []
    for r in sorted(quad, key=lambda r: (r["status"] == "simplex-reference", r["degree"], -r["h"])):
        rows.append([r["scheme"], ("P%d" if r["status"] == "simplex-reference" else "Q%d") % r["degree"], g3(r["h"]),
                     int(r["unknowns"]), g3(r["tau"]), int(r["steps"]), ftime(r["setup_s"]), ftime(r["loop_s"])] +
                    [g3(r.get(k)) for k, _ in QUAD_ERR] + [g3(r.get("d_force_coarser")), r["status"]])
    md.append(table(["scheme", "cells", "h", "unknowns", "τ", "steps", "setup", "loop"] + [n for _, n in QUAD_ERR] +
                    ["‖F_2h − F_h‖/‖F_h‖", "status"], rows))
    rows = []
    for cells, rs_all in (("quadrilaterals", quad), ("triangles", disk or [])):
        for (s, d), rs in curves([r for r in rs_all if ok(r) and r["scheme"] == "hybrid"]).items():
            if len(rs) >= 2:
                rows.append([cells, ("Q%d" if cells == "quadrilaterals" else "P%d") % d,
                             "h %s–%s" % (g3(rs[0]["h"]), g3(rs[-1]["h"]))] +
                            [frate(rate([r["h"] for r in rs], [r.get(k, math.nan) for r in rs])) for k, _ in QUAD_ERR])
    md.append("\nRates (hybrid), slope of log(error) against log(h), each family against its own reference:\n\n")
    md.append(table(["cells", "element", "fit range"] + [n for _, n in QUAD_ERR], rows))
    cross = [r for r in quad if r["status"] == "simplex-reference"]
    if cross:
        r = cross[0]
        md.append("\nThe triangles' reference (P2, h = %s, τ = %s) against the quadrilaterals' (row "
                  "`simplex-reference`): u L² %s and %s at t = 12 and 14, energy %s and %s, force %s: of the size "
                  "of the Q2 and P2 errors at the finest h, as it must be if both families converge to one solution.\n" % (
                      g3(r["h"]), g3(r["tau"]), g3(r["e_l2_u_t12"]), g3(r["e_l2_u_t14"]), g3(r["e_energy_u_t12"]),
                      g3(r["e_energy_u_t14"]), g3(r["e_force_l2"])))
    return md


def sec_ball(ball):
    """The ball in tetrahedra and hexahedra (hybrid) against one reference, P2 tetrahedra: the families' rates
    side by side, and the reference-free successive differences."""
    md = ["## 3D ball in tetrahedra and hexahedra\n"]
    if ball is None:
        return md + ["The ball study was not run (no ball.csv).\n"]
    ref = [r for r in ball if r["status"] == "reference"]
    md.append("The disk's scene in 3D (`examples/meshes/ball.geo` in tetrahedra, `ball_hex.geo` in hexahedra, a "
              "transfinite O-grid; h the size of the cells on the sphere), the hybrid scheme, τ = h/40, both families "
              "against one reference: P2 tetrahedra at h = %s with half its step (`disk_study --body ball`). A finer "
              "3D reference does not fit the machine (P2 tetrahedra at h = 1 have about 660,000 unknowns, Q2 "
              "hexahedra at h = 2 need tens of GB), so the finest rows' errors hold the reference's own; the column "
              "‖u_2h − u_h‖ needs no reference: the L² difference at t = 14 to the same element's run one mesh coarser, "
              "relative to the finer run.\n\n" % (g3(ref[0]["h"]) if ref else "–"))
    key = lambda r: (r["status"] != "reference", r.get("cells") != "tetrahedron", r["degree"], -r["h"])
    rows = []
    for r in sorted(ball, key=key):
        elem = ("Q%d" if r.get("cells") == "hexahedron" else "P%d") % r["degree"]
        rows.append([r.get("cells", ""), elem, g3(r["h"]), int(r["unknowns"]), g3(r["tau"]), int(r["steps"]),
                     ftime(r["setup_s"]), ftime(r["loop_s"])] + [g3(r.get(k)) for k, _ in QUAD_ERR] +
                    [g3(r.get("d_force_coarser")), g3(r.get("d_l2_u_t14_coarser")), r["status"]])
    md.append(table(["cells", "element", "h", "unknowns", "τ", "steps", "setup", "loop"] + [n for _, n in QUAD_ERR] +
                    ["‖F_2h − F_h‖/‖F_h‖", "‖u_2h − u_h‖ L² t=14", "status"], rows))
    rows = []
    for cells in ("tetrahedron", "hexahedron"):
        for (s, d), rs in curves([r for r in ball if ok(r) and r.get("cells") == cells]).items():
            fit = [r for r in rs if r["h"] >= 2]  # the range both families have
            if len(fit) >= 2:
                rows.append([cells, ("Q%d" if cells == "hexahedron" else "P%d") % d,
                             "h %s–%s" % (g3(fit[0]["h"]), g3(fit[-1]["h"]))] +
                            [frate(rate([r["h"] for r in fit], [r.get(k, math.nan) for r in fit])) for k, _ in QUAD_ERR])
            diffs = [r for r in rs if math.isfinite(r.get("d_l2_u_t14_coarser") or math.nan)]
            if len(diffs) >= 2:
                rows.append([cells, ("Q%d" if cells == "hexahedron" else "P%d") % d,
                             "‖u_2h − u_h‖, h %s–%s" % (g3(diffs[0]["h"]), g3(diffs[-1]["h"])), "", "",
                             frate(rate([r["h"] for r in diffs], [r["d_l2_u_t14_coarser"] for r in diffs])), "", ""])
    md.append("\nRates (hybrid), slope of log(error) against log(h) over h = 4 and 2 (the ladder both families have), "
              "against the common reference; a row ‖u_2h − u_h‖ is the rate of the successive differences (no "
              "reference):\n\n")
    md.append(table(["cells", "element", "fit range"] + [n for _, n in QUAD_ERR], rows))
    return md


def sec_failed(parts):
    rows = []
    for name, rs in parts:
        for r in rs or []:
            if r["status"] not in ("ok", "reference"):
                rows.append([name, r.get("scheme", ""), "P%d" % r["degree"] if "degree" in r else "",
                             "%g" % r["Theta"] if "Theta" in r else "", g3(r["nx"]) if "nx" in r else "h = " + g3(r["h"]),
                             g3(r["tau"]), g3(r["T"]), " ".join(r["status"].replace("|", "/").split()) or "(empty)"])
    md = ["## Failed runs\n"]
    md += [table(["file", "scheme", "P", "Θ", "NX", "τ", "T", "status"], rows) if rows
           else "None: every row has status ok.\n" if any(rs for _, rs in parts) else "No runs recorded.\n"]
    # completed runs whose energy left its bounds: unstable, though no step failed
    wild = {}
    for name, rs in parts:
        for r in rs or []:
            if r["status"] == "ok" and (r.get("energy_drift") or 0) > 1:
                key = (r["scheme"], r["degree"], r["Theta"])
                wild.setdefault(key, []).append(r)
    if wild:
        md.append("\n### Completed but unstable\n\nRuns with no failed step whose energy drift "
                  "max|E_Θ − E_Θ(0) − W|/E(0) exceeds 1 (the energy grew past twice its initial value): the "
                  "library does not detect this.\n\n")
        md.append(table(["scheme", "P", "Θ", "NX", "τ/h range", "energy drift", "u L²L²", "v L²L²"],
                        [[k[0], "P%d" % k[1], "%g" % k[2],
                          "%d–%d" % (min(r["nx"] for r in v), max(r["nx"] for r in v)),
                          "%s–%s" % (g3(min(r["tau"] * r["nx"] for r in v)), g3(max(r["tau"] * r["nx"] for r in v))),
                          "%s–%s" % (g3(min(r["energy_drift"] for r in v)), g3(max(r["energy_drift"] for r in v))),
                          "%s–%s" % (g3(min(r["e_l2_l2_u"] for r in v)), g3(max(r["e_l2_l2_u"] for r in v))),
                          "%s–%s" % (g3(min(r["e_l2_l2_v"] for r in v)), g3(max(r["e_l2_l2_v"] for r in v)))]
                         for k, v in sorted(wild.items())]))
    return md


DESCR = {"bar.csv": "bar runs: h-ladder and τ-ladder, one row per run (and per --at summary)",
         "getfem.csv": "the same bar runs with GetFEM", "energy_hybrid.csv": "energy history, hybrid scheme",
         "energy_newmark.csv": "energy history, Newmark(1/4,1/2)", "energy_theta_half.csv": "energy history, θ = 1/2",
         "disk.csv": "2D disk runs and their errors against the reference run",
         "disk_force.csv": "contact force history of every disk run",
         "disk_quad.csv": "the disk in quadrilaterals (Q1, Q2): runs and errors against its Q2 reference",
         "disk_quad_force.csv": "contact force history of every quadrilateral disk run",
         "ball.csv": "the 3D ball in tetrahedra (P1, P2) and hexahedra (Q1, Q2): runs and errors against its P2 reference",
         "ball_force.csv": "contact force history of every ball run",
         "runs_ball.log": "the same for a re-run of the ball study alone (run.py --only ball)", "machine.txt": "machine, date, plan, jobs",
         "runs.log": "command line, exit code and stderr of every run",
         "runs_pressure.log": "the same for a re-run of the pressure study alone (run.py --only pressure)",
         "runs_disk.log": "the same for a re-run of the disk study alone (run.py --only disk)",
         "disk_force_conv.png": "disk force: successive differences and error vs the redistributed reference, vs h",
         "getfem_pair.csv": "nitschedyn runs of the GetFEM cases, made right after them",
         "bar_wp_theta_T3.png": "stress and u L²L² error vs loop time, hybrid and Newmark(1/4,1/2), Θ = 1, 0, −1",
         "bar_conv_T3.png": "the seven errors vs h, Θ = 1, T = 3", "bar_tau_ladder.png": "u L²L² and stress error vs τ",
         "bar_energy.png": "E_Θ − E_Θ(0) and contact stress vs t", "disk_wp.png": "disk errors vs loop time",
         "disk_force.png": "disk contact force histories",
         "bar_pressure_conv.png": "contact-stress error vs h with and without each remedy",
         "bar_pressure_wp.png": "contact-stress error vs loop time with and without each remedy"}
DESCR.update({"bar_wp_%s_T%d.png" % (s, T): "%s error vs loop time, h-ladder, Θ = 1, T = %d" % (NAME[k], T)
              for T in (3, 12) for k, s in WP})


def sec_files(data_dir, data_rel, written):
    md = ["## Files\n"]
    if not os.listdir(data_dir) and not written:
        md.append("None.")
    for f in sorted(os.listdir(data_dir)):
        md.append("- `%s/%s`: %s" % (data_rel, f, DESCR.get(f, "")))
    for f in written:
        md.append("- `%s`: %s" % (f, DESCR.get(f, "")))
    return md + [""]


# ---------------------------------------------------------------- pressure (issue 16)
REMEDIES = [(0, "end", "λ at tⁿ"), (0, "applied", "applied"), (1, "end", "redistributed, λ at tⁿ"),
            (1, "applied", "redistributed, applied")]
PRESSURE_TARGET = (0.05, 320, 0.5)  # error at NX = 320, observed rate


def pressure_rows(bar):
    return [r for r in bar or [] if ok(r) and r["study"] == "pressure"]


def pressure_curves(bar):
    """{(scheme, degree, redistributed, pressure, tau/h): rows}: the explicit scheme runs at several tau/h."""
    return curves(pressure_rows(bar), key=lambda r: (r["scheme"], int(r["degree"]), int(r["redistributed"]),
                                                       r["pressure"], round(r["tau"] * r["nx"], 6)))


def ftau(tau_h):
    """tau/h as "h", "h/2", "h/8", "0.9h"."""
    if tau_h == 1:
        return "h"
    inv = 1 / tau_h
    return "h/%d" % round(inv) if tau_h < 1 and abs(inv - round(inv)) < 1e-9 else "%gh" % tau_h


def is_explicit(scheme):
    return scheme.startswith("newmark(0,")


def plot_pressure(bar, out, written):
    cs = pressure_curves(bar)
    if not cs:
        return
    for name, x, xlabel in (("bar_pressure_conv.png", lambda r: 1 / r["nx"], "h"),
                            ("bar_pressure_wp.png", lambda r: r["loop_s"], "loop time [s]")):
        fig, axs = plt.subplots(1, 4, figsize=(18, 4.6), sharey=True)
        for ax, (red, pr, title) in zip(axs, REMEDIES):
            for (s, d, rr, pp, th), rows in cs.items():
                if rr == red and pp == pr:
                    st = style(s, d)
                    if is_explicit(s) and th == 1:  # CFL 1: its own line
                        st.update(ls=":", lw=2.2)
                    plot_xy(ax, rows, x, "e_l2_stress",
                            label="%s P%d%s" % (s, d, " τ=%s" % ftau(th) if is_explicit(s) else ""), **st)
            ax.set(xlabel=xlabel, title=title)
            ax.grid(True, which="both", alpha=0.3)
        axs[0].set_ylabel(NAME["e_l2_stress"])
        axs[-1].legend(fontsize=6, ncol=2)
        fig.tight_layout()
        save(fig, out, name, written)


def describe(key):
    s, d, red, pr, th = key
    return "%s P%d%s, mass %s, %s pressure" % (s, d, " at τ = %s%s" % (ftau(th), " (CFL 1)" if th == 1 else "")
                                               if is_explicit(s) else "", "redistributed" if red else "as assembled",
                                               pr)


def sec_pressure(bar):
    md = ["## Contact pressure (issue 16)\n"]
    cs = pressure_curves(bar)
    if not cs:
        return md + ["The pressure study was not run (no rows of study `pressure` in bar.csv).\n"]
    md.append("The L²(0,T) error of the contact stress at x = 0 on the bar (Θ = 1, γ0 = 0.2, τ = h/2 unless the "
              "τ column says otherwise, T = 3) with and without each remedy: **mass redistribution** "
              "(`nd_problem_set_mass_redistribution`: the contact "
              "node has no mass, its cell's mass goes to its other nodes keeping the mass and, for P2, the first and "
              "second moments) and the **applied pressure** (`nd_get_contact_pressure_applied`: the pressure the "
              "step applied, −φ_q/γ_q, compared with the exact stress's mean over the step) instead of λ_q at tⁿ. "
              "The explicit scheme (Newmark β = 0, γ = ½, lumped mass: the central difference) runs without "
              "redistribution at τ = dx/4 (dx = h/degree: the penalty limits its critical step to ≈ 0.41 h on P1); "
              "with redistribution the massless contact node is found each step from its static equilibrium with "
              "the contact condition, the critical step is the interior's, and P1 runs at τ = h/2, 0.9 h and h "
              "(**CFL 1**, where the interior stencil is exact at the nodes: not near the contact end, whose node "
              "is massless and whose neighbour carries 3h/2; the critical-step guard is off for these "
              "runs because its estimate is a little below the exact step h/cos(π/2NX)), P2 at τ = h/8 (τ = h/2 "
              "is above P2's critical step, ≈ 0.41 h). For the explicit scheme the applied pressure is λ at tⁿ. "
              "Rates: least-squares slope over the finest three NX.\n")
    md.append("![pressure convergence](bar_pressure_conv.png)\n\n![pressure work-precision](bar_pressure_wp.png)\n")
    rows, best, best_implicit, fits = [], None, None, {}
    for key, rs in cs.items():
        s, d, red, pr, th = key
        fine = rs[-3:]
        r_fit = rate([1 / r["nx"] for r in fine], [r["e_l2_stress"] for r in fine])
        fits[key] = (r_fit, rs[-1]["e_l2_stress"])
        last = rs[-1]
        at = [r for r in rs if r["nx"] == PRESSURE_TARGET[1]]
        rows.append([s, "P%d" % d, ftau(th), "yes" if red else "no", pr] + [g3(r["e_l2_stress"]) for r in rs] +
                    [frate(r_fit), g3(last["e_l2_l2_u"]), g3(last["e_l2_l2_v"]), ftime(last["loop_s"])])
        cand = (last, r_fit, at[0]["e_l2_stress"] if at else math.nan, key)
        if best is None or last["e_l2_stress"] < best[0]["e_l2_stress"]:
            best = cand
        if not is_explicit(s) and (best_implicit is None or last["e_l2_stress"] < best_implicit[0]["e_l2_stress"]):
            best_implicit = cand
    fast = ["%s P%d%s (%s)" % (s, d, " τ=%s" % ftau(th) if is_explicit(s) else "", frate(f[0]))
            for (s, d, red, pr, th), f in fits.items() if red and pr == "applied" and f[0] >= 0.4]
    plain = [f[0] for (s, d, red, pr, th), f in fits.items() if not red and pr == "end" and math.isfinite(f[0])]
    nxs = sorted({int(r["nx"]) for rs in cs.values() for r in rs})
    for row, rs in zip(rows, cs.values()):  # a curve with fewer NX (failed runs): blanks where it has none
        have = {int(r["nx"]): g3(r["e_l2_stress"]) for r in rs}
        row[5:5 + len(rs)] = [have.get(n, "–") for n in nxs]
    md.append(table(["scheme", "P", "τ", "redistributed", "pressure"] + ["NX=%d" % n for n in nxs] +
                    ["rate", "u L²L² (finest)", "v L²L² (finest)", "loop (finest)"], rows))
    last, r_fit, e320, key = best
    err, nx_t, rate_t = PRESSURE_TARGET
    # the rate's target with the rounding it is printed with (a slope of 0.4999 is reported as 0.50)
    met = math.isfinite(e320) and e320 <= err and round(r_fit, 2) >= rate_t
    md.append("\n**Which to pick.** The smallest contact-stress error at NX = %d is %s: %s (rate %s, %.4f before "
              "rounding). Target of the issue: error ≤ %g %% at NX = %d and rate ≥ %g: **%s** (error at NX = %d: %s). "
              "Without either remedy the rates of λ at tⁿ are %s to %s. With mass redistribution and the applied "
              "pressure these reach a rate ≥ 0.4: %s (½ is the most a stress that jumps in time allows in L²(0,T) "
              "with τ tied to h); the first-order dissipative schemes (θ = 1, Newmark(½,1)) stay near ¼ with or "
              "without. Among the implicit schemes (τ = h/2) the best is %s: %s at NX = %d (rate %s).\n" % (
                  int(last["nx"]), g3(last["e_l2_stress"]), describe(key), frate(r_fit), r_fit,
                  100 * err, nx_t, rate_t, "met" if met else "missed", nx_t, g3(e320),
                  frate(min(plain)) if plain else "–", frate(max(plain)) if plain else "–",
                  ", ".join(fast) if fast else "none",
                  describe(best_implicit[3]), g3(best_implicit[0]["e_l2_stress"]), int(best_implicit[0]["nx"]),
                  frate(best_implicit[1])))
    if is_explicit(key[0]):
        s_, d_, red_, pr_, th_ = key
        end = cs.get((s_, d_, red_, "end", th_), [])
        end320 = [r["e_l2_stress"] for r in end if r["nx"] == nx_t]
        end_fit = rate([1 / r["nx"] for r in end[-3:]], [r["e_l2_stress"] for r in end[-3:]])
        md.append("**A user who needs the pressure should set mass redistribution with the explicit central "
                  "difference (Newmark β = 0, γ = ½, lumped mass) at a step close to its critical step** "
                  "(`nd_problem_estimate_critical_timestep`; with redistribution it is the interior's, not the "
                  "penalty's: ≈ h on the P1 bar against ≈ 0.41 h without) and read "
                  "`nd_get_contact_pressure_applied` (for this scheme the same values as λ at tⁿ). CLI: "
                  "`[scheme] name = \"newmark\", beta = 0, gamma = 0.5` and `[solver] mass_lumping = true, "
                  "mass_redistribution = true`, history column `contact_force_applied`. How the error is measured "
                  "matters here: the `applied` rows compare the value at tⁿ with the exact stress's mean over "
                  "(tⁿ⁻¹, tⁿ), the `end` rows with its value at tⁿ; for this run the latter is %s at NX = %d (rate %s), "
                  "above the 5 %% target. The accuracy also depends on the step: at CFL 1 on the uniform P1 bar "
                  "the interior stencil is exact at the nodes (the u error, first order, comes from the contact "
                  "end), at τ = h/2 the scheme does no better than the implicit "
                  "schemes, and a 2D mesh has no step where the interior is exact. Where an implicit scheme is "
                  "needed (stiff materials, large steps), take mass redistribution, the hybrid scheme or "
                  "Newmark(¼,½), P2, and the applied pressure. The displacement and velocity errors are in the "
                  "table (finest NX) next to those without redistribution.\n" % (
                      g3(end320[0]) if end320 else "–", nx_t, frate(end_fit)))
        below = cs.get((s_, d_, red_, pr_, 0.9), [])
        if below and th_ == 1:
            b320 = [r["e_l2_stress"] for r in below if r["nx"] == nx_t]
            b_fit = rate([1 / r["nx"] for r in below[-3:]], [r["e_l2_stress"] for r in below[-3:]])
            md.append("Below CFL 1, where a user runs with the critical-step guard on: at τ = 0.9 h the same "
                      "combination gives %s at NX = %d (%s the 5 %% target) and an observed rate of %s: the jump "
                      "times of the exact stress then fall between time levels, and the error over the finest "
                      "three NX does not decrease as regularly.\n" % (
                          g3(b320[0]) if b320 else "–", nx_t,
                          "within" if b320 and b320[0] <= err else "above", frate(b_fit)))
    else:
        md.append("**A user who needs the pressure should set mass redistribution, an implicit second-order "
                  "scheme (the hybrid scheme or Newmark(¼,½)), P2, and read `nd_get_contact_pressure_applied`** (CLI: "
                  "`solver.mass_redistribution = true`, history column `contact_force_applied`). The displacement "
                  "and velocity errors with redistribution are in the table (finest NX) next to those without.\n")
    return md


# ---------------------------------------------------------------- main
def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", required=True, help="the data directory written by run.py")
    ap.add_argument("--out", required=True, help="where the PNG files and REPORT.md go")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    for names in PNGS.values():  # no stale plots of a part that was not run this time
        for n in names:
            if os.path.exists(os.path.join(a.out, n)):
                os.remove(os.path.join(a.out, n))
    bar = read_csv(os.path.join(a.data, "bar.csv"))
    getfem = read_csv(os.path.join(a.data, "getfem.csv"))
    pairs = read_csv(os.path.join(a.data, "getfem_pair.csv"))
    disk = read_csv(os.path.join(a.data, "disk.csv"))
    force = read_csv(os.path.join(a.data, "disk_force.csv"))
    energy = {}
    for name in ("hybrid", "newmark", "theta_half"):
        rs = read_csv(os.path.join(a.data, "energy_%s.csv" % name))
        if rs and len(rs) > 1:
            energy[name] = {k: np.array([r[k] for r in rs]) for k in ("t", "E", "E_Theta", "contact_stress")}
    machine = None
    if os.path.exists(os.path.join(a.data, "machine.txt")):
        with open(os.path.join(a.data, "machine.txt")) as fh:
            machine = dict(l.rstrip("\n").split(": ", 1) for l in fh if ": " in l)
    data_rel = os.path.relpath(a.data, a.out)

    written = []
    if bar:
        plot_bar(bar, a.out, written)
    if energy:
        plot_energy(energy, a.out, written)
    plot_disk(disk, force, a.out, written)
    plot_pressure(bar, a.out, written)

    md = ["# libnitschedyn: work–precision report\n",
          "**How to regenerate.** `make report` (about 15 minutes) runs the full plan (NX = 20…2560) and writes "
          "this report into `report/`; `make report-quick` (1–2 minutes) runs the CI plan (NX = 20…160) into "
          "`build/report-quick/`. Both call `tools/report/run.py` (the runs, CSV files in `data/`) and then "
          "`tools/report/make_report.py --data DIR --out OUTDIR` (these plots and this file, from the CSV files "
          "only).\n"]
    md += sec_setup(bar, energy, disk, machine)
    if bar:
        md += rates_table(bar) + sec_wp(bar, data_rel) + sec_cheapest(bar) + sec_tau(bar) + sec_pressure(bar)
    else:
        md.append("## 1D bar\n\nThe bar study was not run (no bar.csv): no rates, work–precision or cheapest-choice "
                  "results.\n")
    quad = read_csv(os.path.join(a.data, "disk_quad.csv"))
    md += sec_energy(bar, energy) + sec_getfem(bar, getfem, pairs) + sec_disk(disk, force, machine)
    md += sec_disk_quad(quad, disk)
    ball = read_csv(os.path.join(a.data, "ball.csv"))
    md += sec_ball(ball)
    md += sec_failed([("bar.csv", bar), ("getfem.csv", getfem), ("disk.csv", disk),
                      ("disk_quad.csv", [r for r in quad or [] if r["status"] != "simplex-reference"]),
                      ("ball.csv", ball)])
    md += sec_files(a.data, data_rel, written)
    with open(os.path.join(a.out, "REPORT.md"), "w") as fh:
        fh.write("\n".join(md))
    print("wrote %s and %d plots" % (os.path.join(a.out, "REPORT.md"), len(written)))


if __name__ == "__main__":
    main()
