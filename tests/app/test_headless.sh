#!/usr/bin/env bash
# Headless frame dumping through the real binary on Mesa's software EGL device: file names and sizes,
# observables identical to a run without rendering, video through ffmpeg, and bad arguments that
# exit with code 2 and leave nothing behind. Needs COREBOX and SRC in the environment.
set -u
: "${COREBOX:?}" "${SRC:?}"
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

png_size() {  # prints WIDTHxHEIGHT from a PNG's IHDR chunk
    python3 -c 'import struct,sys; d=open(sys.argv[1],"rb").read(24); assert d[:8]==b"\x89PNG\r\n\x1a\n"; print("%dx%d" % struct.unpack(">II", d[16:24]))' "$1"
}

scene="$SRC/assets/binary_mixture.toml"
if "$COREBOX" run "$scene" --headless --software-gl --frames 4 --steps-per-frame 5 --size 200x120 --out "$work/frames" \
    2>"$work/err"; then
    pass
    names=$(cd "$work/frames" && ls frame_*.png | tr '\n' ' ')
    [ "$names" = "frame_000000.png frame_000001.png frame_000002.png frame_000003.png " ] && pass || fail "frame names: $names"
    for f in "$work"/frames/frame_*.png; do
        [ "$(png_size "$f")" = "200x120" ] && pass || fail "$f is $(png_size "$f"), expected 200x120"
    done
    ls "$work/frames" | grep -q tmp && fail "temporary files left in the frame directory" || pass
    grep -q "make a video with: ffmpeg" "$work/err" && pass || fail "no hint on making a video: $(cat "$work/err")"
    # Script values the scene rules refuse change nothing and say so; the run goes on (exit 0).
    printf '1 set dt -1\n2 set mixing 0 5 1\n3 set temperature 1.2\n' >"$work/bad.script"
    if "$COREBOX" run "$scene" --headless --software-gl --frames 3 --steps-per-frame 2 --size 64x64 --out "$work/refused" \
        --script "$work/bad.script" 2>"$work/err"; then pass; else fail "refused script values ended the run: $(cat "$work/err")"; fi
    grep -q "bad.script:1: script step 1: 'set dt -1' refused, nothing changed: .*integrator.dt: must be" "$work/err" && pass ||
        fail "no refusal of set dt -1: $(cat "$work/err")"
    grep -q "bad.script:2: .*'set mixing 0 5 1' refused" "$work/err" && pass || fail "no refusal of set mixing 0 5 1: $(cat "$work/err")"
    grep -q "script step 3: set temperature 1.2" "$work/err" && pass || fail "set temperature 1.2 not applied: $(cat "$work/err")"
    # --quiet: the same run says nothing but warnings and errors.
    "$COREBOX" run "$scene" --headless --software-gl --frames 2 --steps-per-frame 5 --size 200x120 --out "$work/quiet" \
        --quiet 2>"$work/err"
    [ ! -s "$work/err" ] && pass || fail "--quiet headless run printed: $(cat "$work/err")"
    # Rendering must not change the physics: same observables as a plain run over the same steps.
    "$COREBOX" run "$scene" --steps 15 --every 5 --observables "$work/plain.csv" --quiet 2>/dev/null
    cmp -s "$work/plain.csv" "$work/frames/observables.csv" && pass || fail "observables differ from a run without rendering"
else
    fail "headless run failed: $(cat "$work/err")"
fi

# Colour by speed and a video, when ffmpeg is there.
if command -v ffmpeg >/dev/null; then
    if "$COREBOX" run "$scene" --headless --software-gl --frames 3 --steps-per-frame 2 --size 160x96 --color-by speed \
        --out "$work/speed" --video "$work/speed.mp4" --quiet 2>"$work/err"; then
        [ -s "$work/speed.mp4" ] && pass || fail "no video written"
        ls "$work" | grep -q 'speed.mp4.tmp' && fail "temporary video left behind" || pass
    else
        fail "video run failed: $(cat "$work/err")"
    fi
fi
mkdir -p "$work/nopath"
err=$(PATH="$work/nopath" "$COREBOX" run "$scene" --headless --frames 2 --out "$work/v" --video "$work/v.mp4" 2>&1 >/dev/null)
rc=$?
{ [ $rc -eq 2 ] && grep -q "needs ffmpeg" <<<"$err"; } && pass || fail "missing ffmpeg: exit $rc: $err"

# Bad arguments: exit 2, a message naming the flag, nothing written.
bad() {  # bad NAME PATTERN ARGS...
    local name=$1 pattern=$2
    shift 2
    rm -rf "$work/out"
    local err rc
    err=$("$COREBOX" run "$scene" --headless "$@" 2>&1 >/dev/null)
    rc=$?
    if [ $rc -ne 2 ]; then fail "$name: exit $rc, expected 2: $err"; return; fi
    grep -q -- "$pattern" <<<"$err" && pass || fail "$name: message lacks '$pattern': $err"
    if [ -d "$work/out" ] && [ -n "$(ls -A "$work/out")" ]; then fail "$name: left files: $(ls "$work/out")"; else pass; fi
}
bad "size zero" "--size" --frames 2 --size 0x100 --out "$work/out"
bad "size garbled" "--size" --frames 2 --size big --out "$work/out"
bad "no frames" "--frames" --frames 0 --out "$work/out"
bad "negative frames" "--frames" --frames -4 --out "$work/out"
bad "no out" "--out" --frames 2
bad "bad colour mode" "--color-by" --frames 2 --color-by mass --out "$work/out"
touch "$work/plainfile"
bad "unwritable directory" "--out: cannot create directory" --frames 2 --out "$work/plainfile/sub"

# No EGL vendor at all: exit 4 with a message that says what to install or set.
err=$(__EGL_VENDOR_LIBRARY_FILENAMES="$work/none.json" "$COREBOX" run "$scene" --headless --frames 2 --out "$work/novendor" 2>&1 >/dev/null)
rc=$?
{ [ $rc -eq 4 ] && grep -q "EGL vendor" <<<"$err"; } && pass || fail "no EGL vendor: exit $rc: $err"
[ -z "$(ls -A "$work/novendor" 2>/dev/null)" ] && pass || fail "files left after the EGL failure"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
