"""Plots of a nitschedyn(1) history: ``python3 -m nitschedyn.plot history.csv [-o plot.png]``.

Three panels against time: the energies (E, E_Theta and the work W of the
loads), the balance E_Theta - W (which a conserving scheme keeps at its
initial value: its drift, at its own scale) and the contact force (with the
number of active contact points).
The CSV is the one the driver writes (``[output] history``): the columns
step, t, E, E_Theta, W, contact_force, active_points, max_penetration,
newton_iterations.

matplotlib is imported only when a plot is drawn: reading a history
(``read_history``) needs the standard library only. Without ``-o`` the plot
is written beside the CSV, with the suffix ``.png``; ``--show`` opens a
window instead.
"""

import argparse
import csv
import os
import sys

COLUMNS = ("step", "t", "E", "E_Theta", "W", "contact_force", "active_points", "max_penetration",
           "newton_iterations")


class HistoryError(Exception):
    """The file is not a history written by nitschedyn(1)."""


def read_history(path):
    """The history as a dict of column name -> list of floats."""
    with open(path, newline="") as f:
        rows = csv.reader(f)
        try:
            header = next(rows)
        except StopIteration:
            raise HistoryError(f"{path}: empty file") from None
        missing = [c for c in COLUMNS if c not in header]
        if missing:
            raise HistoryError(f"{path}: not a nitschedyn history (no column {', '.join(missing)})")
        data = {c: [] for c in header}
        for line, row in enumerate(rows, start=2):
            if len(row) != len(header):
                raise HistoryError(f"{path}:{line}: {len(row)} values, the header has {len(header)}")
            try:
                for c, x in zip(header, row):
                    data[c].append(float(x))
            except ValueError as e:
                raise HistoryError(f"{path}:{line}: {e}") from None
    if not data["t"]:
        raise HistoryError(f"{path}: no rows")
    return data


def _matplotlib(show):
    try:
        import matplotlib
    except ImportError:
        raise SystemExit("nitschedyn.plot: matplotlib is not installed "
                         "(Debian: apt-get install python3-matplotlib; pip: pip install matplotlib)") from None
    if not show:
        matplotlib.use("Agg")  # no display needed to write a file
    import matplotlib.pyplot as plt
    return plt


def plot(data, output=None, title=None, show=False):
    """Draws the energy, balance and contact-force panels; writes ``output`` (any
    format matplotlib knows by its suffix) unless ``show``."""
    plt = _matplotlib(show)
    t = data["t"]
    balance = [a - b for a, b in zip(data["E_Theta"], data["W"])]
    fig, (ax_e, ax_b, ax_f) = plt.subplots(3, 1, sharex=True, figsize=(8, 9),
                                           gridspec_kw={"height_ratios": [3, 2, 3]})
    ax_e.plot(t, data["E"], label="E (mechanical)")
    ax_e.plot(t, data["E_Theta"], label="E_Theta = E - Theta R")
    ax_e.plot(t, data["W"], "--", label="W (work of the loads)")
    ax_e.set_ylabel("energy")
    ax_e.legend(loc="best", fontsize="small")
    ax_e.grid(True, alpha=0.3)
    ax_b.plot(t, balance, color="C4", label="E_Theta - W")
    ax_b.set_ylabel("E_Theta - W")
    ax_b.legend(loc="best", fontsize="small")
    ax_b.grid(True, alpha=0.3)
    ax_f.plot(t, data["contact_force"], color="C3", label="contact force")
    ax_f.set_ylabel("contact force")
    ax_f.set_xlabel("t")
    ax_f.grid(True, alpha=0.3)
    ax_n = ax_f.twinx()
    ax_n.plot(t, data["active_points"], color="C7", lw=0.8, alpha=0.7, label="active points")
    ax_n.set_ylabel("active contact points")
    lines = ax_f.get_lines() + ax_n.get_lines()
    ax_f.legend(lines, [ln.get_label() for ln in lines], loc="upper left", fontsize="small")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    if show:
        plt.show()
    else:
        fig.savefig(output, dpi=120)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m nitschedyn.plot",
                                 description="Plot the energies and the contact force of a nitschedyn history (CSV).")
    ap.add_argument("history", help="the CSV written by nitschedyn ([output] history)")
    ap.add_argument("-o", "--output", help="the image to write (default: HISTORY with the suffix .png)")
    ap.add_argument("--title", help="a title (default: the file name)")
    ap.add_argument("--show", action="store_true", help="open a window instead of writing a file")
    args = ap.parse_args(argv)
    try:
        data = read_history(args.history)
    except (OSError, HistoryError) as e:
        print(f"nitschedyn.plot: {e}", file=sys.stderr)
        return 2
    output = args.output or os.path.splitext(args.history)[0] + ".png"
    plot(data, None if args.show else output, args.title or os.path.basename(args.history), args.show)
    if not args.show:
        print(f"nitschedyn.plot: wrote {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
