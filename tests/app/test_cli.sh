#!/usr/bin/env bash
# Command-line contract of `corebox run`: exit codes, messages that name file, line and key, no
# partial output files on errors, blow-up reporting with the last good state, and a normal run; the
# files of `corebox bench pile`; and the device errors of `corebox bench p2p|table1` and of `corebox run --gpus`
# without enough GPUs.
# Needs COREBOX (the binary) and SRC (the source tree) in the environment.
set -u
: "${COREBOX:?}" "${SRC:?}"
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"


# expect NAME CODE PATTERN -- ARGS...: runs corebox, checks the exit code and that stderr matches.
expect() {
    local name=$1 code=$2 pattern=$3
    shift 4
    local err rc
    err=$("$COREBOX" "$@" 2>&1 >/dev/null)
    rc=$?
    if [ "$rc" -ne "$code" ]; then fail "$name: exit $rc, expected $code; stderr: $err"; return; fi
    if ! grep -Eq -- "$pattern" <<<"$err"; then fail "$name: stderr does not match /$pattern/: $err"; return; fi
    pass
}

# no_outputs NAME: nothing but the inputs may be left in $work/out.
no_outputs() {
    local left
    left=$(ls -A "$work/out")
    if [ -n "$left" ]; then fail "$1: left files behind: $left"; else pass; fi
}

scene() {  # scene FILE BODY: a valid scene with BODY appended or substituted
    printf '%s\n' "$2" >"$work/$1"
}

base='[box]
size = [10, 10, 10]

[[species]]
name = "A"
count = 20
mass = 1.0
radius = 0.5

[integrator]
method = "verlet"
dt = 0.002'

run_bad() {  # run_bad NAME FILE LINE KEY [EXTRA PATTERN]
    local name=$1 file=$2 line=$3 key=$4
    rm -rf "$work/out" && mkdir -p "$work/out"
    expect "$name" 2 "$(basename "$file"):$line: $key" -- run "$file" --steps 5 --observables "$work/out/obs.csv" --state-out "$work/out/state.csv"
    no_outputs "$name"
}

scene malformed.toml "$(sed 's/count = 20/count = = 20/' <<<"$base")"
run_bad malformed "$work/malformed.toml" 6 ""
scene unknown_key.toml "$base
colour_depth = 3"
run_bad "unknown key" "$work/unknown_key.toml" 13 "integrator.colour_depth"
scene negative_mass.toml "$(sed 's/mass = 1.0/mass = -2.0/' <<<"$base")"
run_bad "negative mass" "$work/negative_mass.toml" 7 "species\[0\].mass"
scene zero_mass.toml "$(sed 's/mass = 1.0/mass = 0/' <<<"$base")"
run_bad "zero mass" "$work/zero_mass.toml" 7 "species\[0\].mass"
scene zero_radius.toml "$(sed 's/radius = 0.5/radius = 0.0/' <<<"$base")"
run_bad "zero radius" "$work/zero_radius.toml" 8 "species\[0\].radius"
scene zero_dt.toml "$(sed 's/dt = 0.002/dt = 0.0/' <<<"$base")"
run_bad "zero dt" "$work/zero_dt.toml" 12 "integrator.dt"
scene negative_dt.toml "$(sed 's/dt = 0.002/dt = -1e-3/' <<<"$base")"
run_bad "negative dt" "$work/negative_dt.toml" 12 "integrator.dt"
scene zero_box.toml "$(sed 's/size = \[10, 10, 10\]/size = [10, 0, 10]/' <<<"$base")"
run_bad "zero box" "$work/zero_box.toml" 2 "box.size"
scene bad_method.toml "$(sed 's/method = "verlet"/method = "leapfrog"/' <<<"$base")"
run_bad "unknown method" "$work/bad_method.toml" 11 "integrator.method"
scene crowded.toml "$(sed 's/count = 20/count = 2000/' <<<"$base")"
run_bad "too many particles" "$work/crowded.toml" "[0-9]+" "species"

# Particle files: overlapping and outside the box, named by the CSV.
printf 'id,species,x,y,z,vx,vy,vz\n0,0,5,5,5,0,0,0\n1,0,5.4,5,5,0,0,0\n' >"$work/overlap.csv"
printf 'id,species,x,y,z,vx,vy,vz\n0,0,5,5,5,0,0,0\n1,0,12,5,5,0,0,0\n' >"$work/outside.csv"
printf 'id,species,x,y,z,vx,vy,vz\n0,0,5,5,5,0,0,0\n1,0,7,5,five,0,0,0\n' >"$work/garbled.csv"
for case in overlap outside garbled; do
    scene "$case.toml" "$(sed 's/count = 20/count = 2/' <<<"$base")
[init]
particles = \"$case.csv\""
done
rm -rf "$work/out" && mkdir -p "$work/out"
expect "overlapping particles" 2 "overlap.csv.*particles 0 and 1 overlap" -- run "$work/overlap.toml" --steps 5 --observables "$work/out/o.csv"
expect "outside the box" 2 "outside.csv.*outside the box" -- run "$work/outside.toml" --steps 5 --observables "$work/out/o.csv"
expect "garbled particle file" 2 "garbled.csv:3: z: not a finite number" -- run "$work/garbled.toml" --steps 5 --observables "$work/out/o.csv"
no_outputs "bad particle files"

# Files that cannot be read or written.
rm -rf "$work/out" && mkdir -p "$work/out"
expect "missing scene" 2 "cannot read '$work/none.toml'" -- run "$work/none.toml"
scene good.toml "$base"
expect "unwritable observables" 2 "--observables: cannot write" -- run "$work/good.toml" --observables "$work/missing_dir/o.csv"
expect "unwritable state" 2 "--state-out: cannot write" -- run "$work/good.toml" --state-out "$work/missing_dir/s.csv"
no_outputs "unwritable outputs"

# Usage errors.
expect "unknown flag" 2 "--bogus" -- run "$work/good.toml" --bogus
expect "bad steps" 2 "--steps" -- run "$work/good.toml" --steps -3
expect "bad backend" 2 "unknown backend" -- run "$work/good.toml" --backend fpga
# A named choice on the command line: refused with the list of names, from the same table as scene files.
expect "unknown method flag" 2 "--method: unknown method 'leapfrog'; one of: euler, rk2" -- run "$work/good.toml" --method leapfrog
"$COREBOX" --help | grep -q "run" && pass || fail "--help does not list run"

# A normal run: observables header, rows at 0, every K and the end, final state readable.
rm -rf "$work/out" && mkdir -p "$work/out"
if "$COREBOX" run "$SRC/assets/hard_spheres.toml" --steps 25 --every 10 --observables "$work/out/obs.csv" \
    --state-out "$work/out/state.csv" --quiet 2>"$work/err"; then
    pass
    head -1 "$work/out/obs.csv" | grep -q '^step,time,kinetic,potential,total,dissipated,thermostat,px,py,pz,temperature,collisions_pair,collisions_wall,pressure_wall,pressure_virial,pressure_wall_centre,' \
        && pass || fail "observables header"
    # Pressures: 0 in the row at step 0 (no window); then the virial route is positive (its kinetic
    # term) and the walls' is not negative (a window of 5 steps may see no wall hit).
    awk -F, 'NR == 2 && ($14 != 0 || $15 != 0) { bad = 1 } NR > 2 && !($14 >= 0 && $15 > 0) { bad = 1 } END { exit bad }' \
        "$work/out/obs.csv" && pass || fail "pressure columns"
    steps=$(cut -d, -f1 "$work/out/obs.csv" | tail -n +2 | tr '\n' ' ')
    [ "$steps" = "0 10 20 25 " ] && pass || fail "observable rows at steps '$steps', expected '0 10 20 25 '"
    head -1 "$work/out/state.csv" | grep -q '^id,species,x,y,z,vx,vy,vz$' && pass || fail "state header"
    # The written state is a valid particle file for a new run.
    scene restart.toml "$(sed -e '/^\[init\]/,$d' "$SRC/assets/hard_spheres.toml")
[init]
particles = \"$work/out/state.csv\""
    "$COREBOX" run "$work/restart.toml" --steps 5 --quiet >/dev/null 2>"$work/err2" && pass || fail "restart from state: $(cat "$work/err2")"
else
    fail "normal run failed: $(cat "$work/err")"
fi

# The dense preset loads and runs: 4,000 spheres at packing fraction 0.45, the pressures positive and
# the energy kept (elastic: nothing dissipated in 40 steps).
if "$COREBOX" run "$SRC/assets/dense_hard_spheres.toml" --steps 40 --every 20 --observables "$work/out/dense.csv" --quiet \
    --no-window 2>"$work/err"; then
    awk -F, 'NR > 2 && !($14 > 0 && $15 > 0 && $16 > 0 && $6 == 0) { bad = 1 } END { exit bad }' "$work/out/dense.csv" \
        && pass || fail "dense preset: pressures or energy"
else
    fail "dense preset run: $(cat "$work/err")"
fi

# A blow-up: euler with a huge step on an LJ gas stops with exit 3, names the step and the cause,
# writes the last good state and keeps the observables up to the failure.
rm -rf "$work/out" && mkdir -p "$work/out"
expect "blow-up" 3 "instability at step [0-9]+.*likely cause: dt = 0.05 is too large for euler" -- \
    run "$SRC/assets/argon_gas.toml" --method euler --dt 0.05 --steps 5000 --every 1 --observables "$work/out/obs.csv" \
    --state-out "$work/out/state.csv"
[ -s "$work/out/state.last_good.csv" ] && pass || fail "no last good state after a blow-up"
[ ! -e "$work/out/state.csv" ] && pass || fail "final state written despite the blow-up"
if grep -qiE 'nan|inf' "$work/out/obs.csv"; then fail "NaN or inf in the observables"; else pass; fi

# The same blow-up in a headless run (Mesa's software EGL device): exit 3, the observables so far
# and the last good state kept beside them, as in a batch run.
rm -rf "$work/out" && mkdir -p "$work/out"
expect "headless blow-up" 3 "instability at step [0-9]+" -- \
    run "$SRC/assets/argon_gas.toml" --method euler --dt 0.05 --headless --software-gl --frames 201 --steps-per-frame 25 \
    --size 64x64 --out "$work/out/frames"
[ -s "$work/out/frames/observables.csv" ] && pass || fail "no observables after a headless blow-up"
[ -s "$work/out/frames/last_good_state.csv" ] && pass || fail "no last good state after a headless blow-up"

# --recover: verlet at 25 times the preset's dt blows up (exit 3 without it); with it the run goes
# back to the last good row, halves dt, says so and finishes: exit 0, one row per step in order up to
# the end, and the final state. The same in a headless run.
rm -rf "$work/out" && mkdir -p "$work/out"
expect "no recover" 3 "instability at step [0-9]+" -- run "$SRC/assets/argon_gas.toml" --dt 0.05 --steps 400 --every 10 --quiet \
    --observables "$work/out/plain.csv"
expect "recover" 0 "recovered from a blow-up at step [0-9]+ .*back to step [0-9]+, verlet fp64 dt 0.05 -> 0.025" -- \
    run "$SRC/assets/argon_gas.toml" --dt 0.05 --steps 400 --every 10 --recover --observables "$work/out/obs.csv" \
    --state-out "$work/out/state.csv"
python3 - "$work/out/obs.csv" <<'PY' && pass || fail "recovered run: rows not one per step in order up to 400"
import csv, sys
steps = [int(r["step"]) for r in csv.DictReader(open(sys.argv[1]))]
sys.exit(0 if steps == list(range(0, 401, 10)) else 1)
PY
[ -s "$work/out/state.csv" ] && pass || fail "recovered run: no final state"
expect "headless recover" 0 "recovered from a blow-up" -- run "$SRC/assets/argon_gas.toml" --dt 0.05 --recover --headless --software-gl \
    --frames 21 --steps-per-frame 20 --size 64x64 --out "$work/out/frames"
[ -s "$work/out/frames/frame_000020.png" ] && pass || fail "recovered headless run: no last frame"

# method = "auto": a pilot study picks the integrator and says which and why; the run goes on with it.
sed -e 's/^method = .*/method = "auto"/' -e 's/^dt = .*/dt = 0.002\ntolerance = 1e-3/' "$SRC/assets/argon_gas.toml" >"$work/auto.toml"
expect "method auto" 0 "integrator auto \(energy error <= 0.001 per unit time\): [a-z0-9_]+ fp64 dt = [0-9.e-]+, .*the fastest of [0-9]+ pilot runs" -- \
    run "$work/auto.toml" --steps 20 --every 10 --observables "$work/out/auto.csv"
# ... or from a study file of the scene, without a pilot: its cheapest run that meets the tolerance.
expect "method auto from a study" 0 "integrator auto \(energy error <= 0.001 per unit time\): [a-z0-9_]+ fp(32|64) dt = [0-9.e-]+ from the study .*study_argon_gas_cpu.json" -- \
    run "$work/auto.toml" --study "$SRC/docs/results/study_argon_gas_cpu.json" --steps 20 --every 10 --observables "$work/out/auto2.csv"

# An output that fails during the run (a script's screenshot into a missing directory): exit 2,
# the path named.
printf '2 screenshot %s\n' "$work/missing_dir/shot.png" >"$work/shot.script"
expect "unwritable screenshot" 2 "cannot write '$work/missing_dir/shot.png'" -- \
    run "$SRC/assets/hard_spheres.toml" --headless --software-gl --frames 3 --steps-per-frame 2 --size 64x64 \
    --out "$work/out/shots" --script "$work/shot.script"

# A frame-rate run: every frame rendered, no PNG written, the rate reported; --screenshot still works.
expect "headless without PNG" 0 "4 frames rendered, no PNG written: [0-9.]+ frames/s" -- \
    run "$SRC/assets/hard_spheres.toml" --headless --software-gl --frames 4 --steps-per-frame 2 --size 64x64 \
    --out "$work/out/nopng" --no-png --screenshot "$work/out/nopng_last.png"
if ls "$work/out/nopng"/frame_*.png >/dev/null 2>&1; then fail "--no-png wrote frames"; else pass; fi
[ -s "$work/out/nopng_last.png" ] && pass || fail "--no-png lost the screenshot"

# Issue 11, never a crash: values that pass "> 0" but overflow (inf, products beyond the precision)
# and scenes too large for the machine are input errors naming the key and the size, exit 2.
rm -rf "$work/out" && mkdir -p "$work/out"
expect "dt inf" 2 "--dt: must be a finite number" -- run "$work/good.toml" --dt inf --observables "$work/out/o.csv"
scene eps_huge.toml "$(sed 's/radius = 0.5/radius = 0.5\nepsilon = 1e300/' <<<"$base")"
expect "epsilon 1e300" 2 "eps_huge.toml:9: species\[0\].epsilon: epsilon is 1e\+300, beyond what fp64" -- run "$work/eps_huge.toml" --steps 5
scene gravity_huge.toml "$base
[interaction]
gravity = [0, 0, -1e308]"
expect "gravity 1e308" 2 "interaction.gravity: \|g\| is 1e\+308" -- run "$work/gravity_huge.toml" --steps 5
scene temperature_huge.toml "$base
[init]
temperature = 1e308"
expect "temperature 1e308" 2 "init.temperature: kT is 1e\+308" -- run "$work/temperature_huge.toml" --steps 5
scene tiny_mass.toml "$(sed 's/mass = 1.0/mass = 1e-40/' <<<"$base")"
expect "mass 1e-40 in fp32" 2 "species\[0\].mass: the mass is 1e-40, beyond what fp32" -- run "$work/tiny_mass.toml" --precision fp32 --steps 5
scene huge_count.toml "$(sed -e 's/count = 20/count = 100000000000000/' -e 's/size = \[10, 10, 10\]/size = [1e6, 1e6, 1e6]/' <<<"$base")"
expect "huge count" 2 "species: 100000000000000 particles need about .* of memory .* this machine has" -- run "$work/huge_count.toml" --steps 5
scene long_box.toml "$(sed 's/size = \[10, 10, 10\]/size = [1e18, 10, 10]/' <<<"$base")"
expect "very long box" 2 "sites of the lattice placement" -- run "$work/long_box.toml" --steps 5
expect "video with an unknown extension" 2 "--video: '$work/out/v.xyz' has the extension .xyz" -- \
    run "$work/good.toml" --headless --software-gl --frames 3 --size 64x64 --out "$work/out/f" --video "$work/out/v.xyz"
no_outputs "refused runs"

# Never damage what is at an output path: links followed, devices and FIFOs streamed to, a directory
# refused before the run, an output that is an input (or another output) refused.
rm -rf "$work/out" && mkdir -p "$work/out/real"
echo old >"$work/out/real/obs.csv"
ln -s real/obs.csv "$work/out/link.csv"
"$COREBOX" run "$work/good.toml" --steps 5 --every 1 --observables "$work/out/link.csv" --quiet 2>/dev/null \
    && [ -L "$work/out/link.csv" ] && [ "$(wc -l <"$work/out/real/obs.csv")" -eq 7 ] && pass || fail "observables through a symbolic link"
"$COREBOX" run "$work/good.toml" --steps 5 --observables /dev/null --state-out /dev/null --quiet 2>/dev/null \
    && [ -c /dev/null ] && pass || fail "observables to /dev/null"
mkfifo "$work/out/fifo"
cat "$work/out/fifo" >"$work/out/from_fifo" &
reader=$!
"$COREBOX" run "$work/good.toml" --steps 5 --every 1 --observables "$work/out/fifo" --quiet 2>/dev/null && pass || fail "observables to a FIFO"
wait $reader
[ -p "$work/out/fifo" ] && [ "$(wc -l <"$work/out/from_fifo")" -eq 7 ] && pass || fail "FIFO replaced or rows lost"
cp "$work/good.toml" "$work/out/scene.toml"
expect "observables over the scene" 2 "--observables: '$work/out/scene.toml' is this run's scene" -- \
    run "$work/out/scene.toml" --observables "$work/out/scene.toml"
cmp -s "$work/good.toml" "$work/out/scene.toml" && pass || fail "the input scene was changed"
expect "state over the particles file" 2 "--state-out: .* is this run's init.particles file" -- \
    run "$work/overlap.toml" --state-out "$work/overlap.csv"
expect "two outputs, one file" 2 "--state-out and --observables both name" -- \
    run "$work/good.toml" --observables "$work/out/o.csv" --state-out "$work/out/./o.csv"
expect "directory as output" 2 "--observables: '$work/out/real' is a directory" -- run "$work/good.toml" --steps 100000 --observables "$work/out/real"

# Write errors are errors: a full device and a closed pipe on stdout exit non-zero with a message.
expect "observables to /dev/full" 2 "cannot write '/dev/full': No space left on device" -- run "$work/good.toml" --steps 5 --observables /dev/full
err=$("$COREBOX" run "$work/good.toml" --steps 20000 --every 1 2>&1 >/dev/full)
[ $? -eq 2 ] && grep -q "cannot write the observables to stdout: No space left" <<<"$err" && pass || fail "stdout on /dev/full: $err"
"$COREBOX" run "$work/good.toml" --steps 20000 --every 1 2>"$work/err" | head -2 >/dev/null
rc=${PIPESTATUS[0]}
[ "$rc" -eq 2 ] && grep -q "cannot write the observables to stdout: Broken pipe" "$work/err" && pass || fail "closed stdout pipe: exit $rc, $(cat "$work/err")"

# Interruption loses nothing: SIGINT and SIGTERM after a few rows (waited for, not timed) finish the
# step, commit the observables (complete rows up to the current step), write the state, exit 128 +
# signal and leave no temporary; a second signal exits at once and still removes the temporaries.
wait_rows() {  # wait_rows FILE_GLOB N: until a file matching the glob has N lines (at most ~60 s)
    for _ in $(seq 600); do
        for f in $1; do [ -e "$f" ] && [ "$(wc -l <"$f")" -ge "$2" ] && return 0; done
        sleep 0.1
    done
    return 1
}
for sig in INT TERM; do
    code=$([ $sig = INT ] && echo 130 || echo 143)
    rm -rf "$work/out" && mkdir -p "$work/out"
    "$COREBOX" run "$SRC/assets/argon_gas.toml" --steps 100000000 --every 5 --observables "$work/out/obs.csv" --quiet 2>"$work/err" &
    pid=$!
    wait_rows "$work/out/obs.csv.tmp-*" 4 || fail "batch SIG$sig: no rows appeared"
    kill -$sig $pid
    wait $pid
    rc=$?
    [ "$rc" -eq "$code" ] && pass || fail "batch SIG$sig: exit $rc, expected $code: $(cat "$work/err")"
    grep -q "SIG$sig: stopped after step [0-9]*.*observables in $work/out/obs.csv, state in $work/out/interrupted_state.csv" "$work/err" \
        && pass || fail "batch SIG$sig message: $(cat "$work/err")"
    last=$(tail -1 "$work/out/obs.csv" | cut -d, -f1)
    stopped=$(sed -n 's/.*stopped after step \([0-9]*\).*/\1/p' "$work/err")
    [ -n "$last" ] && [ "$last" = "$stopped" ] && pass || fail "batch SIG$sig: last row at step '$last', stopped at '$stopped'"
    python3 -c "import csv,sys; rows=list(csv.reader(open(sys.argv[1]))); assert all(len(r)==len(rows[0]) for r in rows)" "$work/out/obs.csv" \
        && pass || fail "batch SIG$sig: ragged observables"
    [ "$(wc -l <"$work/out/interrupted_state.csv")" -eq 513 ] && pass || fail "batch SIG$sig: state incomplete"
    ls "$work/out" | grep -q tmp- && fail "batch SIG$sig: temporaries left: $(ls "$work/out")" || pass
done
rm -rf "$work/out" && mkdir -p "$work/out"
"$COREBOX" run "$SRC/assets/argon_gas.toml" --steps 100000000 --every 5 --observables "$work/out/obs.csv" --state-out "$work/out/s.csv" --quiet 2>/dev/null &
pid=$!
wait_rows "$work/out/obs.csv.tmp-*" 4 || fail "second signal: no rows appeared"
kill -STOP $pid; kill -INT $pid; kill -TERM $pid; kill -CONT $pid
wait $pid
rc=$?
# Both arrive at once on SIGCONT, in an order the kernel picks: either exit code is the second's.
{ [ "$rc" -eq 143 ] || [ "$rc" -eq 130 ]; } && pass || fail "second signal: exit $rc, expected 130 or 143"
[ -z "$(ls -A "$work/out")" ] && pass || fail "second signal left files: $(ls "$work/out")"
# Headless with a video: frames complete, the video closed and playable, no temporaries.
for sig in INT TERM; do
    code=$([ $sig = INT ] && echo 130 || echo 143)
    rm -rf "$work/out" && mkdir -p "$work/out"
    "$COREBOX" run "$SRC/assets/argon_gas.toml" --headless --software-gl --frames 1000000 --steps-per-frame 2 --size 64x64 \
        --out "$work/out/f" --video "$work/out/v.mp4" --quiet 2>"$work/err" &
    pid=$!
    for _ in $(seq 600); do [ -e "$work/out/f/frame_000003.png" ] && break; sleep 0.1; done
    kill -$sig $pid
    wait $pid
    rc=$?
    [ "$rc" -eq "$code" ] && pass || fail "headless SIG$sig: exit $rc, expected $code: $(cat "$work/err")"
    frames=$(ls "$work/out/f" | grep -c '^frame_.*\.png$')
    ffprobe -v error "$work/out/f/frame_$(printf %06d $((frames - 1))).png" >/dev/null 2>&1 \
        && pass || fail "headless SIG$sig: last frame unreadable"
    [ -s "$work/out/f/observables.csv" ] && [ -s "$work/out/f/interrupted_state.csv" ] && [ -s "$work/out/v.mp4" ] \
        && pass || fail "headless SIG$sig: outputs missing: $(ls "$work/out" "$work/out/f" | tr '\n' ' ')"
    n=$(ffprobe -v error -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$work/out/v.mp4" 2>/dev/null)
    [ "$n" = "$frames" ] && pass || fail "headless SIG$sig: video has '$n' frames, $frames PNGs"
    find "$work/out" -name '*tmp-*' | grep -q . && fail "headless SIG$sig: temporaries left" || pass
done

# `corebox bench pile` on a tiny pile (200 balls, 0.2 s): CSV and JSON written with their columns and
# keys, one corebox row per precision and a Bullet row where the driver was built, whatever the runs'
# outcome (a blow-up is a recorded result, not an exit code 3); with --trace, a CSV per corebox run
# with a row per frame (0.2 s: 12 frames), each frame's impact rounds at least its 4 steps.
rm -rf "$work/out" && mkdir -p "$work/out"
pile="$work/out/pile"
if "$COREBOX" bench pile --n 200 --seconds 0.2 --precision fp32,fp64 --out "$pile" --trace "$pile-trace" >/dev/null 2>"$work/err"; then
    pass
    trace_columns='frame,time,ms_frame,kinetic,rounds,max_rounds,round_cap_hits,listings,sweeps,contacts_max,'
    trace_columns+='overlap_left_max,ms_impacts,ms_contacts,ms_listings'
    for precision in fp32 fp64; do
        trace="$pile-trace_cpu_${precision}_200.csv"
        [ "$(sed -n 2p "$trace" 2>/dev/null)" = "$trace_columns" ] && pass || fail "pile trace $precision header: $(sed -n 2p "$trace" 2>/dev/null)"
        frames=$(tail -n +3 "$trace" | awk -F, '$1 == NR - 1 && $5 >= 4' | wc -l)
        [ "$frames" -eq 12 ] && pass || fail "pile trace $precision: $frames frames of 12 numbered with 4 or more rounds"
    done
    columns='engine,backend,device,precision,threads,n,box_x,box_y,box_z,box_grown,substeps,dt,seconds_requested,'
    columns+='seconds_simulated,frames,ms_per_frame_mean,ms_per_frame_last_second,ms_per_frame_max,max_overlap_fraction,'
    columns+='max_wall_penetration_fraction,outside,energy_start,energy_end,energy_change_relative,potential_released,'
    columns+='dissipated,time_to_rest,round_cap_hits,max_rounds,mean_rounds,mean_contact_sweeps,mean_listings,'
    columns+='contact_sweeps_cap,capped_speed_per_step,capped_overlap_per_step,jacobi_listings_per_step,'
    columns+='collide_share,impact_share,contact_share,listing_share,final_state,outcome,message'
    head -1 "$pile.csv" | grep -q '^# corebox bench pile --n 200' && pass || fail "pile CSV does not start with the command"
    [ "$(sed -n 2p "$pile.csv")" = "$columns" ] && pass || fail "pile CSV header: $(sed -n 2p "$pile.csv")"
    corebox_rows=$(grep -cE '^corebox,cpu,.*,(fp32|fp64),[0-9]+,200,' "$pile.csv")
    [ "$corebox_rows" -eq 2 ] && pass || fail "pile CSV: $corebox_rows corebox rows, expected one per precision"
    bullet_rows=$(grep -c '^bullet,' "$pile.csv")
    if [ -x "$(dirname "$COREBOX")/corebox_bullet_pile" ]; then expected_bullet=1; else expected_bullet=0; fi
    [ "$bullet_rows" -eq "$expected_bullet" ] && pass || fail "pile CSV: $bullet_rows Bullet rows, expected $expected_bullet"
    if python3 - "$pile.json" "$expected_bullet" <<'PY'
import json, sys
data = json.load(open(sys.argv[1]))
assert data["benchmark"] == "pile" and data["command"].startswith("corebox bench pile"), "benchmark, command"
assert {"cpu", "hardware_threads"} <= data["host"].keys() and data["device"], "host, device"
assert data["scene"]["box"] == [30, 30, 60] and data["scene"]["restitution"] == 0.5, "scene"
keys = {"engine", "backend", "precision", "n", "box", "ms_per_frame_mean", "ms_per_frame_last_second",
        "max_overlap_fraction", "outside", "energy_start", "energy_end", "energy_change_relative", "time_to_rest",
        "round_cap_hits", "outcome", "message"}
for r in data["results"]:
    assert keys <= r.keys(), f"result keys missing: {keys - r.keys()}"
    assert r["outcome"] in ("ok", "instability", "device_error", "error"), r["outcome"]
corebox = [r for r in data["results"] if r["engine"] == "corebox"]
assert sorted(r["precision"] for r in corebox) == ["fp32", "fp64"], "corebox runs"
assert all(r["n"] == 200 for r in corebox), "corebox sizes"
assert all(r["round_cap"] == 64 for r in corebox), "round cap: the scene's own"
assert len([r for r in data["results"] if r["engine"] == "bullet"]) == int(sys.argv[2]), "bullet runs"
assert len(data["targets"]) >= 2, "targets"
PY
    then pass; else fail "pile JSON"; fi
else
    fail "bench pile failed: $(cat "$work/err")"
fi
expect "bench pile: missing Bullet driver" 2 "--bullet: no program at '$work/none'" -- \
    bench pile --n 200 --seconds 0.1 --bullet "$work/none"
expect "bench pile: zero balls" 2 "--n" -- bench pile --n 0 --seconds 0.1
expect "bench pile: negative round cap" 2 "--max-rounds" -- bench pile --n 200 --seconds 0.1 --max-rounds -1

# Numbers that do not fit, thread counts above the cores, options that a batch run cannot honour,
# --headless without --frames, and --quiet.
scene guards.toml "$base"
expect "steps beyond 64 bits" 2 "--steps: value 99999999999999999999 is out of the range of a 64-bit integer" -- \
    run "$work/guards.toml" --steps 99999999999999999999 --observables /dev/null
expect "seed beyond 64 bits" 2 "--seed: value 99999999999999999999 is out of the range" -- \
    run "$work/guards.toml" --seed 99999999999999999999 --observables /dev/null
expect "bench sizes beyond 64 bits" 2 "--n: value 99999999999999999999999 is out of the range" -- \
    bench forces --n 99999999999999999999999
expect "frame size that wraps" 2 "--size: expected WIDTHxHEIGHT with each between 16 and 16384, got '4294967312x720'" -- \
    run "$work/guards.toml" --headless --frames 1 --out "$work/frames" --size 4294967312x720
expect "headless without --frames" 2 "--headless needs --frames N" -- run "$work/guards.toml" --headless --out "$work/frames"
expect "threads above the cores" 0 "warning: --threads 100000 is more than the [0-9]+ hardware threads here; using [0-9]+" -- \
    run "$work/guards.toml" --steps 2 --threads 100000 --no-window --observables /dev/null
expect "script in a batch run" 0 "warning: --script is ignored in a batch run \(--no-window\)" -- \
    run "$work/guards.toml" --steps 2 --no-window --script /dev/null --observables /dev/null
quiet_err=$("$COREBOX" run "$work/guards.toml" --steps 2 --no-window --quiet --observables /dev/null 2>&1 >/dev/null)
[ -z "$quiet_err" ] && pass || fail "--quiet still printed: $quiet_err"

# Checkpoint and restart: a run stopped at a checkpoint and restarted ends in the same state, bit for
# bit, with the same observables rows after the checkpoint; the previous checkpoint is kept as .prev.
ckscene="$SRC/assets/binary_mixture.toml"
"$COREBOX" run "$ckscene" --steps 120 --every 40 --observables "$work/ck_whole.csv" --state-out "$work/ck_whole_state.csv" --quiet
"$COREBOX" run "$ckscene" --steps 90 --every 40 --observables "$work/ck_a.csv" --checkpoint "$work/ck.bin" --checkpoint-every 40 --quiet
[ -f "$work/ck.bin" ] && [ -f "$work/ck.bin.prev" ] && pass || fail "checkpoint and its .prev not written"
if "$COREBOX" run --restart "$work/ck.bin" --steps 120 --every 40 --observables "$work/ck_b.csv" \
    --state-out "$work/ck_restarted_state.csv" --checkpoint "$work/ck.bin" --quiet; then
    cmp -s "$work/ck_whole_state.csv" "$work/ck_restarted_state.csv" && pass || fail "restarted state differs from the uninterrupted one"
    [ "$(grep -E '^120,' "$work/ck_whole.csv")" = "$(grep -E '^120,' "$work/ck_b.csv")" ] && pass ||
        fail "row 120 differs: $(grep -E '^120,' "$work/ck_whole.csv") vs $(grep -E '^120,' "$work/ck_b.csv")"
    grep -qE '^(0|40|80),' "$work/ck_b.csv" && fail "the restarted run repeated rows before its checkpoint" || pass
else
    fail "restart failed"
fi
expect "restart with a scene too" 2 "--restart: the checkpoint holds the scene" -- run "$ckscene" --restart "$work/ck.bin"
expect "restart with --dt" 2 "--restart: --precision, --method, --dt and --seed" -- run --restart "$work/ck.bin" --dt 0.001
expect "restart from a scene file" 2 "not a corebox checkpoint" -- run --restart "$ckscene" --steps 10
head -c 2000 "$work/ck.bin" >"$work/ck_truncated.bin"
expect "restart from a truncated checkpoint" 2 "truncated" -- run --restart "$work/ck_truncated.bin" --steps 200
expect "restart beyond --steps" 2 "the checkpoint is at step 120, beyond --steps 50" -- run --restart "$work/ck.bin" --steps 50 --observables /dev/null
expect "run without a scene" 2 "give a SCENE file" -- run --steps 5

# `corebox bench p2p` and `corebox bench table1` where GPUs are missing: exit 4 (device error) with a
# message naming what is missing. Where nvidia-smi lists GPUs, only what that count still lacks is
# checked (p2p needs two, table1 one). Option errors come first and exit 2 on any machine.
gpus=$(nvidia-smi -L 2>/dev/null | grep -c '^GPU' || true)
if [ "${gpus:-0}" -lt 2 ]; then
    expect "bench p2p without 2 GPUs" 4 "device error: bench p2p needs at least 2 CUDA devices; (found|this build)" -- \
        bench p2p --max-bytes 8KiB --repeats 1
fi
if [ "${gpus:-0}" -eq 0 ]; then
    expect "bench table1 without a GPU" 4 "device error: bench table1 needs a CUDA device; (found none|this build)" -- \
        bench table1 --sizes 1024 --gpus-list 1
fi
# `corebox run` asking for more GPUs than exist: exit 4 naming what was found (none here, or the
# devices CUDA sees where nvidia-smi lists some; CUDA may see fewer, so no count is assumed).
if [ "${gpus:-0}" -eq 0 ]; then
    expect "run on GPUs without one" 4 "device error: (no CUDA device found|--backend cuda: this build)" -- run "$work/good.toml" --backend cuda --gpus 2 --steps 1
else
    expect "run on more GPUs than exist" 4 "device error: [0-9]+ GPU\(s\) asked for from device 0, but only devices 0 \.\. [0-9]+ exist \([0-9]+ found: " -- \
        run "$work/good.toml" --backend cuda --gpus $((gpus + 1)) --steps 1
fi
expect "bench p2p: auto is not a method" 2 "--methods: 'auto' is not a transfer method" -- bench p2p --methods dts,auto
expect "bench p2p: max below min" 2 "--max-bytes: 1024 is below --min-bytes 4096" -- bench p2p --max-bytes 1KiB
expect "bench table1: auto is not an exchange" 2 "--exchanges: name the methods" -- bench table1 --exchanges auto
"$COREBOX" bench p2p --help | grep -q -- "--max-bytes" && pass || fail "bench p2p --help does not list --max-bytes"
"$COREBOX" bench table1 --help | grep -q -- "--gpus-list" && pass || fail "bench table1 --help does not list --gpus-list"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
