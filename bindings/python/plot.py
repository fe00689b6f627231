"""Plots of a nitschedyn(1) history: ``python3 -m nitschedyn.plot history.csv [-o plot.png]``.

Three panels against time: the energies (E, E_Theta and the work W of the
loads), the balance E_Theta - W (which a conserving scheme keeps at its
initial value: its drift, at its own scale) and the contact force (with the
number of active contact points): the resultant at t^n and, when the history
has it, the one the step applied (``contact_force_applied``, the accurate one
the README recommends).
The CSV is the one the driver writes (``[output] history``): the columns
step, t, E, E_Theta, W, contact_force, active_points, max_penetration,
newton_iterations and, from the driver of this version on,
contact_force_applied. Lines that start with ``#`` are comments; the driver
writes the scene's title as ``# title: ...`` before the header, and it is the
plot's title (``--title`` overrides it; without either, the file name).

numpy and matplotlib are imported only when a plot is drawn: ``--help``,
argument errors and reading a history (``read_history``) need the standard
library only, and without them a plot fails with one line naming the Debian
package to install (exit status 2). Without ``-o`` the plot is written beside
the CSV, with the suffix ``.png``; ``--show`` opens a window instead.
"""

import argparse
import csv
import os
import sys

COLUMNS = ("step", "t", "E", "E_Theta", "W", "contact_force", "active_points", "max_penetration",
           "newton_iterations")
APPLIED = "contact_force_applied"  # optional: histories of older drivers lack it
FRICTION = "dissipation_friction"  # optional: D_f, drawn when the history has some


class HistoryError(Exception):
    """The file is not a history written by nitschedyn(1)."""


class MissingModule(ImportError):
    """numpy or matplotlib, needed to draw, is not installed; the message names the package."""


class History(dict):
    """A history: column name -> list of floats, and ``title``, the scene's
    title from the comment ``# title: ...`` (None without one)."""

    title = None


def _lines(f, comments):
    """The lines of f that are not comments, with their numbers; the comments
    ``# key: value`` go into the dict comments (the first of each key)."""
    for number, line in enumerate(f, start=1):
        if line.startswith("#"):
            key, sep, value = line[1:].partition(":")
            if sep:
                comments.setdefault(key.strip().lower(), value.strip())
            continue
        yield number, line


def read_history(path):
    """The history as a ``History``: a dict of column name -> list of floats."""
    comments = {}
    with open(path, newline="") as f:
        lines = _lines(f, comments)
        try:
            _, first = next(lines)
        except StopIteration:
            raise HistoryError(f"{path}: empty file") from None
        header = next(csv.reader([first]), [])
        missing = [c for c in COLUMNS if c not in header]
        if missing:
            raise HistoryError(f"{path}: not a nitschedyn history (no column {', '.join(missing)})")
        data = History((c, []) for c in header)
        for number, line in lines:
            row = next(csv.reader([line]), [])
            if len(row) != len(header):
                raise HistoryError(f"{path}:{number}: {len(row)} values, the header has {len(header)}")
            try:
                for c, x in zip(header, row):
                    data[c].append(float(x))
            except ValueError as e:
                raise HistoryError(f"{path}:{number}: {e}") from None
    if not data["t"]:
        raise HistoryError(f"{path}: no rows")
    data.title = comments.get("title") or None
    return data


def _import(module, package):
    """Imports module; a MissingModule naming the Debian package when it (or
    what it needs) is not installed."""
    import importlib
    try:
        return importlib.import_module(module)
    except ImportError as e:
        name, why = module.split(".")[0], " ".join(str(e).split())  # (one line)
        raise MissingModule(f"{name} is not installed (Debian: apt-get install {package}; pip: pip install {name}): "
                            f"{why}") from None


def _matplotlib(show):
    _import("numpy", "python3-numpy")  # first: matplotlib needs it, and would hide its name
    matplotlib = _import("matplotlib", "python3-matplotlib")
    if not show:
        matplotlib.use("Agg")  # no display needed to write a file
    return _import("matplotlib.pyplot", "python3-matplotlib")


def plot(data, output=None, title=None, show=False):
    """Draws the energy, balance and contact-force panels; writes ``output`` (any
    format matplotlib knows by its suffix) unless ``show``. The title is
    ``title``, else the history's (``data.title``). Returns what was drawn:
    {"title": the figure's title, "legends": {"energy", "balance",
    "contact force": the labels of each panel's legend}}. Raises MissingModule
    without numpy or matplotlib."""
    plt = _matplotlib(show)
    if title is None:
        title = getattr(data, "title", None)
    t = data["t"]
    friction = FRICTION in data and any(x != 0 for x in data[FRICTION])
    D_f = data[FRICTION] if friction else [0.0] * len(t)
    balance = [a + d - b for a, d, b in zip(data["E_Theta"], D_f, data["W"])]
    balance_label = "E_Theta + D_f - W" if friction else "E_Theta - W"
    fig, (ax_e, ax_b, ax_f) = plt.subplots(3, 1, sharex=True, figsize=(8, 9),
                                           gridspec_kw={"height_ratios": [3, 2, 3]})
    ax_e.plot(t, data["E"], label="E (mechanical)")
    ax_e.plot(t, data["E_Theta"], label="E_Theta = E - Theta R")
    ax_e.plot(t, data["W"], "--", label="W (work of the loads)")
    if friction:
        ax_e.plot(t, D_f, ":", label="D_f (dissipated by friction)")
    ax_e.set_ylabel("energy")
    ax_e.legend(loc="best", fontsize="small")
    ax_e.grid(True, alpha=0.3)
    ax_b.plot(t, balance, color="C4", label=balance_label)
    ax_b.set_ylabel(balance_label)
    ax_b.legend(loc="best", fontsize="small")
    ax_b.grid(True, alpha=0.3)
    if APPLIED in data:  # beneath, wider: the thin resultant at t^n stays visible on it
        ax_f.plot(t, data[APPLIED], color="C0", lw=1.8, label=APPLIED + " (the step's: recommended)")
    ax_f.plot(t, data["contact_force"], color="C3", lw=0.8, label="contact_force (at t^n)")
    ax_f.set_ylabel("contact force")
    ax_f.set_xlabel("t")
    ax_f.grid(True, alpha=0.3)
    ax_n = ax_f.twinx()
    ax_n.plot(t, data["active_points"], color="C7", lw=0.8, alpha=0.7, label="active points")
    ax_n.set_ylabel("active contact points")
    lines = ax_f.get_lines() + ax_n.get_lines()
    ax_f.legend(lines, [ln.get_label() for ln in lines], loc="upper left", fontsize="small")
    drawn = {"title": "", "legends": {}}
    if title:
        drawn["title"] = fig.suptitle(title).get_text()
    for name, ax in (("energy", ax_e), ("balance", ax_b), ("contact force", ax_f)):
        drawn["legends"][name] = [text.get_text() for text in ax.get_legend().get_texts()]
    fig.tight_layout()
    if show:
        plt.show()
    else:
        fig.savefig(output, dpi=120)
    plt.close(fig)
    return drawn


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m nitschedyn.plot",
                                 description="Plot the energies and the contact force of a nitschedyn history (CSV). "
                                             "Needs numpy and matplotlib (Debian: python3-numpy, python3-matplotlib).")
    ap.add_argument("history", help="the CSV written by nitschedyn ([output] history)")
    ap.add_argument("-o", "--output", help="the image to write (default: HISTORY with the suffix .png)")
    ap.add_argument("--title", help="a title (default: the scene's title in the history, else the file name)")
    ap.add_argument("--show", action="store_true", help="open a window instead of writing a file")
    args = ap.parse_args(argv)
    try:
        data = read_history(args.history)
    except (OSError, HistoryError) as e:
        print(f"nitschedyn.plot: {e}", file=sys.stderr)
        return 2
    output = args.output or os.path.splitext(args.history)[0] + ".png"
    title = args.title or data.title or os.path.basename(args.history)
    try:
        plot(data, None if args.show else output, title, args.show)
    except MissingModule as e:
        print(f"nitschedyn.plot: cannot plot: {e}", file=sys.stderr)
        return 2
    if not args.show:
        print(f"nitschedyn.plot: wrote {output} ({title})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
