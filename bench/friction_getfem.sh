#!/bin/sh
# The frictional landing of bench/friction.sh side by side with GetFEM
# (docs/performance.md, "Friction"): the disk and the ball h = 4, P1,
# Newmark(1/4, 1/2), Theta = 1, gamma0 = 1e-3, tau = 0.05, to t = 16, v_x = 0.5,
# frictionless and with Coulomb's F = 0.3. Ours: bench/friction_step.c;
# GetFEM's: bench/getfem_drop.py (its Nitsche brick, with friction the slip
# u - U^n). One run each, one BLAS thread, one after the other. Writes
# OUT_DIR/friction_getfem.txt and GetFEM's histories in OUT_DIR/history.
# usage: sh bench/friction_getfem.sh [BUILD_DIR] [OUT_DIR=bench/results]
set -eu
build=${1:-build}
out=${2:-bench/results}
mkdir -p "$out/history"
cmake --build "$build" --target friction_step >/dev/null
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
ours=$(mktemp)
trap 'rm -f "$ours"' EXIT
"$build/friction_step" examples/meshes 4 16 newmark 1e-3 > "$ours"
for mesh in disk_h4:2 ball_h4:3; do
  name=${mesh%:*} dim=${mesh#*:}
  /usr/bin/python3 bench/getfem_drop.py "examples/meshes/$name.msh" "$dim" 1 0.05 16 \
    "$out/history/getfem_friction_${name}_none.csv" > /dev/null
  /usr/bin/python3 bench/getfem_drop.py "examples/meshes/$name.msh" "$dim" 1 0.05 16 \
    "$out/history/getfem_friction_${name}_coulomb.csv" 0.3 0.5 > /dev/null
done
/usr/bin/python3 - "$ours" "$out" <<'EOF' | tee "$out/friction_getfem.txt"
import csv, re, sys
ours, out = sys.argv[1], sys.argv[2]
# friction_step's lines: a mesh line, then "frictionless ..." and "Coulomb F = 0.3 ..."
runs, mesh = {}, None
for line in open(ours):
    if line.startswith(("disk", "ball")):
        mesh = line.split()[0]
        continue
    m = re.search(r"contact steps +(\d+), mean ([0-9.]+) s, Newton ([0-9.]+).*loop ([0-9.]+) s", line)
    runs[(mesh, "coulomb" if line.startswith("Coulomb") else "none")] = \
        (int(m.group(1)), float(m.group(2)), float(m.group(3)), float(m.group(4)))

def getfem(name, law):
    """friction_step's measures from GetFEM's history: a contact step starts or
    ends with a contact force; the loop is every step's time."""
    rows = list(csv.DictReader(open("%s/history/getfem_friction_%s_%s.csv" % (out, name, law))))
    times, newton, loop = [], 0, 0.0
    for before, row in zip(rows, rows[1:]):
        loop += float(row["step_s"])
        if float(before["contact_force"]) > 0 or float(row["contact_force"]) > 0:
            times.append(float(row["step_s"]))
            newton += int(row["newton"])
    return len(times), sum(times) / len(times), newton / len(times), loop

print("P1, Newmark(1/4, 1/2), Theta = 1, gamma0 = 1e-3, tau = 0.05, T = 16, v_x = 0.5; one run each, one BLAS thread")
print("%-8s %-12s %-28s %-28s %s" % ("mesh", "law", "ours: steps, mean, Newton", "GetFEM: steps, mean, Newton",
                                      "GetFEM/ours: contact step, loop"))
for name in ("disk_h4", "ball_h4"):
    for law in ("none", "coulomb"):
        o, g = runs[(name, law)], getfem(name, law)
        print("%-8s %-12s %4d, %8.3f ms, %4.2f        %4d, %8.3f ms, %4.2f        %6.1fx, %6.1fx"
              % (name, "Coulomb 0.3" if law == "coulomb" else "frictionless", o[0], 1e3 * o[1], o[2],
                 g[0], 1e3 * g[1], g[2], g[1] / o[1], g[3] / o[3]))
EOF
