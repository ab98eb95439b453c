#!/bin/sh
# End-to-end checks of the xrad command line: help on every command, exit
# statuses (0 ok, 1 bad input, 2 system/GPU error) and messages that name
# the file and field. Usage: test_cli.sh XRAD SOURCE_ROOT
set -u
xrad=$1
root=$2
tmp=$(mktemp -d /tmp/xrad-cli-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fails=0
checks=0

expect() { # expect STATUS DESCRIPTION -- command...
    want=$1; what=$2; shift 3
    checks=$((checks + 1))
    "$@" >"$tmp/out" 2>"$tmp/err"
    got=$?
    if [ "$got" != "$want" ]; then
        fails=$((fails + 1))
        echo "FAIL: $what: exit $got, want $want: $*"
        sed 's/^/    /' "$tmp/out" "$tmp/err" | head -20
    fi
    # The suite runs with XRAD_VALIDATION=1: any message of the layer
    # (src/gpu/context.c prints "xrad: vulkan validation ...") fails.
    checks=$((checks + 1))
    if grep -q "vulkan validation" "$tmp/err"; then
        fails=$((fails + 1))
        echo "FAIL: $what: validation messages: $*"
        grep "vulkan validation" "$tmp/err" | head -5 | sed 's/^/    /'
    fi
}
expect_text() { # expect_text FILE PATTERN DESCRIPTION
    checks=$((checks + 1))
    if ! grep -q -- "$2" "$1"; then
        fails=$((fails + 1))
        echo "FAIL: $3: '$2' not in output:"
        sed 's/^/    /' "$1" | head -20
    fi
}

expect 0 "top-level help" -- "$xrad" --help
expect_text "$tmp/out" "render" "help lists commands"
for c in render compare info devices bench; do
    expect 0 "$c --help" -- "$xrad" "$c" --help
    expect_text "$tmp/out" "usage: xrad $c" "$c help text"
done
expect 0 "compare --help" -- "$xrad" compare --help
expect_text "$tmp/out" "--scene" "compare's help has --scene"
expect_text "$tmp/out" "surface_error" "compare's help defines its figures"
expect 0 "bench --help" -- "$xrad" bench --help
expect_text "$tmp/out" "--metric" "bench's help has --metric"
expect 0 "render --help" -- "$xrad" render --help
expect_text "$tmp/out" "--atlas" "render's help has --atlas"
expect 1 "no command" -- "$xrad"
expect 1 "unknown command" -- "$xrad" frobnicate
expect 1 "render without a scene" -- "$xrad" render
expect 1 "unknown option" -- "$xrad" render "$root/scenes/cornell-box.json" --bogus
expect_text "$tmp/err" "bogus" "unknown option is named"
expect 1 "unknown short option" -- "$xrad" render "$root/scenes/cornell-box.json" -o x.png
expect_text "$tmp/err" "unknown option -o (" "an unknown option is named as written"
expect 1 "unknown method" -- "$xrad" render "$root/scenes/cornell-box.json" --method bogus
expect 1 "bad number" -- "$xrad" render "$root/scenes/cornell-box.json" --width -3
expect 1 "bad extension" -- "$xrad" render "$root/scenes/cornell-box.json" --out x.jpg

# info on every shipped scene
for s in "$root"/scenes/*.json; do
    expect 0 "info $(basename "$s")" -- "$xrad" info "$s"
    expect_text "$tmp/out" "elements" "info prints elements"
done

# bad scene files: exit 1, message names the file and the field
printf '{"materials": [{"name": "m", "albedo": [1.5, 0, 0]}], "objects": []}' >"$tmp/bad-albedo.json"
expect 1 "albedo out of range" -- "$xrad" info "$tmp/bad-albedo.json"
expect_text "$tmp/err" "bad-albedo.json" "message names the file"
expect_text "$tmp/err" "albedo" "message names the field"
printf '{"objects": [' >"$tmp/truncated.json"
expect 1 "malformed JSON" -- "$xrad" info "$tmp/truncated.json"
expect_text "$tmp/err" "truncated.json" "message names the file"
expect 1 "missing file" -- "$xrad" info "$tmp/does-not-exist.json"
expect_text "$tmp/err" "does-not-exist.json" "message names the file"
# An output that cannot be written is refused before the solve (nothing
# solved: no timing line on stdout).
: >"$tmp/plain-file"
expect 1 "an output under a file" -- "$xrad" render "$root/scenes/cornell-box.json" --method progressive --out "$tmp/plain-file/x.png" --quiet
expect_text "$tmp/err" "plain-file/x.png: cannot write: Not a directory" "the output is named"
checks=$((checks + 1))
if grep -q "time:" "$tmp/out"; then
    fails=$((fails + 1))
    echo "FAIL: the solve ran before the output was found unwritable"
fi
# A directory opens and fails its first read: the user's error all the same.
mkdir -p "$tmp/dir.json" "$tmp/dir.glb"
expect 1 "a directory as the scene" -- "$xrad" render "$tmp/dir.json" --quiet
expect_text "$tmp/err" "dir.json: cannot read: Is a directory" "the directory is named"
expect 1 "a directory as the model" -- "$xrad" info "$tmp/dir.glb" --no-gpu
expect_text "$tmp/err" "dir.glb: cannot read: Is a directory" "the directory is named"

# Luminaire files: what they hold; a bad one names its line and field.
expect 0 "info of an EULUMDAT file" -- "$xrad" info "$root/tests/data/photometry/asymmetric.ldt"
expect_text "$tmp/out" "the file states 1000 lm (ratio 0.99" "the LDT's flux against its integral"
expect 0 "info of an IES file" -- "$xrad" info "$root/tests/data/photometry/asymmetric.ies"
expect_text "$tmp/out" "gamma       19 angles, 0 to 90" "the IES file's gamma range"
printf 'xrad\n1\n7\n' >"$tmp/bad.ldt"
expect 1 "a bad EULUMDAT file" -- "$xrad" info "$tmp/bad.ldt"
expect_text "$tmp/err" "bad.ldt: line 3 (Isym, symmetry indicator)" "the line and field are named"

# unknown device: bad input, and the message lists what there is
expect 1 "unknown device" -- "$xrad" devices --device no-such-device-xyz
expect 0 "devices" -- "$xrad" devices
expect_text "$tmp/out" "\*" "devices marks the chosen one"

# a small scene end to end: reference solve, PNG + EXR, compare with itself
cat >"$tmp/tiny.json" <<'JSON'
{"unit": "m", "density": 4,
 "materials": [{"name": "white", "albedo": [0.7, 0.7, 0.7]},
               {"name": "lamp", "albedo": [0, 0, 0], "emission": [10, 10, 10]}],
 "objects": [{"name": "room", "surfaces": [
   {"name": "walls", "material": "white", "box": {"origin": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0], "w": [0, 0, 1]}, "inward": true},
   {"name": "light", "material": "lamp", "quad": {"origin": [0.4, 0.99, 0.4], "u": [0.2, 0, 0], "v": [0, 0, 0.2]}}]}],
 "camera": {"position": [0.5, 0.5, 0.05], "look_at": [0.5, 0.5, 1], "up": [0, 1, 0], "fov_degrees": 60, "width": 64, "height": 64}}
JSON
expect 0 "render tiny" -- "$xrad" render "$tmp/tiny.json" --out "$tmp/tiny.exr" --quiet
expect_text "$tmp/out" "tiny.exr" "render says where the image went"
expect_text "$tmp/out" "time:" "render prints its timings"
# Reinhard's operator: a PNG; another name is refused, the choices listed.
expect 0 "render --tonemap reinhard" -- "$xrad" render "$tmp/tiny.json" --tonemap reinhard --out "$tmp/tiny-r.png" --quiet
expect_text "$tmp/out" "tiny-r.png" "the Reinhard PNG is written"
expect 1 "unknown tone mapping" -- "$xrad" render "$tmp/tiny.json" --tonemap filmic --out "$tmp/x.png"
expect_text "$tmp/err" "--tonemap: 'filmic' is none of exposure, reinhard" "the choices are named"
# --check: the error against the CPU reference at the last frame's pose.
expect 0 "render --check" -- "$xrad" render "$tmp/tiny.json" --method progressive --check --out "$tmp/c.png" --quiet
expect_text "$tmp/out" "against the CPU reference at t = 0.000 s (.*): surface_error [0-9.]* (.*), element p50 [0-9.]*, p95 [0-9.]*, mean ratio [0-9.]*$" "the figures"
# Long solves say how far they are on stderr (unless --quiet).
expect 0 "progress of a progressive solve" -- "$xrad" render "$tmp/tiny.json" --method progressive --out "$tmp/p.png"
expect_text "$tmp/err" "progressive  *100.0%" "progressive's progress"
expect 0 "progress of gather" -- "$xrad" render "$tmp/tiny.json" --method gather --out "$tmp/g.png"
expect_text "$tmp/err" "gather: direct  *100.0%" "gather's direct light"
expect_text "$tmp/err" "gather: bounce 2  *100.0%" "gather's bounces"
# What solves but is likely not meant is said: no emitter, a material no
# surface uses.
sed 's/"light", "material": "lamp"/"light", "material": "white"/' "$tmp/tiny.json" >"$tmp/dark.json"
expect 0 "a scene without emitters" -- "$xrad" info "$tmp/dark.json" --no-gpu
expect_text "$tmp/err" "warning: .*dark.json: no surface emits light" "no emitter is said"
expect_text "$tmp/err" "warning: .*dark.json: material 'lamp' is used by no surface" "the unused material is named"
expect 0 "render tiny png" -- "$xrad" render "$tmp/tiny.json" --png "$tmp/tiny.png" --exr "$tmp/tiny2.exr" --quiet
[ -s "$tmp/tiny.png" ] || { fails=$((fails + 1)); echo "FAIL: no PNG written"; }
expect 0 "compare identical" -- "$xrad" compare "$tmp/tiny.exr" "$tmp/tiny2.exr"
expect_text "$tmp/out" "^nrmse 0.0000000$" "identical renders have NRMSE 0"
expect 1 "compare a non-image" -- "$xrad" compare "$tmp/tiny.json" "$tmp/tiny.exr"
cp "$tmp/tiny.json" "$tmp/fake.png"
expect 1 "compare a non-PNG named .png" -- "$xrad" compare "$tmp/fake.png" "$tmp/tiny.png"
expect_text "$tmp/err" "fake.png" "the unreadable PNG is named"
expect 0 "compare PNGs" -- "$xrad" compare "$tmp/tiny.png" "$tmp/tiny.png"
expect_text "$tmp/out" "^nrmse 0.0000000$" "a PNG against itself has NRMSE 0"

# Accuracy figures (README "Accuracy") on the Cornell box at 64 x 64: the
# EXR carries an emitter mask, --atlas the element solution; compare keeps
# "nrmse" first and prints the image figures after it, compare --scene the
# element figures. A solution against itself has every error 0.
box="$root/scenes/cornell-box.json"
expect 0 "render reference with --atlas" -- "$xrad" render "$box" --width 64 --height 64 --exr "$tmp/box-ref.exr" --atlas "$tmp/box-ref-atlas.exr" --quiet
expect_text "$tmp/out" "box-ref-atlas.exr (element atlas" "render says where the atlas went"
expect 0 "render progressive with --atlas" -- "$xrad" render "$box" --method progressive --width 64 --height 64 --exr "$tmp/box-pr.exr" --atlas "$tmp/box-pr-atlas.exr" --quiet
expect 0 "compare images" -- "$xrad" compare "$tmp/box-pr.exr" "$tmp/box-ref.exr"
checks=$((checks + 1))
awk 'NR == 1 && !/^nrmse [0-9.]+$/ { exit 1 }
     NR == 2 && !/^mean_ratio [0-9.]+$/ { exit 1 }
     NR == 3 && !/^rel_rms [0-9.]+$/ { exit 1 }
     NR == 4 && !/^pixels [0-9]+$/ { exit 1 }
     END { exit NR < 5 }' "$tmp/out" ||
    { fails=$((fails + 1)); echo "FAIL: compare's lines are not nrmse, mean_ratio, rel_rms, pixels:"; sed 's/^/    /' "$tmp/out"; }
expect_text "$tmp/out" "^mask .*box-ref.exr$" "the mask is the reference's emitter channel"
# The light is in view: masked pixels are fewer than the image's 4096.
checks=$((checks + 1))
awk '/^pixels/ { exit !($2 > 2000 && $2 < 4096) }' "$tmp/out" ||
    { fails=$((fails + 1)); echo "FAIL: emitter and background pixels counted: $(grep pixels "$tmp/out")"; }
expect 0 "compare an image with itself" -- "$xrad" compare "$tmp/box-ref.exr" "$tmp/box-ref.exr"
checks=$((checks + 1))
awk '/^nrmse|^rel_rms/ { if ($2 != 0) exit 1 } /^mean_ratio/ { if ($2 != 1) exit 1 }' "$tmp/out" ||
    { fails=$((fails + 1)); echo "FAIL: an image against itself:"; sed 's/^/    /' "$tmp/out"; }
# An EXR without the emitter channel (--diff writes plain RGBA): no mask.
expect 0 "write a diff" -- "$xrad" compare "$tmp/box-pr.exr" "$tmp/box-ref.exr" --diff "$tmp/box-diff.exr"
expect 0 "compare EXRs without masks" -- "$xrad" compare "$tmp/box-diff.exr" "$tmp/box-diff.exr"
expect_text "$tmp/out" "^mask none" "no emitter channel, no mask"
expect_text "$tmp/out" "^pixels 4096$" "without a mask every covered pixel counts"
expect 0 "compare --scene, reference against itself" -- "$xrad" compare --scene "$box" "$tmp/box-ref-atlas.exr" "$tmp/box-ref-atlas.exr"
expect_text "$tmp/out" "^surface_error 0.0000000 (floor, ratio 1.0000000)$" "no surface error against itself"
for k in element_p50 element_p95 element_max; do
    expect_text "$tmp/out" "^$k 0.0000000$" "$k of a solution against itself"
done
expect_text "$tmp/out" "^element_mean_ratio 1.0000000$" "element mean ratio against itself"
expect 0 "compare --scene --surfaces" -- "$xrad" compare --scene "$box" "$tmp/box-pr-atlas.exr" "$tmp/box-ref-atlas.exr" --surfaces
expect_text "$tmp/out" "^surface_error [0-9.]* ([^,]*, ratio [0-9.]*)$" "surface_error names its surface"
expect_text "$tmp/out" "^surface floor ratio [0-9.]*$" "one line per surface"
expect_text "$tmp/out" "^surface light emitter (not counted)$" "emitters are named as left out"
checks=$((checks + 1))
awk '/^surface_error/ { exit !($2 > 0) }' "$tmp/out" ||
    { fails=$((fails + 1)); echo "FAIL: progressive has no surface error"; }
# --elements: every counted element, worst first, the worst as element_max ranks it.
expect 0 "compare --scene --elements" -- "$xrad" compare --scene "$box" "$tmp/box-pr-atlas.exr" "$tmp/box-ref-atlas.exr" --elements "$tmp/elements.csv"
checks=$((checks + 1))
n=$(awk '/^elements/ { print $2 }' "$tmp/out"); max=$(awk '/^element_max/ { print $2 }' "$tmp/out")
awk -F, -v n="$n" -v max="$max" '
    NR == 1 { if ($0 != "surface,i,j,x,y,z,a,b,rel") { print "header: " $0; bad = 1 }; next }
    NR == 2 { top = $9 }
    NR > 2 && $9 > last { print "row " NR " ranks above the row before it"; bad = 1 }
    { last = $9 }
    END { if (NR - 1 != n) { print NR - 1 " rows for " n " elements"; bad = 1 }
          if (top - max > 1e-4 * max || max - top > 1e-4 * max) { print "worst " top " but element_max " max; bad = 1 }
          exit bad }' "$tmp/elements.csv" ||
    { fails=$((fails + 1)); echo "FAIL: compare --elements:"; head -3 "$tmp/elements.csv" | sed 's/^/    /'; }
expect 0 "compare --elements, reference against itself" -- "$xrad" compare --scene "$box" "$tmp/box-ref-atlas.exr" "$tmp/box-ref-atlas.exr" --elements "$tmp/same.csv"
checks=$((checks + 1))
awk -F, 'NR > 1 && $9 != 0 { exit 1 } END { exit NR < 2 }' "$tmp/same.csv" ||
    { fails=$((fails + 1)); echo "FAIL: a solution against itself has element errors"; }
expect 1 "--elements to a path that cannot be written" -- "$xrad" compare --scene "$box" "$tmp/box-ref-atlas.exr" "$tmp/box-ref-atlas.exr" --elements "$tmp/no/such/dir.csv"
expect_text "$tmp/err" "no/such/dir.csv: cannot write" "the path is named"
expect 1 "compare --scene with an image for an atlas" -- "$xrad" compare --scene "$box" "$tmp/box-pr.exr" "$tmp/box-ref-atlas.exr"
expect_text "$tmp/err" "box-pr.exr is 64x64" "the file of the wrong size is named"
expect_text "$tmp/err" "cornell-box.json's element atlas" "the scene is named"
expect 1 "compare images of two sizes" -- "$xrad" compare "$tmp/box-pr.exr" "$tmp/box-ref-atlas.exr"
expect_text "$tmp/err" "box-pr.exr is 64x64 but .*box-ref-atlas.exr is" "both files are named"
expect 1 "--surfaces without --scene" -- "$xrad" compare --surfaces "$tmp/box-pr.exr" "$tmp/box-ref.exr"

# frames: the last of --frames N at --fps F is the render at time N / F
expect 0 "frames" -- "$xrad" render "$tmp/tiny.json" --method progressive --frames 3 --fps 6 --frame-out "$tmp/frames" --exr "$tmp/last.exr" --quiet
n=$(ls "$tmp/frames" | grep -c '^frame-000[0-3].png$')
checks=$((checks + 1)); [ "$n" -eq 4 ] || { fails=$((fails + 1)); echo "FAIL: $n frame files, want 4"; }
expect 0 "render at the last frame's time" -- "$xrad" render "$tmp/tiny.json" --method progressive --time 0.5 --exr "$tmp/at.exr" --quiet
expect 0 "compare frames" -- "$xrad" compare "$tmp/last.exr" "$tmp/at.exr"
expect_text "$tmp/out" "^nrmse 0.0000000$" "the last frame is the pose at N / fps"
# dynamic methods redistribute frame to frame and end near a fresh solve
for m in incremental cross; do
    rm -rf "$tmp/frames"
    expect 0 "$m frames" -- "$xrad" render "$tmp/tiny.json" --method $m --frames 3 --fps 6 --frame-out "$tmp/frames" --exr "$tmp/$m.exr"
    expect_text "$tmp/out" "redistribution" "$m reports its redistribution time"
    n=$(ls "$tmp/frames" | grep -c '^frame-000[0-3].png$')
    checks=$((checks + 1)); [ "$n" -eq 4 ] || { fails=$((fails + 1)); echo "FAIL: $m: $n frame files, want 4"; }
    expect 0 "compare $m" -- "$xrad" compare "$tmp/$m.exr" "$tmp/at.exr"
    checks=$((checks + 1))
    awk '/^nrmse/ { exit !($2 < 0.02) }' "$tmp/out" ||
        { fails=$((fails + 1)); echo "FAIL: $m after 3 frames: $(cat "$tmp/out") vs a fresh solve"; }
done

# GPU methods on the tiny scene, and GPU failures: exit 2 with the call named
expect 0 "render progressive" -- "$xrad" render "$tmp/tiny.json" --method progressive --exr "$tmp/pr.exr" --quiet
expect_text "$tmp/out" "reconstruct" "progressive prints per-pass GPU times"
expect 0 "render gather" -- "$xrad" render "$tmp/tiny.json" --method gather --hemicube-res 16 --exr "$tmp/ga.exr" --quiet
expect_text "$tmp/out" "integrate" "gather prints per-pass GPU times"
expect 2 "out of device memory" -- env XRAD_FAULT=vkAllocateMemory:1:VK_ERROR_OUT_OF_DEVICE_MEMORY "$xrad" render "$tmp/tiny.json" --method progressive --quiet --exr "$tmp/f.exr"
expect_text "$tmp/err" "vkAllocateMemory" "the failing call is named"
expect_text "$tmp/err" "VK_ERROR_OUT_OF_DEVICE_MEMORY" "the error is named"
expect 2 "out of host memory" -- env XRAD_FAULT=vkCreateBuffer:2:VK_ERROR_OUT_OF_HOST_MEMORY "$xrad" render "$tmp/tiny.json" --method progressive --quiet --exr "$tmp/f.exr"
expect_text "$tmp/err" "VK_ERROR_OUT_OF_HOST_MEMORY" "the error is named"
expect 2 "device lost" -- env XRAD_FAULT=vkQueueSubmit:2:VK_ERROR_DEVICE_LOST "$xrad" render "$tmp/tiny.json" --method progressive --quiet --exr "$tmp/f.exr"
expect_text "$tmp/err" "VK_ERROR_DEVICE_LOST" "the error is named"
# a scene that does not fit is refused before its buffers are allocated,
# with the bytes needed and left
expect 2 "scene too big for the GPU" -- env XRAD_GPU_MEMORY_MIB=0.05 "$xrad" render "$tmp/tiny.json" --method progressive --quiet --exr "$tmp/f.exr"
expect_text "$tmp/err" "needs .* MiB of GPU memory, but only" "needed and available are named"

# Quality: presets and settings from the command line and the scene file,
# named errors for bad values.
expect 0 "preset draft" -- "$xrad" render "$tmp/tiny.json" --method progressive --preset draft --exr "$tmp/q.exr" --quiet
# A preset's density applies (a preset table short of a column once read
# every preset's density as the default): draft lays out the elements of
# --density-scale 0.5, not those of the defaults.
for q in "--preset draft" "--density-scale 0.5" ""; do
    # shellcheck disable=SC2086 # the options split into words
    expect 0 "info $q" -- "$xrad" info "$root/scenes/cornell-box.json" --no-gpu $q
    grep '^elements' "$tmp/out" >"$tmp/elements${q:+-}$(echo "$q" | tr -d ' .-')"
done
checks=$((checks + 1))
if ! cmp -s "$tmp/elements-presetdraft" "$tmp/elements-densityscale05" ||
    cmp -s "$tmp/elements-presetdraft" "$tmp/elements"; then
    fails=$((fails + 1))
    echo "FAIL: --preset draft: $(cat "$tmp/elements-presetdraft"); density 0.5: $(cat "$tmp/elements-densityscale05"); default: $(cat "$tmp/elements")"
fi
expect 1 "odd hemicube resolution" -- "$xrad" render "$tmp/tiny.json" --method progressive --hemicube-res 33
expect_text "$tmp/err" "hemicube_res" "the setting is named"
expect 1 "unknown preset" -- "$xrad" render "$tmp/tiny.json" --method progressive --preset ultra
expect_text "$tmp/err" "ultra" "the preset is named"
expect 1 "unknown choice" -- "$xrad" render "$tmp/tiny.json" --method progressive --id-check fuzzy
expect_text "$tmp/err" "neighbours|exact" "the choices are listed"
sed 's/^{/{"quality": {"preset": "draft", "hemicube_res": 35},/' "$tmp/tiny.json" >"$tmp/badq.json"
expect 1 "bad quality in a scene file" -- "$xrad" info "$tmp/badq.json" --no-gpu
expect_text "$tmp/err" "quality.hemicube_res" "the scene field is named"
expect 0 "info with GPU memory" -- "$xrad" info "$tmp/tiny.json" --method cross
expect_text "$tmp/out" "redistribution" "memory by category"
expect_text "$tmp/out" "render targets" "memory by category"
# A device or hemicube path that names nothing is an error, not a missing GPU.
expect 1 "info, bad XRAD_HEMICUBE_PATH" -- env XRAD_HEMICUBE_PATH=sideways "$xrad" info "$tmp/tiny.json"
expect_text "$tmp/err" "XRAD_HEMICUBE_PATH: 'sideways'" "the variable is named"
expect 1 "info, no such device" -- "$xrad" info "$tmp/tiny.json" --device no-such-device
expect_text "$tmp/err" "no-such-device" "the device asked for is named"
# cross says how many patches it made: cornell-lowq's box at cross_density
# 3 has 2 x 2 blocks on each of its 6 faces (sides under 1/3 m: 2 samples).
expect 0 "info, cross patches" -- "$xrad" info "$root/scenes/cornell-lowq.json" --method cross
expect_text "$tmp/out" "cross       24 patches on the dynamic objects" "the patch count"

# The sweep: a 2-point grid writes CSV, JSON and a well-formed SVG with a
# Pareto front.
expect 0 "sweep" -- "$xrad" bench "$tmp/tiny.json" --methods progressive --sweep grid --sweep-settings "hemicube_res=16,32" --repeat 1 --cache "$tmp/cache" --sweep-out "$tmp/sweep"
for ext in csv json svg; do
    checks=$((checks + 1))
    [ -s "$tmp/sweep/tiny-progressive.$ext" ] || { fails=$((fails + 1)); echo "FAIL: no sweep $ext"; }
done
checks=$((checks + 1))
python3 - "$tmp/sweep" <<'PY' || { fails=$((fails + 1)); echo "FAIL: sweep outputs"; }
import csv, json, sys, xml.dom.minidom
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/tiny-progressive.csv")))
assert len(rows) == 2, rows
assert {r["hemicube_res"] for r in rows} == {"16", "32"}
assert any(r["pareto"] == "1" for r in rows)
assert all(float(r["peak_gpu_mib"]) > 0 and float(r["nrmse"]) >= 0 for r in rows)
assert all(float(r["surface_error"]) >= 0 and r["worst_surface"] and
           float(r["element_p95"]) >= 0 and float(r["rel_rms"]) >= 0 for r in rows)
points = json.load(open(d + "/tiny-progressive.json"))["points"]
assert len(points) == 2 and all("passes" in p and "settings" in p for p in points)
assert all(p["surface_error"] is not None for p in points)
assert json.load(open(d + "/tiny-progressive.json"))["pareto_metric"] == "surface_error"
xml.dom.minidom.parse(d + "/tiny-progressive.svg")
PY
expect 1 "sweep grid without settings" -- "$xrad" bench "$tmp/tiny.json" --methods progressive --sweep grid --cache "$tmp/cache"
expect_text "$tmp/err" "sweep-settings" "the missing option is named"
expect 1 "unknown sweep metric" -- "$xrad" bench "$tmp/tiny.json" --sweep one --metric psnr
expect_text "$tmp/err" "surface_error" "the metrics are listed"

# Bench rows carry the accuracy figures beside nrmse, against the CPU
# reference, and say so; a second run reads the cached reference (image,
# mask and atlas) and gives the same figures.
for run in 1 2; do
    expect 0 "bench with accuracy figures ($run)" -- "$xrad" bench "$box" --methods progressive --repeat 1 --width 64 --height 64 --cache "$tmp/cache" --json "$tmp/bench$run.json"
done
expect_text "$tmp/err" "reference from" "the second run reads the cache"
checks=$((checks + 1))
python3 - "$tmp/bench1.json" "$tmp/bench2.json" <<'PY' || { fails=$((fails + 1)); echo "FAIL: bench rows"; }
import json, sys
a, b = (json.load(open(p))["rows"] for p in sys.argv[1:])
keys = ["nrmse", "mean_ratio", "rel_rms", "surface_error", "worst_surface", "element_p50",
        "element_p95", "element_max"]
for rows in (a, b):
    assert len(rows) == 1, rows
    r = rows[0]
    missing = [k for k in keys if k not in r or r[k] is None]
    assert not missing, missing
    assert r["reference"] == "cpu-reference" and r["element_reference"] == "cpu-reference", r
    assert isinstance(r["worst_surface"], str) and r["worst_surface"], r
    assert 0.5 < r["mean_ratio"] < 2 and r["rel_rms"] > 0 and r["surface_error"] > 0, r
    assert 0 <= r["element_p50"] <= r["element_p95"] <= r["element_max"], r
# The cached reference measures what the fresh one did.
for k in keys:
    assert a[0][k] == b[0][k], (k, a[0][k], b[0][k])
PY

# Broken model files (issue 15; assimp-testmodels, tools/setup.sh): bad
# input, exit 1, the message names the file and the mesh or buffer; a file
# assimp repairs loads, and its warning says what was dropped.
gltf2=/usr/share/assimp/models/glTF2
if [ -d "$gltf2" ]; then
    expect 1 "model with infinite positions" -- "$xrad" info "$gltf2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb"
    expect_text "$tmp/err" "BoxWithInfinites.glb: node 'nodes_1': mesh 'Mesh': vertex 0 is not finite" "names file, node, mesh, vertex"
    expect 1 "model without its buffer" -- "$xrad" info "$gltf2/MissingBin/BoxTextured.gltf"
    expect_text "$tmp/err" "MissingBin/BoxTextured.gltf: cannot import: .*BoxTextured0.bin" "names the file and the buffer"
    expect 1 "model with every index out of range" -- "$xrad" info "$gltf2/IndexOutOfRange/AllIndicesOutOfRange.gltf"
    expect_text "$tmp/err" "AllIndicesOutOfRange.gltf: .*Mesh \"Mesh\"" "names the file and the mesh"
    expect 0 "model with one index out of range" -- "$xrad" info "$gltf2/IndexOutOfRange/IndexOutOfRange.gltf"
    expect_text "$tmp/err" "warning: .*IndexOutOfRange.gltf: assimp: .*dropped" "the dropped face is a warning"
else
    checks=$((checks + 1)) fails=$((fails + 1))
    echo "FAIL: $gltf2 missing (package assimp-testmodels, tools/setup.sh)"
fi

echo "$checks checks, $fails failed"
[ "$fails" -eq 0 ]
