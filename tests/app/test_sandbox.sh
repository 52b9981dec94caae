#!/usr/bin/env bash
# The sandbox example (examples/sandbox.cpp) under Xvfb with its built-in scripted session: exit 0, a
# screenshot with balls and the HUD text, a --stats JSON with every field and bookkeeping that adds up
# (balls at the end = start + spawned + fired - removed), multisampling off on the software renderer
# (--samples auto) and frames pipelined (the step on a worker thread while the frame before is drawn).
# Then the same session headless and --sequential (EGL on Mesa's software renderer, a smaller frame of
# the same aspect, so the clicks pick the same points): the same state hash, as a fixed-step loop must
# give whatever the frame rate and whichever thread steps the world (both on 2 world threads: the World
# promises the same bits for the same thread count). Then bad options and scripts: exit 2 and a message naming the culprit. Needs SANDBOX and SRC.
set -u
: "${SANDBOX:?}" "${SRC:?}"
if ! command -v xvfb-run >/dev/null; then echo "xvfb-run not installed: sandbox test skipped"; exit 77; fi
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

# check_json FILE FRAMES HEADLESS PIPELINED: every field, summaries that make sense, bookkeeping that
# adds up, no multisampling (llvmpipe, --samples auto).
check_json() {
    python3 - "$@" <<'PY'
import json, math, sys
path, frames, headless, pipelined = sys.argv[1], int(sys.argv[2]), sys.argv[3] == "true", sys.argv[4] == "true"
d = json.load(open(path))
problems = []
for key in ["command_line", "backend", "backend_name", "precision", "cpu", "gpu", "gl_renderer", "headless", "frames",
            "frames_measured", "n_start", "n_end", "spawned", "spawn_refused", "removed", "fired", "flashes",
            "substeps", "simulated_time", "state_hash", "sim_ms", "render_ms", "wait_ms", "frame_ms", "fps_mean",
            "samples", "pipelined", "impacts_ms", "contacts_ms", "listings_ms", "kinetic_per_ball_end",
            "max_overlap_end"]:
    if key not in d:
        problems.append("no field " + key)
for key in ["sim_ms", "render_ms", "wait_ms", "frame_ms", "impacts_ms", "contacts_ms", "listings_ms"]:
    s = d.get(key, {})
    values = [s.get(k) for k in ("mean", "median", "p95", "max")]
    if not all(isinstance(v, (int, float)) and math.isfinite(v) and v >= 0 for v in values):
        problems.append(f"{key}: {s}")
    elif not s["median"] <= s["p95"] <= s["max"]:
        problems.append(f"{key}: median <= p95 <= max fails: {s}")
# The collision stage is part of the step, the contact lists part of the contact phase (means: the
# sums over the same frames); a pile on the floor lists contacts.
if all(isinstance(d.get(k), dict) for k in ["sim_ms", "impacts_ms", "contacts_ms", "listings_ms"]):
    if not d["impacts_ms"]["mean"] + d["contacts_ms"]["mean"] <= d["sim_ms"]["mean"]:
        problems.append(f"impacts + contacts above the step: {d['impacts_ms']} {d['contacts_ms']} {d['sim_ms']}")
    if not 0 < d["listings_ms"]["mean"] <= d["contacts_ms"]["mean"]:
        problems.append(f"contact lists: {d['listings_ms']} of {d['contacts_ms']}")
# Every frame's figures, the skipped first ones too, each within what the summaries say of the rest.
for key in ["frame", "sim", "impacts", "contacts", "render"]:
    values = d.get(f"per_frame_{key}_ms")
    if not isinstance(values, list) or len(values) != frames:
        problems.append(f"per_frame_{key}_ms: {len(values) if isinstance(values, list) else values} values for {frames} frames")
    elif isinstance(d.get(f"{key}_ms"), dict) and d[f"{key}_ms"].get("max") is not None and \
            max(values[10:]) > d[f"{key}_ms"]["max"] + 1e-3:
        problems.append(f"per_frame_{key}_ms: {max(values[10:])} above the summary's max {d[f'{key}_ms']['max']}")
# The balls at the end: overlaps (cores and walls) within 1% of a contact distance, as issue 9's piles.
overlap, kinetic = d.get("max_overlap_end"), d.get("kinetic_per_ball_end")
if not (isinstance(overlap, (int, float)) and 0 <= overlap < 0.01):
    problems.append(f"max_overlap_end {overlap}: not within 1% of a contact distance")
if not (isinstance(kinetic, (int, float)) and math.isfinite(kinetic) and kinetic >= 0):
    problems.append(f"kinetic_per_ball_end {kinetic}")
if d.get("frames") != frames or d.get("frames_measured") != frames - 10:
    problems.append(f"frames {d.get('frames')}, measured {d.get('frames_measured')}")
if d.get("backend") != "cpu" or d.get("precision") != "fp64" or d.get("headless") != headless:
    problems.append(f"setup: {d.get('backend')} {d.get('precision')} headless {d.get('headless')}")
if d.get("pipelined") != pipelined or d.get("samples") != 0:
    problems.append(f"pipelined {d.get('pipelined')} (expected {pipelined}), samples {d.get('samples')} (expected 0 on llvmpipe)")
if not pipelined and d.get("wait_ms", {}).get("max") != 0:
    problems.append(f"sequential frames waited for a worker: {d.get('wait_ms')}")
if "--scripted" not in d.get("command_line", ""):
    problems.append("command line: " + d.get("command_line", ""))
if d.get("n_start") != 500 or d.get("spawned", 0) <= 0 or d.get("removed", 0) <= 0 or d.get("fired") != 2:
    problems.append(f"session: start {d.get('n_start')}, spawned {d.get('spawned')}, removed {d.get('removed')}, fired {d.get('fired')}")
if d.get("n_end") != d.get("n_start", 0) + d.get("spawned", 0) + d.get("fired", 0) - d.get("removed", 0):
    problems.append(f"n_end {d.get('n_end')} != start + spawned + fired - removed")
if d.get("substeps") != 4 * frames or abs(d.get("simulated_time", 0) - frames / 60) > 1e-9:
    problems.append(f"not fixed-step: {d.get('substeps')} substeps, t = {d.get('simulated_time')}")
if d.get("flashes", 0) <= 0:
    problems.append("no impact flashed")
for p in problems:
    print(p)
sys.exit(1 if problems else 0)
PY
}

# ---- the window under Xvfb ---------------------------------------------------------------------------
timeout 300 xvfb-run -a -s "-screen 0 1600x900x24" "$SANDBOX" --scripted --frames 120 --balls 500 --threads 2 \
    --screenshot "$work/s.png" --stats "$work/s.json" >"$work/out" 2>"$work/err"
rc=$?
[ $rc -eq 0 ] && pass || fail "window run exit $rc: $(tail -5 "$work/err")"
if [ -s "$work/s.png" ]; then
    read -r size _ < <(stats "$work/s.png" 0 0 1 1 any)
    [ "$size" = "1280x720" ] && pass || fail "screenshot is $size"
    above "$(fraction "$work/s.png" 0.25 0.1 0.75 0.95 any)" 0.03 && pass || fail "blank screenshot: nothing in the box"
    above "$(fraction "$work/s.png" 0.25 0.1 0.75 0.95 red)" 0.005 && pass || fail "no red balls in the screenshot"
    # The HUD's text (light grey, top left).
    above "$(fraction "$work/s.png" 0 0 0.5 0.22 any)" 0.01 && pass || fail "no HUD text in the top left"
else
    fail "no screenshot written"
fi
if [ -s "$work/s.json" ]; then
    out=$(check_json "$work/s.json" 120 false true) && pass || fail "stats JSON: $out"
else
    fail "no stats JSON written"
fi
grep -q "^\[sandbox\] frame [0-9]*, t [0-9.]*: [0-9]* frames, [0-9.]* fps; sim [0-9.]* ms" "$work/err" && pass ||
    fail "no per-second summary on stderr: $(head -3 "$work/err")"
grep -q "frame 30 (built-in): fire -> heavy ball from" "$work/err" && pass || fail "no shot at frame 30: $(grep fire "$work/err")"
# On llvmpipe: no multisampling and flat sphere depth (--depth auto), the game's solver budget, unpaced.
grep -q "no multisampling, flat depth; pipelined frames" "$work/err" && pass || fail "no setup line: $(grep 'drawing with' "$work/err")"
python3 - "$work/s.json" <<'PY' && pass || fail "window stats: depth, pacing or solver caps not as set"
import json, sys
d = json.load(open(sys.argv[1]))
want = {"exact_depth": False, "paced_hz": 0, "impact_rounds": 16, "contact_sweeps": 8, "contact_listings": 2}
bad = {k: d.get(k) for k, v in want.items() if d.get(k) != v}
if bad:
    print(bad)
sys.exit(1 if bad else 0)
PY

# ---- the same session headless, sequential and paced at 60 Hz, with exact depth: the same state ----------
env -u DISPLAY -u WAYLAND_DISPLAY timeout 300 "$SANDBOX" --headless --software-gl --sequential --scripted --frames 120 --balls 500 --threads 2 --size 640x360 \
    --pace 60 --depth exact --screenshot "$work/h.png" --stats "$work/h.json" >"$work/hout" 2>"$work/herr"
rc=$?
[ $rc -eq 0 ] && pass || fail "headless run exit $rc: $(tail -5 "$work/herr")"
if [ -s "$work/h.png" ]; then
    above "$(fraction "$work/h.png" 0.25 0.1 0.75 0.95 red)" 0.005 && pass || fail "no red balls in the headless frame"
else
    fail "no headless screenshot written"
fi
if [ -s "$work/h.json" ]; then
    out=$(check_json "$work/h.json" 120 true false) && pass || fail "headless stats JSON: $out"
    python3 - "$work/s.json" "$work/h.json" <<'PY' && pass || fail "window and headless sessions differ (fixed step, same inputs; pipelined and sequential)"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
sys.exit(0 if a["state_hash"] == b["state_hash"] and a["n_end"] == b["n_end"] else 1)
PY
    # Paced: the loop waits for each refresh, so 120 frames take at least 119 periods. A lower bound only:
    # frames start on absolute grid points and sleep_until never returns early, so a slow or loaded host
    # can only lengthen the run.
    python3 - "$work/h.json" <<'PY' && pass || fail "headless stats: not paced at 60 Hz with exact depth"
import json, sys
d = json.load(open(sys.argv[1]))
ok = d.get("paced_hz") == 60 and d.get("exact_depth") is True and d.get("wall_s", 0) >= 119 / 60
if not ok:
    print(d.get("paced_hz"), d.get("exact_depth"), d.get("wall_s"))
sys.exit(0 if ok else 1)
PY
fi

# ---- bad options and scripts: exit 2, a message naming the culprit, no window needed ----------------
bad() {  # bad NAME PATTERN ARGS...
    local name=$1 pattern=$2
    shift 2
    local err rc
    err=$(env -u DISPLAY -u WAYLAND_DISPLAY timeout 60 "$SANDBOX" "$@" 2>&1 >/dev/null)
    rc=$?
    if [ $rc -ne 2 ]; then fail "$name: exit $rc, expected 2: $err"; return; fi
    grep -q -- "$pattern" <<<"$err" && pass || fail "$name: message lacks '$pattern': $err"
}
bad "unknown backend" "--backend" --backend gpu
bad "negative balls" "--balls" --balls -3
bad "zero frames" "--frames" --frames 0
bad "unknown option" "--bogus" --bogus
bad "unknown depth" "--depth" --depth deep
bad "negative pace" "--pace" --pace -60
bad "too many listings" "--contact-listings" --contact-listings 33
bad "too many balls" "at most" --headless --balls 10000000
bad "too many samples" "--samples: at most 16" --headless --samples 32
bad "negative contact sweeps" "--contact-sweeps" --headless --contact-sweeps -2
bad "negative impact rounds" "--impact-rounds" --headless --impact-rounds -1
bad "impact rounds past int" "--impact-rounds: at most 4096" --headless --impact-rounds 4294967297
bad "size past the limit" "--size width: at most 8192" --headless --size 9000x600
bad "heavy ball too large" "--heavy-radius" --headless --heavy-radius 9
bad "samples not a number" "--samples" --headless --samples many
bad "missing script" "cannot open" --headless --script "$work/none.script"
printf '10 click 0.5 0.5\n20 jump\n' >"$work/bad.script"
bad "bad script command" "bad.script:2: unknown command 'jump'" --headless --script "$work/bad.script"
printf '10 click 1.5 0.5\n' >"$work/range.script"
bad "click outside the window" "range.script:1: click needs U V" --headless --script "$work/range.script"
"$SANDBOX" --help | grep -q -- "--stats FILE.json" && pass || fail "--help does not list --stats"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
