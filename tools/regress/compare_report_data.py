#!/usr/bin/python3
"""Compares two runs of the work-precision study (make report / report-quick)
row by row: every column but the timings must be identical, to the digit.
A refactoring of the step path must leave them so.

usage: compare_report_data.py OLD_DATA_DIR NEW_DATA_DIR FILE.csv [FILE.csv ...]
e.g.   compare_report_data.py /tmp/before/data build/report-quick/data bar.csv disk.csv

Rows are matched by their run parameters; rows only in NEW (a new scheme)
are counted, not compared. Exit status 1 when a row differs or is missing.
"""
import csv
import sys
TIMING = {"setup_s", "loop_s", "repeats", "run", "wall_s", "time_s", "setup", "loop"}
def load(p):
    rows = list(csv.DictReader(open(p)))
    return rows
status = False
for name in sys.argv[3:]:
    a = load(sys.argv[1] + "/" + name); b = load(sys.argv[2] + "/" + name)
    def key(r): return tuple(v for k, v in r.items() if k in ("code","study","scheme","degree","Theta","gamma0","lumped","nx","tau","T","steps","h","mesh","unknowns"))
    bmap = {}
    for r in b: bmap.setdefault(key(r), []).append(r)
    same = diff = missing = 0
    for r in a:
        k = key(r)
        if k not in bmap: missing += 1; continue
        r2 = bmap[k].pop(0)
        cols = [c for c in r if not any(t in c for t in ("_s", "time", "repeat", "rss", "mem")) and c not in ("run",)]
        d = [(c, r[c], r2.get(c)) for c in cols if r[c] != r2.get(c)]
        if d: diff += 1; print(name, k, d[:4])
        else: same += 1
    extra = sum(len(v) for v in bmap.values())
    print("%s: %d rows identical (all but timing columns), %d differ, %d missing in new, %d new rows" % (name, same, diff, missing, extra))
    status = status or diff > 0 or missing > 0
sys.exit(1 if status else 0)
