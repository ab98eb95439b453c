#!/bin/sh
# xrad view under a virtual X server (Xvfb) on lavapipe: the windowed
# real-time loop's screenshot matches xrad render of the same frame, a
# resize recreates the swapchain without validation messages, and without a
# display the command says so and exits 2. Usage: test_view.sh XRAD ROOT
set -u
xrad=$1
root=$2
tmp=$(mktemp -d /tmp/xrad-view-XXXXXX)
xvfb_pid=
cleanup() {
    [ -n "$xvfb_pid" ] && kill "$xvfb_pid" 2>/dev/null
    rm -rf "$tmp"
}
trap cleanup EXIT
fails=0
checks=0
fail() {
    fails=$((fails + 1))
    echo "FAIL: $*"
}

if ! "$xrad" view --help >/dev/null 2>&1; then
    echo "SKIP: this xrad was built without GLFW (meson option window), so it has no view"
    exit 77
fi

# Without a display: a clear message, exit status 2.
checks=$((checks + 1))
env -u DISPLAY -u WAYLAND_DISPLAY "$xrad" view "$root/scenes/cornell-lowq.json" --frames 1 \
    >"$tmp/out" 2>"$tmp/err"
rc=$?
if [ "$rc" != 2 ] || ! grep -q "no display" "$tmp/err"; then
    fail "no display: exit $rc, want 2 and 'no display':"
    sed 's/^/    /' "$tmp/err" | head -5
fi

. "$(dirname "$0")/xvfb.sh"
xvfb_start "$tmp"

# run DESCRIPTION -- command: exit 0 and no validation message
run() {
    what=$1
    shift 2
    checks=$((checks + 1))
    if ! "$@" >"$tmp/out" 2>"$tmp/err"; then
        fail "$what: exit status $?: $*"
        sed 's/^/    /' "$tmp/out" "$tmp/err" | head -20
        return 1
    fi
    checks=$((checks + 1))
    if grep -qi "validation" "$tmp/err"; then
        fail "$what: validation messages"
        grep -i validation "$tmp/err" | head -5
    fi
    return 0
}
# nrmse A B LIMIT
nrmse() {
    checks=$((checks + 1))
    e=$("$xrad" compare "$1" "$2" | sed -n 's/^nrmse //p')
    echo "$(basename "$1") vs $(basename "$2"): NRMSE $e"
    if ! awk -v e="$e" -v l="$3" 'BEGIN { exit !(e != "" && e < l) }'; then
        fail "NRMSE $e of $1 against $2 is not below $3"
    fi
}

# The issue's check: 60 frames of cornell-large in the window against the
# CLI's rendering of the same frame (cross, 60 frames at 30 fps).
# XRAD_VIEW_FRAMES and XRAD_VIEW_SCENE change the count and the scene:
# tools/tsan.sh, after the threads and not the frame rate, runs 12 frames
# of cornell-lowq for CI's time (the test ran 9 minutes there with
# cornell-large, whose solve is the slowest step of the test).
# XRAD_VIEW_THREADS=1 (tools/tsan.sh) runs the windows alone: the renders
# they are compared with run no thread of the loop, and the plain run
# compares them; under ThreadSanitizer the progressive pair's render took
# 350 s of the test's 540 (the driver's compute slowed by its interceptors).
threads_only=${XRAD_VIEW_THREADS:-0}
# render_and_compare SCREENSHOT NAME -- RENDER ARGS...: xrad render of the
# same frame within NRMSE 0.02 of the window's screenshot.
# (sh has no local variables: run() sets `what`, so these names differ.)
render_and_compare() {
    rc_shot=$1
    rc_png=$tmp/$2-render.png
    rc_what="render $2"
    shift 3
    [ "$threads_only" = 1 ] && return 0
    run "$rc_what" -- "$xrad" render "$@" --png "$rc_png" --quiet &&
        nrmse "$rc_shot" "$rc_png" 0.02
}
frames=${XRAD_VIEW_FRAMES:-60}
scene=$root/scenes/${XRAD_VIEW_SCENE:-cornell-large}.json
name=$(basename "$scene" .json)
if run "view $name" -- "$xrad" view "$scene" --screenshot "$tmp/view.png" --frames "$frames" \
    --exposure 2; then
    sed -n 's/^view: /  view: /p' "$tmp/out"
fi
render_and_compare "$tmp/view.png" "$name" -- "$scene" --method cross --frames "$frames" \
    --exposure 2

# A resize mid-run recreates the swapchain; the screenshot has the new size.
lowq=$root/scenes/cornell-lowq.json
if run "view with a resize" -- "$xrad" view "$lowq" --frames 20 --resize-at 5 \
    --resize-to 320x240 --screenshot "$tmp/small.png" --exposure 2; then
    checks=$((checks + 1))
    grep -q "swapchain recreations: [1-9]" "$tmp/out" || fail "no swapchain recreation after the resize"
    checks=$((checks + 1))
    size=$(python3 -c "import struct,sys; d=open(sys.argv[1],'rb').read(24); print('%dx%d' % struct.unpack('>II', d[16:24]))" "$tmp/small.png")
    [ "$size" = 320x240 ] || fail "screenshot after the resize is $size, want 320x240"
fi

# The other dynamic method and the restarting one match render too, the
# restarting one through Reinhard's operator on both sides.
# Progressive restarts every frame, so its last frame is a solve at that
# time whatever came before: 2 frames (one restart) check what 10 do, and
# each is a full solve of cornell-lowq with conserve far (its default; 25
# s a frame against 18 s with on, measured beside two other tests,
# 2026-12-07).
for m in incremental progressive; do
    mframes=10
    tm=exposure
    [ $m = progressive ] && tm=reinhard && mframes=2
    [ "$threads_only" = 1 ] && mframes=3
    run "view $m" -- "$xrad" view "$lowq" --method $m --frames $mframes \
        --screenshot "$tmp/$m.png" --exposure 2 --tonemap $tm
    render_and_compare "$tmp/$m.png" $m -- "$lowq" --method $m --frames $mframes --exposure 2 \
        --tonemap $tm
done

echo "$checks checks, $fails failed"
[ "$fails" = 0 ]
