#!/bin/sh
# examples/embed under a virtual X server (Xvfb) on lavapipe (issue 17.4):
# a GLFW + Vulkan program with its own instance and device, drawing with its
# own pipeline from xrad's front atlas, matches `xrad render` of the same
# frame within issue 14's image thresholds (image mean ratio within 1%,
# NRMSE below 0.01), with no validation message on its instance (exit 0).
# progressive: a fresh solve per request, so the two solutions agree and
# the comparison measures the drawing. Usage: test_embed.sh EMBED XRAD ROOT
set -u
embed=$1
xrad=$2
root=$3
tmp=$(mktemp -d /tmp/xrad-embed-XXXXXX)
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

. "$(dirname "$0")/xvfb.sh"
xvfb_start "$tmp"

# Frame 10 at 30 fps: the box has turned by its animation since t = 0.
scene=$root/scenes/cornell-lowq.json
checks=$((checks + 1))
if ! "$embed" "$scene" --method progressive --frames 10 --fps 30 --screenshot "$tmp/embed.exr" \
    >"$tmp/out" 2>"$tmp/err"; then
    fail "embed: exit status $?"
    sed 's/^/    /' "$tmp/out" "$tmp/err" | head -20
fi
cat "$tmp/out"
checks=$((checks + 1))
if grep -qi "validation" "$tmp/err"; then
    fail "embed: validation messages"
    grep -i validation "$tmp/err" | head -5
fi
checks=$((checks + 1))
if ! "$xrad" render "$scene" --method progressive --time 0.333333333 --out "$tmp/render.exr" \
    --quiet >"$tmp/rout" 2>"$tmp/rerr"; then
    fail "render: exit status $?"
    sed 's/^/    /' "$tmp/rout" "$tmp/rerr" | head -20
fi
if [ -f "$tmp/embed.exr" ] && [ -f "$tmp/render.exr" ]; then
    "$xrad" compare "$tmp/embed.exr" "$tmp/render.exr" >"$tmp/cmp" 2>&1
    cat "$tmp/cmp"
    checks=$((checks + 1))
    nrmse=$(sed -n 's/^nrmse //p' "$tmp/cmp")
    ratio=$(sed -n 's/^mean_ratio //p' "$tmp/cmp")
    awk -v e="$nrmse" 'BEGIN { exit !(e != "" && e < 0.01) }' || fail "NRMSE $nrmse is not below 0.01"
    checks=$((checks + 1))
    awk -v r="$ratio" 'BEGIN { exit !(r != "" && r > 0.99 && r < 1.01) }' ||
        fail "image mean ratio $ratio is not within 1%"
else
    fail "no images to compare"
fi
echo "$checks checks, $fails failed"
[ "$fails" = 0 ]
