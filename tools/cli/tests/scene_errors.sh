#!/bin/sh
# Scene files and command lines that must be refused, each with exit status 2
# (usage or scene error) or 1 (the library refused the problem) and a message
# naming the file, the line and the key; --check, --help, --version; and
# generated-mesh scenes (1D bar, 2D block) that use the other tables.
#
# usage: scene_errors.sh DRIVER SOURCE_DIR WORK_DIR
set -u
driver=$1 src=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
cd "$work" || exit 1
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

# a valid scene: the disk on the plane y = 0, one second
cat > base.toml <<EOT
[mesh]
gmsh = "$src/examples/meshes/disk_h4.msh"
[material]
E = 50.0
nu = 0.25
rho = 1.0
[obstacle]
region = 1
point = [0.0, 0.0]
normal = [0.0, 1.0]
[time]
tau = 0.05
T = 1.0
EOT

# expect STATUS NAME 'MESSAGE' SED-SCRIPT [ARGS...]: the scene is base.toml
# through sed; the message must appear in stderr (fixed string)
expect() {
  want=$1 name=$2 msg=$3 script=$4
  shift 4
  sed "$script" base.toml > "$name.toml"
  "$driver" "$name.toml" --quiet "$@" > "$name.out" 2> "$name.err"
  got=$?
  if [ $got -ne "$want" ]; then
    fail "$name: exit status $got, not $want: $(cat "$name.err")"
  elif [ -n "$msg" ] && ! grep -qF -- "$msg" "$name.err"; then
    fail "$name: stderr does not say '$msg': $(cat "$name.err")"
  else
    echo "ok: $name (exit $got): $(cat "$name.err")"
  fi
}

expect 0 valid '' 's/^$//'
expect 2 unknown_key "unknown_key.toml:7:1: unknown key 'material.colour'" '6a\
colour = "red"'
expect 2 unknown_table "unknown_table.toml:14:2: unknown key 'outputs'" '$a\
[outputs]'
expect 2 wrong_type "wrong_type.toml:4:5: 'material.E' must be a number, not a string" '4s/.*/E = "fifty"/'
expect 2 wrong_type_vector "wrong_type_vector.toml:9:15: 'obstacle.point[1]' must be a number, not a string" \
  '9s/.*/point = [0.0, "0"]/'
expect 2 no_mesh_table "no_mesh_table.toml: no [mesh] table" '1,2d'
expect 2 missing_mesh_file "missing_mesh_file.toml:2:8: 'mesh.gmsh': no mesh file" '2s/.*/gmsh = "nowhere.msh"/'
expect 2 negative_tau "negative_tau.toml:12:7: 'time.tau' must be positive" '12s/.*/tau = -0.05/'
expect 2 missing_key "missing_key.toml:3:1: [material] has no key 'rho'" '6d'
expect 2 missing_tau "missing_tau.toml: no 'time.tau'" '12d'
expect 0 tau_on_command_line '' '12d' --tau 0.05
expect 2 syntax "syntax.toml:5:" '5s/.*/nu = /'
expect 2 duplicate_key "duplicate_key.toml:7:" '6a\
E = 1.0'
expect 2 unknown_region_name "unknown_region_name.toml:8:10: no region named 'bottom'" '8s/.*/region = "bottom"/'
expect 2 empty_region "empty_region.toml:8:10: region 7 (obstacle.region) has no facet" '8s/.*/region = 7/'
expect 2 library_refuses_nu "library_refuses_nu.toml:3:1: [material]: nd_problem_set_material" '5s/.*/nu = 0.6/'
expect 2 dimension "dimension.toml:15:14: 'loads.body_force' has 3 components; the mesh is 2D" '$a\
[loads]\
body_force = [0.0, 0.0, -0.1]'
expect 2 scheme_parameter "scheme_parameter.toml:16:1: 'scheme.beta' is not a parameter of the hybrid scheme" '$a\
[scheme]\
name = "hybrid"\
beta = 0.25'
expect 2 unknown_scheme "unknown_scheme.toml:15:8: 'scheme.name' is \"leapfrog\"" '$a\
[scheme]\
name = "leapfrog"'
expect 2 gamma0_word "gamma0_word.toml:15:10: 'nitsche.gamma0' must be a number >= 0 or \"auto\"" '$a\
[nitsche]\
gamma0 = "safe"'
expect 1 not_coercive "nitschedyn: setting up the problem (nd_problem_setup): " '$a\
[nitsche]\
gamma0 = 1.0'
expect 2 bad_option "--frobnicate" 's/^$//' --frobnicate
expect 2 bad_tau_option "--tau: -1 is not a positive number" 's/^$//' --tau -1
expect 2 bad_T_option "--T: x is not a number >= 0" 's/^$//' --T x

# --check: set up, no output written
mkdir check_out
sed 's/^$//' base.toml > check.toml
printf '[output]\nhistory = "h.csv"\nparaview = "p"\n' >> check.toml
if "$driver" check.toml --check --out check_out > check.out 2>&1; then
  grep -q 'the scene is valid and the problem is set up' check.out || fail "--check: $(cat check.out)"
  [ -z "$(ls check_out)" ] || fail "--check wrote $(ls check_out)"
  echo "ok: --check: $(tail -1 check.out)"
else
  fail "--check: $(cat check.out)"
fi
# usage
"$driver" --help > help.out 2>&1 || fail "--help exits $?"
grep -q -- '--check' help.out && grep -q -- '--progress' help.out || fail "--help: $(cat help.out)"
"$driver" --version > version.out 2>&1 || fail "--version exits $?"
grep -q '^nitschedyn [0-9]*\.[0-9]*\.[0-9]* (libnitschedyn [0-9.]*)$' version.out || fail "--version: $(cat version.out)"
"$driver" > noscene.out 2>&1
[ $? -eq 2 ] && grep -q 'no scene file' noscene.out || fail "no scene: $(cat noscene.out)"
"$driver" nowhere.toml > noscene.out 2>&1
[ $? -eq 2 ] && grep -q 'nowhere.toml: no such scene file' noscene.out || fail "missing scene: $(cat noscene.out)"
echo "ok: --help, --version, no scene, missing scene"
# not a terminal: no progress bar, unless --progress (then a line every 10 %)
"$driver" base.toml --quiet > quiet.out 2> quiet.err || fail "--quiet: $(cat quiet.err)"
[ ! -s quiet.err ] && [ "$(wc -l < quiet.out)" -eq 1 ] || fail "--quiet: $(cat quiet.out quiet.err)"
"$driver" base.toml --quiet --progress > progress.out 2> progress.err || fail "--progress: $(cat progress.err)"
[ "$(grep -c '^progress: ' progress.err)" -eq 11 ] && grep -q '^progress: 100%  step 20/20' progress.err ||
  fail "--progress: $(cat progress.err)"
echo "ok: --quiet, --progress"

# generated meshes: the 1D bar of docs/design.md §7 falling with speed 1/2 on x = 0
# (clamped at x = 1), and a 2D block with a traction on its top
cat > bar.toml <<'EOT'
title = "1D bar"
[mesh]
generate = "interval"
cells = [40]
lo = [0.0]
hi = [1.0]
[regions]
contact = { id = 1, lo = [-0.5], hi = [0.5] }
clamped = { id = 2, lo = [0.5], hi = [1.5] }
[material]
E = 1.0
rho = 1.0
[dirichlet]
regions = ["clamped"]
[obstacle]
region = "contact"
point = [0.0]
normal = [1.0]
[nitsche]
gamma0 = 0.2
[scheme]
name = "newmark"
beta = 0.25
gamma = 0.5
[initial]
displacement = [0.01]
velocity = [-0.5]
[time]
tau = 0.0125
T = 3.0
[output]
history = "bar/history.csv"
EOT
if "$driver" bar.toml > bar.out 2>&1; then
  rows=$(($(grep -vc '^#' bar/history.csv) - 1))  # (the title's comment, the header)
  [ "$rows" -eq 241 ] || fail "bar: $rows rows"
  [ "$(head -1 bar/history.csv)" = "# title: 1D bar" ] || fail "bar: line 1 is not the title: $(head -1 bar/history.csv)"
  awk -F, '$1 ~ /^[0-9]/ && $6 > 0 { c++ } END { exit c == 0 }' bar/history.csv || fail "bar: never in contact"
  echo "ok: bar: $(tail -1 bar.out)"
else
  fail "bar: $(cat bar.out)"
fi
cat > block.toml <<'EOT'
[mesh]
generate = "rectangle"
cells = [8, 4]
lo = [0.0, 0.5]
hi = [4.0, 2.5]
degree = 2
[regions]
bottom = { id = 1, lo = [-inf, 0.49], hi = [inf, 0.51] }
top = { id = 3, lo = [-inf, 2.49], hi = [inf, 2.51] }
[material]
E = 50.0
nu = 0.3
rho = 1.0
[loads]
traction = [{ region = "top", value = [0.0, -1.0] }]
[obstacle]
region = "bottom"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[scheme]
name = "galpha"
rho_inf = 0.9
[solver]
linear = "umfpack"
newton_max_iter = 40
[time]
tau = 0.02
T = 2.0
[output]
history = "block.csv"
paraview = "vtu/block"
interval = 0.5
EOT
if "$driver" block.toml --out block_out > block.out 2>&1; then
  [ "$(grep -c '<DataSet ' block_out/vtu/block.pvd)" -eq 5 ] || fail "block: $(cat block_out/vtu/block.pvd)"
  awk -F, '$1 ~ /^[0-9]/ && $6 > 0 { c++ } END { exit c == 0 }' block_out/block.csv || fail "block: never in contact"
  echo "ok: block: $(tail -1 block.out)"
else
  fail "block: $(cat block.out)"
fi

# [guards]: bad values name their line and key; good ones are applied
expect 2 guard_negative 'guards.energy' 's/^\[time\]/[guards]\nenergy = -1.0\n[time]/'
expect 2 guard_not_bool 'guards.coercivity' 's/^\[time\]/[guards]\ncoercivity = 1\n[time]/'
expect 2 guard_unknown "unknown key 'guards.energi'" 's/^\[time\]/[guards]\nenergi = 2.0\n[time]/'
expect 0 guards_valid '' 's/^\[time\]/[guards]\nenergy = 3.0\npenetration = 0.0\ncritical_timestep = true\n[time]/'
grep -q ':1[0-9]:[0-9]*: ' guard_negative.err || fail "guard_negative: no file:line:col in $(cat guard_negative.err)"
expect 2 checkpoint_no_file "[checkpoint] has no key 'file'" 's/^\[time\]/[checkpoint]\nevery = 2\n[time]/'
expect 2 checkpoint_negative 'checkpoint.every' 's/^\[time\]/[checkpoint]\nfile = "c.ndck"\nevery = -2\n[time]/'

# [checkpoint] and --restart: the second half of the bar's run (through the
# impact, steps 2-80) resumed from the checkpoint of its first half has the same history
# rows, digit for digit, and ends with the same checkpoint
{ sed 's|^history = .*|history = "h.csv"|' bar.toml; printf '[checkpoint]\nfile = "state.ndck"\nevery = 40\n'; } > ck.toml
if "$driver" ck.toml --quiet --out ck_full > ck.out 2>&1 && "$driver" ck.toml --quiet --T 0.75 --out ck_half >> ck.out 2>&1 &&
   "$driver" ck.toml --quiet --restart ck_half/state.ndck --out ck_rest >> ck.out 2>&1; then
  awk -F, '$1 ~ /^[0-9]/ && $1 >= 60' ck_full/h.csv > ck_full.rows
  grep -v '^#' ck_rest/h.csv | tail -n +2 > ck_rest.rows
  if [ "$(wc -l < ck_rest.rows)" -eq 181 ] && cmp -s ck_full.rows ck_rest.rows; then
    echo "ok: restart from step 60 reproduces steps 60-240"
  else
    fail "restart: the resumed history differs: $(diff ck_full.rows ck_rest.rows | head -5)"
  fi
  awk -F, '$1 ~ /^[0-9]/ && $6 > 0 { c++ } END { exit c == 0 }' ck_rest/h.csv || fail "restart: never in contact"
  cmp -s ck_full/state.ndck ck_rest/state.ndck || fail "restart: the final checkpoints differ"
else
  fail "checkpoint/restart: $(cat ck.out)"
fi
expect 1 restart_missing 'no_such.ndck' 's/^$//' --restart no_such.ndck
{ cat base.toml; printf '[checkpoint]\nfile = "disk.ndck"\n'; } > disk_ck.toml
"$driver" disk_ck.toml --quiet --T 0.1 > /dev/null 2>&1 || fail "disk_ck: no checkpoint written"
"$driver" bar.toml --quiet --restart disk.ndck > bar_restart.out 2>&1
[ $? -eq 1 ] && grep -q 'another problem' bar_restart.out ||
  fail "restart from another scene's checkpoint: $(cat bar_restart.out)"

[ $fails -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
echo "all scene checks passed"
