#!/usr/bin/env bash
# The window app under Xvfb running a script that raises the temperature, switches rk4 to verlet,
# takes a screenshot and quits: exit code 0, a screenshot showing particles and the panel, and
# observables with the temperature rising and the switch at the scripted step. Then the same script
# headless with --hud: the histogram is drawn into the frame. Then a scripted dt jump that blows the
# window's run up: recovered, and the observables go on. Needs COREBOX and SRC.
set -u
: "${COREBOX:?}" "${SRC:?}"
if ! command -v xvfb-run >/dev/null; then echo "xvfb-run not installed: window test skipped"; exit 77; fi
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
export XDG_CONFIG_HOME="$work/config"

cat >"$work/demo.script" <<SCRIPT
# rk4 is the scene's method; raise T, switch to verlet, take a picture, quit
20 set temperature 3.0
40 set method verlet
60 screenshot $work/window.png
60 quit
SCRIPT

scene="$SRC/assets/binary_mixture.toml"
grep -q 'method = "rk4"' "$scene" || fail "the scene no longer starts with rk4"

timeout 300 xvfb-run -a -s "-screen 0 1600x900x24" "$COREBOX" run "$scene" --script "$work/demo.script" --frames 500 \
    --observables "$work/window.csv" >"$work/out" 2>"$work/err"
rc=$?
if [ $rc -ne 0 ]; then fail "window run exit $rc: $(tail -5 "$work/err")"; else pass; fi
grep -q "script step 40: set method verlet" "$work/err" && pass || fail "no method switch at step 40 in the log"
grep -q "script step 20: set temperature 3.0" "$work/err" && pass || fail "no temperature change at step 20 in the log"
if [ -s "$work/window.png" ]; then
    read -r size _ < <(stats "$work/window.png" 0 0 1 1 any)
    [ "$size" = "1600x900" ] && pass || fail "screenshot is $size"
    # The panel (top left): ImGui's dark blue widgets.
    above "$(fraction "$work/window.png" 0 0 0.2 0.45 panel)" 0.2 && pass || fail "no panel in the top left of the screenshot"
    # The particles (centre): the red species.
    above "$(fraction "$work/window.png" 0.3 0.2 0.7 0.8 red)" 0.05 && pass || fail "no particles in the centre of the screenshot"
    # The histogram window (top right): white MB curves and labels.
    above "$(fraction "$work/window.png" 0.75 0.05 0.98 0.5 white)" 0.002 && pass || fail "no histogram curves in the screenshot"
else
    fail "no screenshot written"
fi
# Observables: rows up to the quit, temperature rising after the scripted change.
last=$(tail -1 "$work/window.csv" | cut -d, -f1)
[ "$last" -ge 60 ] 2>/dev/null && pass || fail "observables end at step '$last'"
python3 - "$work/window.csv" <<'PY' && pass || fail "temperature did not rise after step 20"
import csv, sys
rows = {int(r["step"]): float(r["temperature"]) for r in csv.DictReader(open(sys.argv[1]))}
sys.exit(0 if rows[60] > rows[20] + 0.5 and rows[20] < 1.5 else 1)
PY

# The same script headless with the HUD: the histogram and plots are in the frame.
sed "s#$work/window.png#$work/hud.png#" "$work/demo.script" >"$work/hud.script"
"$COREBOX" run "$scene" --headless --hud --frames 40 --steps-per-frame 4 --size 1280x720 --out "$work/hud" \
    --script "$work/hud.script" --quiet 2>"$work/hud_err"
rc=$?
[ $rc -eq 0 ] && pass || fail "headless HUD run exit $rc: $(tail -3 "$work/hud_err")"
if [ -s "$work/hud.png" ]; then
    above "$(fraction "$work/hud.png" 0.68 0.05 0.98 0.6 red)" 0.02 && pass || fail "no histogram bars in the HUD frame"
    above "$(fraction "$work/hud.png" 0.68 0.05 0.98 0.6 white)" 0.002 && pass || fail "no MB curves in the HUD frame"
    # Without --hud that corner is empty background.
    "$COREBOX" run "$scene" --headless --frames 2 --size 1280x720 --out "$work/plain" --quiet 2>/dev/null
    above 0.002 "$(fraction "$work/plain/frame_000001.png" 0.75 0.05 0.98 0.6 white)" && pass || fail "white pixels in the corner without --hud"
else
    fail "no HUD screenshot written"
fi

# A scripted dt jump (25 times the preset's) blows the run up; the window goes back to its last good
# state with dt halved, says so, and the run and its observables go on to the quit, one row per step.
cat >"$work/jump.script" <<SCRIPT
30 set dt 0.05
150 quit
SCRIPT
timeout 300 xvfb-run -a -s "-screen 0 1280x720x24" "$COREBOX" run "$SRC/assets/argon_gas.toml" --script "$work/jump.script" \
    --frames 2000 --observables "$work/jump.csv" >"$work/jump_out" 2>"$work/jump_err"
rc=$?
[ $rc -eq 0 ] && pass || fail "window run with a dt jump exit $rc: $(tail -3 "$work/jump_err")"
grep -q "recovered from a blow-up at step .*dt 0.05 -> 0.025" "$work/jump_err" && pass || fail "no recovery in the log: $(grep corebox "$work/jump_err" | tail -3)"
python3 - "$work/jump.csv" <<'PY' && pass || fail "observables do not go on after the recovery"
import csv, sys
steps = [int(r["step"]) for r in csv.DictReader(open(sys.argv[1]))]
ok = steps == sorted(set(steps)) and steps[-1] >= 150 and any(s > 30 for s in steps)
sys.exit(0 if ok else 1)
PY

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
