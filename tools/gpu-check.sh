#!/usr/bin/env bash
# tools/gpu-check.sh: the one prepared check for a machine with a real GPU
# (issue 16). In about 8 minutes in all it
#   1. unpacks carried .deb files where the machine lacks libraries (--debs),
#   2. checks the Vulkan loader and every library the xrad binaries need, and
#      says which are missing and how to bring them,
#   3. finds the GPU through Vulkan (pointing the loader at the NVIDIA driver
#      when it sees none), prints the device and the hemicube path chosen
#      (multiview or layered),
#   4. runs `xrad bench` of the four thesis scenes with progressive,
#      incremental and cross (per-pass GPU times, frame-time ratios), and
#      where time is left incremental and cross on the layered path (when
#      multiview was chosen) and cross with two of its options,
#   5. runs the test suite on that GPU under a wall-clock cap,
# and writes ONE JSON file with all of it ($OUT/gpu-check.json where OUT is
# set, else out/gpu-check.json), with the logs beside it.
#
# The GPU machine (device README: an H200, 16 cores, no network, root) has
# neither the network nor the -dev packages to build xrad, so the build
# travels. Here, with network, after each change of the sources:
#
#   meson compile -C build && tools/gpu-check.sh --prepare
#       # build-gpu/: build/'s executables without debug sections and its
#       #   test list (meson-info), about 14 MiB;
#       # build-debs/: the runtime .debs (loader, validation layer, assimp,
#       #   Embree, OpenEXR, ...), about 18 MiB, and in build-debs/gl/
#       #   glvnd, which the NVIDIA driver needs (unpacked into / there);
#       # build-gpu/assimp-models/: the assimp test models the tests read
#       #   (linked to /usr/share/assimp/models there), about 4 MiB
#
# Both match .gitignore's /build*/, so they travel only when carried. Then,
# through the device tool (under 2000 characters; add "out/bench-cache" to
# carry to reuse references made here with the same --repeat):
#
#   run(command="tools/gpu-check.sh --build build-gpu --debs build-debs",
#       carry=["build-gpu", "build-debs"], timeout_s=560)
#
# The tests run there from meson-info/intro-tests.json with this machine's
# paths mapped onto that checkout (meson test cannot use a moved build), on
# the GPU named by --device (XRAD_DEVICE, default NVIDIA, so never lavapipe).
# The run takes --budget (450 s) at most: the bench first (its CPU reference
# per scene: indirect-light's took 145 CPU-seconds here, about 10 s on 16
# cores), capped at --bench-timeout, then the suite in the time left,
# longest tests first; what the cap stops is
# reported as cut, not failed. A session's device time (15 minutes, a
# machine's start included) leaves no room for a second full run: for a
# retry pass e.g. --budget 240 --no-bench. The reply's output_tail ends with
# the summary (device, hemicube path, steps, suite, the bench table with the
# per-pass GPU times, and the README table); $OUT brings back 4 files:
# gpu-check.json, gpu-check.log, bench.txt and testlog.txt.
#
# Test it anywhere with a fast subset, e.g. on lavapipe:
#   tools/gpu-check.sh --build build-dev --device auto --no-suite \
#       --scenes scenes/cornell-lowq.json --repeat 1
#   tools/gpu-check.sh --build build-dev --device auto --no-bench --suite scene
#
# Exit status: 0 every step passed; 1 a step failed (a test, a bench scene);
# 2 the check could not run (usage, missing libraries, no such GPU).
set -u -o pipefail

usage() {
    cat <<'EOF'
usage: tools/gpu-check.sh [options]

Runs the GPU check (device, hemicube path, xrad bench of the thesis scenes,
the test suite) and writes one JSON file. See the header of this file for
how to run it through the device tool.

  --build DIR          build directory: a meson build, or a folder made by
                       --prepare [build]
  --debs DIR           .deb files to unpack before the checks (dpkg -x), for
                       the libraries the machine lacks; with --prepare, where
                       to download them [build-debs with --prepare]
  --debs-root DIR      where --debs unpacks: a private root whose libraries
                       are used only where the system has none (no system file
                       is changed), or / (dpkg -x into / and ldconfig, as the
                       device README does for the loaders) [/opt/xrad-debs]
  --device NAME        Vulkan device by name substring (XRAD_DEVICE for the
                       tests, --device for xrad); "auto": xrad's own choice
                       (the first discrete GPU) [NVIDIA]
  --scenes LIST        bench scenes, comma-separated or repeated [the four
                       thesis scenes: scenes/cornell-lowq.json,
                       scenes/cornell-large.json, scenes/cornell-small.json,
                       scenes/indirect-light.json]
  --methods LIST       bench methods [progressive,incremental,cross]
  --repeat N           timed frames per scene and method [3]
  --cache DIR          bench reference cache; a carried one is reused where
                       it was made with the same --repeat [out/bench-cache]
  --max-reference-elements N   passed to xrad bench [xrad's: 12000]
  --bench-timeout S    wall-clock cap on the whole bench [240]
  --no-bench           skip the bench
  --no-suite           skip the test suite
  --suite NAME         run only this suite (scene, gpu, solvers, ...);
                       comma-separated or repeated [all]
  --skip NAMES         tests to leave out, comma-separated ('models' is left
                       out by itself where assimp's test models are missing)
  --suite-timeout S    wall-clock cap on the suite [what --budget leaves]
  --budget S           the whole run's wall-clock target [450]
  --jobs N             test processes at a time [online cores]
  --runner R           meson (meson test), own (this script's runner, for
                       carried builds), auto: meson where the build is a meson
                       build of this checkout and this meson made it [auto]
  --out FILE           the JSON [$OUT/gpu-check.json, else out/gpu-check.json]
  --prepare            here, with network: check --build is up to date, copy
                       it stripped to --pack-to, download the runtime .debs
                       into --debs; then exit
  --pack-to DIR        where --prepare puts the build [build-gpu]
  -h, --help           this text
EOF
}

REPO=$(cd "$(dirname "$0")/.." && pwd) || exit 2
cd "$REPO" || exit 2

BUILD=build
DEBS=
DEBS_ROOT=/opt/xrad-debs
DEVICE=NVIDIA
SCENES=
METHODS=progressive,incremental,cross
REPEAT=3
CACHE=out/bench-cache
MAX_REF=
BENCH_TIMEOUT=240
DO_BENCH=1
DO_SUITE=1
SUITES=
SKIP=
SUITE_TIMEOUT=
BUDGET=450
JOBS=$(nproc 2>/dev/null || echo 2)
RUNNER=auto
JSON_OUT=
PREPARE=0
PACK_TO=build-gpu
GL_PACKAGES="libglvnd0 libegl1 libgl1 libglx0 libopengl0 libgles2"
MODELS=/usr/share/assimp/models
TEST_MODELS="PLY/Wuson.ply glTF2 STL/triangle_with_two_solids.stl"
THESIS_SCENES=scenes/cornell-lowq.json,scenes/cornell-large.json,scenes/cornell-small.json,scenes/indirect-light.json

die_usage() {
    echo "gpu-check: $*" >&2
    echo "gpu-check: see tools/gpu-check.sh --help" >&2
    exit 2
}
need_value() { if [ $# -lt 2 ] || [ -z "$2" ]; then die_usage "$1 needs a value"; fi; }
need_number() { case $2 in '' | *[!0-9]*) die_usage "$1 needs a whole number, not '$2'" ;; esac; }
add_list() { if [ -n "$1" ]; then printf '%s,%s' "$1" "$2"; else printf '%s' "$2"; fi; }

while [ $# -gt 0 ]; do
    case $1 in
    -h | --help) usage; exit 0 ;;
    --build) need_value "$@"; BUILD=$2; shift ;;
    --debs) need_value "$@"; DEBS=$2; shift ;;
    --debs-root) need_value "$@"; DEBS_ROOT=$2; shift ;;
    --device) need_value "$@"; DEVICE=$2; shift ;;
    --scenes) need_value "$@"; SCENES=$(add_list "$SCENES" "$2"); shift ;;
    --methods) need_value "$@"; METHODS=$2; shift ;;
    --repeat) need_value "$@"; need_number "$1" "$2"; REPEAT=$2; shift ;;
    --cache) need_value "$@"; CACHE=$2; shift ;;
    --max-reference-elements) need_value "$@"; need_number "$1" "$2"; MAX_REF=$2; shift ;;
    --bench-timeout) need_value "$@"; need_number "$1" "$2"; BENCH_TIMEOUT=$2; shift ;;
    --no-bench) DO_BENCH=0 ;;
    --no-suite) DO_SUITE=0 ;;
    --suite) need_value "$@"; SUITES=$(add_list "$SUITES" "$2"); shift ;;
    --skip) need_value "$@"; SKIP=$(add_list "$SKIP" "$2"); shift ;;
    --suite-timeout) need_value "$@"; need_number "$1" "$2"; SUITE_TIMEOUT=$2; shift ;;
    --budget) need_value "$@"; need_number "$1" "$2"; BUDGET=$2; shift ;;
    --jobs) need_value "$@"; need_number "$1" "$2"; JOBS=$2; shift ;;
    --runner)
        need_value "$@"
        case $2 in auto | meson | own) RUNNER=$2 ;; *) die_usage "--runner: auto, meson or own, not '$2'" ;; esac
        shift ;;
    --out) need_value "$@"; JSON_OUT=$2; shift ;;
    --prepare) PREPARE=1 ;;
    --pack-to) need_value "$@"; PACK_TO=$2; shift ;;
    *) die_usage "unknown option '$1'" ;;
    esac
    shift
done
[ -n "$SCENES" ] || SCENES=$THESIS_SCENES
[ "$REPEAT" -ge 1 ] || die_usage "--repeat must be at least 1"
[ "$JOBS" -ge 1 ] || JOBS=1
BUILD=${BUILD%/}
command -v python3 >/dev/null 2>&1 ||
    { echo "gpu-check: python3 is needed (JSON, the test runner) and is not on PATH" >&2; exit 2; }

# ---------------------------------------------------------------- helpers --

# The libraries every Linux has; never carried.
BASE_PACKAGES=" libc6 libgcc-s1 libstdc++6 zlib1g "

# soname -> Debian 12 package, for the messages about a missing library.
package_of() {
    case $1 in
    libvulkan.so*) echo libvulkan1 ;;
    libcjson.so*) echo libcjson1 ;;
    libpng16.so*) echo libpng16-16 ;;
    libOpenEXRCore-3_1.so* | libOpenEXR-3_1.so* | libIex-3_1.so* | libIlmThread-3_1.so*) echo libopenexr-3-1-30 ;;
    libassimp.so*) echo libassimp5 ;;
    libembree3.so*) echo libembree3-3 ;;
    libglfw.so*) echo libglfw3 ;;
    libdraco.so*) echo libdraco7 ;;
    libminizip.so*) echo libminizip1 ;;
    libtbb.so*) echo libtbb12 ;;
    libX11.so*) echo libx11-6 ;;
    libxcb.so*) echo libxcb1 ;;
    libXau.so*) echo libxau6 ;;
    libXdmcp.so*) echo libxdmcp6 ;;
    libbsd.so*) echo libbsd0 ;;
    libmd.so*) echo libmd0 ;;
    libz.so*) echo zlib1g ;;
    libVkLayer_khronos_validation.so) echo vulkan-validationlayers ;;
    *) echo "" ;;
    esac
}

# The ELF files of a build: xrad, its tools, the test executables.
build_elves() {
    find "$1" -type f -perm -u+x ! -path '*.p/*' ! -path '*/meson-private/*' \
        ! -path '*/meson-logs/*' 2>/dev/null | sort | while read -r f; do
        [ "$(head -c 4 "$f" | od -An -c | tr -d ' \n')" = '177ELF' ] && echo "$f"
    done
}

# The validation layer's library on this machine, if any.
validation_layer_lib() {
    for d in /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/lib /usr/local/lib; do
        [ -e "$d/libVkLayer_khronos_validation.so" ] && { echo "$d/libVkLayer_khronos_validation.so"; return 0; }
    done
    return 1
}

# ---------------------------------------------------------------- prepare --

if [ "$PREPARE" = 1 ]; then
    [ -n "$DEBS" ] || DEBS=build-debs
    PACK_TO=${PACK_TO%/}
    if [ ! -f "$BUILD/build.ninja" ] || [ ! -f "$BUILD/meson-info/intro-tests.json" ]; then
        echo "gpu-check: $BUILD is not a configured meson build (tools/setup.sh makes build/)" >&2
        exit 2
    fi
    [ -x "$BUILD/tools/xrad" ] || { echo "gpu-check: $BUILD/tools/xrad is missing: run meson compile -C $BUILD" >&2; exit 2; }
    # It is emptied: only a folder made by --prepare, or a new one.
    if [ -e "$PACK_TO" ] && [ ! -f "$PACK_TO/gpu-check-pack.txt" ] &&
        [ -n "$(ls -A "$PACK_TO" 2>/dev/null)" ]; then
        echo "gpu-check: $PACK_TO exists and was not made by --prepare; name another --pack-to" >&2
        exit 2
    fi
    if command -v ninja >/dev/null 2>&1; then
        if ! ninja -C "$BUILD" -n 2>/dev/null | grep -q "no work to do"; then
            echo "gpu-check: $BUILD is not up to date with the sources: run 'meson compile -C $BUILD' first" >&2
            exit 2
        fi
    else
        echo "gpu-check: warning: no ninja here, cannot check that $BUILD is up to date"
    fi
    echo "gpu-check: copying $BUILD to $PACK_TO (executables without debug sections, the test list)"
    rm -rf "$PACK_TO" && mkdir -p "$PACK_TO/meson-info" || exit 2
    echo "incomplete (--prepare did not finish)" >"$PACK_TO/gpu-check-pack.txt"
    cp "$BUILD"/meson-info/meson-info.json "$BUILD"/meson-info/intro-tests.json "$PACK_TO/meson-info/" || exit 2
    elves=$(build_elves "$BUILD")
    for f in $elves; do
        rel=${f#"$BUILD"/}
        mkdir -p "$PACK_TO/$(dirname "$rel")" || exit 2
        if command -v strip >/dev/null 2>&1; then
            strip --strip-debug -o "$PACK_TO/$rel" "$f" || exit 2
        else
            cp "$f" "$PACK_TO/$rel" || exit 2
        fi
    done
    # The packages of every library those files (and the validation layer,
    # which the tests load) need, less the ones every Linux has.
    layer=$(validation_layer_lib) || layer=
    [ -n "$layer" ] || echo "gpu-check: warning: no validation layer here (vulkan-validationlayers); the tests need one there"
    pkgs=" libvulkan1 vulkan-validationlayers "
    for lib in $({ for f in $elves $layer; do ldd "$f"; done; } | awk '/=> \// {print $3}' | sort -u); do
        p=$(dpkg -S "$(readlink -f "$lib")" 2>/dev/null || dpkg -S "$lib" 2>/dev/null) || p=
        p=${p%%:*}
        [ -n "$p" ] || { echo "gpu-check: warning: no package owns $lib; it will not travel"; continue; }
        case "$BASE_PACKAGES$pkgs" in *" $p "*) ;; *) pkgs="$pkgs$p " ;; esac
    done
    mkdir -p "$DEBS" && rm -f "$DEBS"/*.deb || exit 2
    echo "gpu-check: downloading into $DEBS:$pkgs"
    failed=
    for p in $pkgs; do
        v=$(dpkg-query -W -f='${Version}' "$p" 2>/dev/null) || v=
        (cd "$DEBS" && { { [ -n "$v" ] && apt-get download -qq "$p=$v" 2>/dev/null; } || apt-get download -qq "$p"; }) 2>&1 |
            grep -v "unsandboxed" >&2
        ls "$DEBS/${p}_"*.deb >/dev/null 2>&1 || failed="$failed $p"
    done
    # The NVIDIA Vulkan driver (libGLX_nvidia.so.0) needs glvnd's
    # libGLdispatch, which the GPU machine's image lacks: without it the
    # loader answered VK_ERROR_INCOMPATIBLE_DRIVER (2026-12-04). The device
    # README's loaders, unpacked into / there where they are missing.
    mkdir -p "$DEBS/gl" && rm -f "$DEBS"/gl/*.deb || exit 2
    for p in $GL_PACKAGES; do
        (cd "$DEBS/gl" && apt-get download -qq "$p") 2>&1 | grep -v "unsandboxed" >&2
        ls "$DEBS/gl/${p}_"*.deb >/dev/null 2>&1 || failed="$failed $p"
    done
    # The assimp test models the tests read (Debian assimp-testmodels, 75
    # MiB in all: these are about 4), put in place there where missing.
    if [ -d "$MODELS" ]; then
        for m in $TEST_MODELS; do
            mkdir -p "$PACK_TO/assimp-models/$(dirname "$m")" &&
                cp -r "$MODELS/$m" "$PACK_TO/assimp-models/$m" || exit 2
        done
    else
        echo "gpu-check: warning: no $MODELS here (assimp-testmodels); the model tests will be left out there"
    fi
    if [ -n "$failed" ]; then
        echo "gpu-check: could not download$failed (apt-get update first? is there a network?)" >&2
        exit 2
    fi
    {
        echo "built_from $(git rev-parse HEAD 2>/dev/null || echo unknown)$(git diff --quiet HEAD -- src tools tests spirv include meson.build 2>/dev/null || echo '+local-changes')"
        echo "build $(cd "$BUILD" && pwd)"
        echo "made $(date -u +%Y-%m-%dT%H:%M:%SZ) on $(sed -n 's/^PRETTY_NAME=//p' /etc/os-release 2>/dev/null | tr -d '"')"
        echo "packages$pkgs"
    } >"$PACK_TO/gpu-check-pack.txt"
    tree_kb=$(git ls-files -z 2>/dev/null | du -ck --files0-from=- 2>/dev/null | tail -1 | cut -f1) || tree_kb=0
    pack_kb=$(du -sk "$PACK_TO" | cut -f1)
    debs_kb=$(du -sk "$DEBS" | cut -f1)
    total_mib=$(((${tree_kb:-0} + pack_kb + debs_kb) / 1024))
    echo "gpu-check: $PACK_TO $((pack_kb / 1024)) MiB, $DEBS $((debs_kb / 1024)) MiB, tracked tree $((${tree_kb:-0} / 1024)) MiB: about $total_mib MiB of the device tool's 64"
    [ "$total_mib" -lt 62 ] || echo "gpu-check: warning: that is near or over the 64 MiB the device tool carries"
    echo "gpu-check: now, through the device tool:"
    echo "  run(command=\"tools/gpu-check.sh --build $PACK_TO --debs $DEBS\", carry=[\"$PACK_TO\", \"$DEBS\"], timeout_s=560)"
    exit 0
fi

# ------------------------------------------------------------- the check --

if [ -n "${OUT:-}" ]; then
    LOGDIR=$OUT
    [ -n "$JSON_OUT" ] || JSON_OUT=$OUT/gpu-check.json
else
    LOGDIR=out/gpu-check
    [ -n "$JSON_OUT" ] || JSON_OUT=out/gpu-check.json
fi
mkdir -p "$LOGDIR" "$(dirname "$JSON_OUT")" || { echo "gpu-check: cannot make $LOGDIR" >&2; exit 2; }
TMPD=$(mktemp -d /tmp/gpu-check-XXXXXX) || exit 2
trap 'rm -rf "$TMPD"' EXIT
: >"$TMPD/steps.tsv"
STARTED=$(date -u +%Y-%m-%dT%H:%M:%SZ)
SECONDS=0
STATUS=0

# Everything printed goes to the console and to gpu-check.log.
exec 3>&1 4>&2
exec > >(tee "$LOGDIR/gpu-check.log") 2>&1
TEE_PID=$!

say() { printf '\n== %s\n' "$*"; }
# step NAME STATUS SECONDS MESSAGE: one line of steps.tsv for the JSON.
step() { printf '%s\t%s\t%s\t%s\n' "$1" "$2" "$3" "$(printf '%s' "$4" | tr '\t\n' '  ')" >>"$TMPD/steps.tsv"; }

# Writes the JSON and the summary from what the steps left in $TMPD.
finish() {
    python3 -c "$PY" assemble "$TMPD" "$JSON_OUT" "$STARTED" "$SECONDS" "$BUDGET" \
        "$BUILD" "$DEVICE" "$SCENES" "$METHODS" "$REPEAT" "$STATUS"
    local rc=$?
    [ "$rc" = 0 ] || { echo "gpu-check: could not write $JSON_OUT"; [ "$STATUS" != 0 ] || STATUS=1; }
    echo "gpu-check: wrote $JSON_OUT; logs in $LOGDIR; ${SECONDS} s; exit status $STATUS"
    # Let tee write the last lines before the command returns.
    exec 1>&3 2>&4
    for _ in 1 2 3 4 5 6 7 8 9 10; do
        kill -0 "$TEE_PID" 2>/dev/null || break
        sleep 0.5
    done
    exit "$STATUS"
}

read -r -d '' PY <<'PYEOF'
import json, os, re, signal, subprocess, sys, time, random

def fmt_ms(v):
    if not isinstance(v, (int, float)) or v != v:
        return "-"
    return "%.2f" % v if v < 10 else ("%.1f" % v if v < 100 else "%.0f" % v)

def fmt_err(v):
    return "-" if not isinstance(v, (int, float)) or v != v else "%.4f" % v

# ---- the test runner for carried builds: meson-info/intro-tests.json with
# the paths of the machine that built it mapped onto this checkout.
def run_suite(build, src, jobs, deadline, suites, skip, logtxt, outjson):
    build = os.path.abspath(build)
    src = os.path.abspath(src)
    info = json.load(open(os.path.join(build, "meson-info", "meson-info.json")))
    old_src = info["directories"]["source"]
    old_build = info["directories"]["build"]
    tests = json.load(open(os.path.join(build, "meson-info", "intro-tests.json")))
    olds = sorted({old_build, old_src}, key=len, reverse=True)
    pat = re.compile("|".join(re.escape(o) for o in olds))
    def remap(s):
        return pat.sub(lambda m: build if m.group(0) == old_build else src, s)
    want = [s for s in suites.split(",") if s]
    skips = set(s for s in skip.split(",") if s)
    def chosen(t):
        if not want:
            return True
        return any(s == w or s.split(":", 1)[-1] == w for s in t["suite"] for w in want)
    sel = [t for t in tests if chosen(t)]
    sel.sort(key=lambda t: -t.get("priority", 0))
    if not sel:
        print("gpu-check: no test in suite(s) %s; the suites: %s" % (
            suites, ", ".join(sorted({s.split(":", 1)[-1] for t in tests for s in t["suite"]}))))
        return 2
    results = []
    queue = []
    for t in sel:
        if t["name"] in skips or any(x.split(":", 1)[-1] + "/" + t["name"] in skips for x in t["suite"]):
            results.append({"name": t["name"], "suite": t["suite"], "result": "SKIP",
                            "returncode": None, "duration": 0, "note": "--skip"})
        else:
            queue.append(t)
    total = len(sel)
    log = open(logtxt, "w")
    log.write("gpu-check test log: %d tests from %s, source %s (built as %s in %s)\n\n" % (
        total, build, src, old_build, old_src))
    running = []
    done_count = [0]
    def report(r):
        done_count[0] += 1
        print("[%2d/%d] %-40s %-8s %7.1f s%s" % (
            done_count[0], total, "/".join(s.split(":", 1)[-1] for s in r["suite"]) + ":" + r["name"],
            r["result"], r["duration"], ("  " + r["note"]) if r.get("note") else ""), flush=True)
    for r in results:
        report(r)
    def finish_one(p, result, note=""):
        p["out"].flush()
        p["out"].seek(0)
        text = p["out"].read().decode("utf-8", "replace")
        p["out"].close()
        dur = time.time() - p["start"]
        r = {"name": p["t"]["name"], "suite": p["t"]["suite"], "result": result,
             "returncode": p["proc"].returncode, "duration": round(dur, 2)}
        if note:
            r["note"] = note
        results.append(r)
        log.write("==== %s (%s) %s rc=%s %.1f s\n$ %s %s\n%s\n" % (
            r["name"], ",".join(r["suite"]), result, r["returncode"], dur,
            " ".join("%s=%s" % kv for kv in p["env"]), " ".join(p["cmd"]), text[-200000:]))
        log.flush()
        report(r)
    def kill(p):
        try:
            os.killpg(p["proc"].pid, signal.SIGTERM)
        except OSError:
            pass
        try:
            p["proc"].wait(5)
        except subprocess.TimeoutExpired:
            try:
                os.killpg(p["proc"].pid, signal.SIGKILL)
            except OSError:
                pass
            p["proc"].wait()
    import tempfile
    while queue or running:
        now = time.time()
        while queue and len(running) < jobs and now < deadline:
            t = queue.pop(0)
            cmd = [remap(c) for c in t["cmd"]]
            env = dict(os.environ)
            for k, v in (t.get("env") or {}).items():
                env[k] = remap(v)
            env.setdefault("MALLOC_PERTURB_", str(random.randint(1, 255)))
            out = tempfile.TemporaryFile()
            cwd = remap(t["workdir"]) if t.get("workdir") else build
            try:
                proc = subprocess.Popen(cmd, cwd=cwd, env=env, stdin=subprocess.DEVNULL,
                                        stdout=out, stderr=subprocess.STDOUT,
                                        start_new_session=True)
            except OSError as e:
                results.append({"name": t["name"], "suite": t["suite"], "result": "FAIL",
                                "returncode": None, "duration": 0, "note": str(e)})
                log.write("==== %s FAIL: cannot start %s: %s\n" % (t["name"], cmd, e))
                report(results[-1])
                out.close()
                continue
            tmo = t.get("timeout") or 0
            running.append({"t": t, "cmd": cmd, "proc": proc, "out": out, "start": now,
                            "env": [(k, env[k]) for k in sorted(t.get("env") or {})],
                            "end": now + tmo if tmo > 0 else None})
        if not running and now >= deadline:
            break
        time.sleep(0.2)
        now = time.time()
        for p in list(running):
            rc = p["proc"].poll()
            if rc is not None:
                running.remove(p)
                finish_one(p, "OK" if rc == 0 else ("SKIP" if rc == 77 else "FAIL"))
            elif p["end"] is not None and now > p["end"]:
                running.remove(p)
                kill(p)
                finish_one(p, "TIMEOUT", "its own timeout, %d s" % p["t"]["timeout"])
            elif now >= deadline:
                running.remove(p)
                kill(p)
                finish_one(p, "CUT", "stopped by the suite's cap")
    for t in queue:
        results.append({"name": t["name"], "suite": t["suite"], "result": "NOTRUN",
                        "returncode": None, "duration": 0, "note": "not started before the cap"})
        report(results[-1])
    log.close()
    json.dump({"runner": "own", "tests": results}, open(outjson, "w"), indent=1)
    return 0

# ---- meson's own log (meson-logs/NAME.json, one JSON object a line) in the
# same form; tests meson listed but never logged were cut by the cap.
def meson_results(logjson, listed, outjson):
    tests = []
    seen = set()
    if os.path.exists(logjson):
        for line in open(logjson):
            line = line.strip()
            if not line:
                continue
            try:
                d = json.loads(line)
            except ValueError:
                continue
            res = d.get("result", "ERROR")
            if res in ("ERROR", "UNEXPECTEDPASS", "INTERRUPT"):
                res = "FAIL" if res != "INTERRUPT" else "CUT"
            if res == "EXPECTEDFAIL":
                res = "OK"
            full = d.get("name", "?")
            seen.add(full)
            suite, _, short = full.rpartition(" / ")
            tests.append({"name": short, "suite": [suite] if suite else [], "result": res,
                          "returncode": d.get("returncode"),
                          "duration": round(d.get("duration") or 0, 2)})
    for full in open(listed).read().split("\n"):
        full = full.strip()
        if " / " not in full or full in seen:
            continue
        suite, _, short = full.rpartition(" / ")
        tests.append({"name": short, "suite": [suite], "result": "NOTRUN", "returncode": None,
                      "duration": 0, "note": "not finished before the cap"})
    json.dump({"runner": "meson", "tests": tests}, open(outjson, "w"), indent=1)
    return 0

def suite_summary(tests):
    s = {"passed": 0, "failed": 0, "timed_out": 0, "skipped": 0, "cut_by_cap": 0, "not_run": 0}
    key = {"OK": "passed", "FAIL": "failed", "TIMEOUT": "timed_out", "SKIP": "skipped",
           "CUT": "cut_by_cap", "NOTRUN": "not_run"}
    for t in tests:
        s[key.get(t["result"], "failed")] += 1
    def label(t):  # "suite/name": two suites have a test named gather
        return "/".join([x.split(":", 1)[-1] for x in t["suite"][:1]] + [t["name"]])
    s["failures"] = [label(t) for t in tests if t["result"] == "FAIL"]
    s["timeouts"] = [label(t) for t in tests if t["result"] == "TIMEOUT"]
    s["cut"] = [label(t) for t in tests if t["result"] in ("CUT", "NOTRUN")]
    s["skips"] = [label(t) for t in tests if t["result"] == "SKIP"]
    return s

def readme_table(rows, ratios, scenes, methods):
    by = {(r.get("scene"), r.get("method")): r for r in rows}
    scenes = [s for s in scenes if any(k[0] == s for k in by)]
    if not scenes:
        return ""
    names = [os.path.splitext(os.path.basename(s))[0] for s in scenes]
    out = ["| frame ms / NRMSE | " + " | ".join(names) + " |",
           "|---|" + "---|" * len(names)]
    for m in methods:
        cells = []
        for s in scenes:
            r = by.get((s, m))
            cells.append("%s / %s" % (fmt_ms(r.get("frame_ms")), fmt_err(r.get("nrmse"))) if r else "-")
        out.append("| %s | %s |" % (m, " | ".join(cells)))
    rat = {r.get("scene"): r for r in ratios}
    for key, label in (("progressive_over_cross", "progressive / cross"),
                       ("incremental_over_cross", "incremental / cross")):
        if any(key in rat.get(s, {}) for s in scenes):
            out.append("| %s | %s |" % (label, " | ".join(
                ("%.1fx" % rat[s][key]) if key in rat.get(s, {}) else "-" for s in scenes)))
    return "\n".join(out)

def read(path, default=""):
    try:
        return open(path).read()
    except OSError:
        return default

def assemble(tmpd, out, started, elapsed, budget, build, device, scenes, methods, repeat, status):
    steps = []
    for line in read(os.path.join(tmpd, "steps.tsv")).splitlines():
        f = line.split("\t")
        if len(f) >= 4:
            steps.append({"step": f[0], "status": f[1], "seconds": int(f[2] or 0), "message": f[3]})
    devices = [l for l in read(os.path.join(tmpd, "devices.txt")).splitlines() if l.strip()]
    chosen = read(os.path.join(tmpd, "device-name.txt")).strip() or None
    probe_path = read(os.path.join(tmpd, "probe-path.txt")).strip() or None
    scene_list = [s for s in scenes.split(",") if s]
    method_list = [m for m in methods.split(",") if m]
    rows, ratios = [], []
    failed_scenes = read(os.path.join(tmpd, "bench-failed.txt")).split()
    for i, s in enumerate(scene_list):
        p = os.path.join(tmpd, "bench-%d.json" % i)
        try:
            d = json.load(open(p))
        except (OSError, ValueError):
            continue
        rows += d.get("rows", [])
        ratios += d.get("ratios", [])
    variant_rows = {"layered": [], "pairs": [], "mips1": []}
    for v, vrows in variant_rows.items():
        for i, s in enumerate(scene_list):
            try:
                vrows += json.load(open(os.path.join(tmpd, "%s-%d.json" % (v, i)))).get("rows", [])
            except (OSError, ValueError):
                continue
    pair_rows = variant_rows["pairs"]
    bench_paths = sorted({r.get("hemicube_path") for r in rows if r.get("hemicube_path") not in (None, "-")})
    path = probe_path or (bench_paths[0] if bench_paths else None)
    suite = None
    sp = os.path.join(tmpd, "suite.json")
    if os.path.exists(sp):
        d = json.load(open(sp))
        suite = {"runner": d.get("runner"), "cap_s": int(read(os.path.join(tmpd, "suite-cap.txt"), "0") or 0)}
        suite.update(suite_summary(d["tests"]))
        suite["tests"] = d["tests"]
    table = readme_table(rows, ratios, scene_list, method_list)
    pack = {}
    for line in read(os.path.join(build, "gpu-check-pack.txt")).splitlines():
        k, _, v = line.partition(" ")
        pack[k] = v
    nvsmi = read(os.path.join(tmpd, "nvidia-smi.txt")).strip() or None
    doc = {
        "tool": "tools/gpu-check.sh",
        "started": started,
        "elapsed_s": int(elapsed),
        "budget_s": int(budget),
        "status": "ok" if status == "0" else "failed",
        "exit_status": int(status),
        "host": {"uname": os.uname().release + " " + os.uname().machine,
                 "cpus": os.cpu_count(), "nvidia_smi": nvsmi},
        "build": {"dir": build, "pack": pack or None,
                  "checkout": read(os.path.join(tmpd, "checkout.txt")).strip() or None},
        "device": {"wanted": device, "name": chosen, "devices": devices,
                   "vk_driver_files": os.environ.get("VK_DRIVER_FILES") or
                   read(os.path.join(tmpd, "driver-files.txt")).strip() or None},
        "hemicube_path": path,
        "hemicube_path_bench": bench_paths,
        "steps": steps,
        "suite": suite,
        "bench": {"scenes": scene_list, "methods": method_list, "repeat": int(repeat),
                  "rows": rows, "ratios": ratios, "failed_scenes": failed_scenes,
                  "layered_path_rows": variant_rows["layered"],
                  "cross_pairs_on_rows": pair_rows,
                  "cross_back_mips_grid1_rows": variant_rows["mips1"]},
        "readme_table": table,
    }
    def clean(v):  # strict JSON: NaN and infinities as null
        if isinstance(v, float) and (v != v or v in (float("inf"), float("-inf"))):
            return None
        if isinstance(v, dict):
            return {k: clean(x) for k, x in v.items()}
        if isinstance(v, list):
            return [clean(x) for x in v]
        return v
    with open(out, "w") as f:
        json.dump(clean(doc), f, indent=1, allow_nan=False)
        f.write("\n")
    # The summary: the end of the console output.
    print("\n================ gpu-check summary ================")
    print("device:         %s" % (chosen or "none"))
    print("hemicube path:  %s" % (path or "unknown"))
    for s in steps:
        print("step %-10s %-7s %4d s  %s" % (s["step"], s["status"], s["seconds"], s["message"]))
    if suite:
        print("suite (%s runner, cap %d s): %d passed, %d failed, %d timed out, %d skipped, "
              "%d cut by the cap" % (suite["runner"], suite["cap_s"], suite["passed"], suite["failed"],
                                     suite["timed_out"], suite["skipped"],
                                     suite["cut_by_cap"] + suite["not_run"]))
        for k in ("failures", "timeouts", "cut", "skips"):
            if suite[k]:
                print("  %-9s %s" % (k + ":", " ".join(suite[k])))
    if rows:
        print("%-28s %-12s %10s %10s %8s %8s  passes (median GPU ms per frame)" % (
            "scene", "method", "frame_ms", "gpu_ms", "nrmse", "surf_err"))
        for r in rows:
            passes = " ".join("%s %s" % (k, fmt_ms(v)) for k, v in (r.get("passes") or {}).items())
            print("%-28s %-12s %10s %10s %8s %8s  %s" % (
                r.get("scene"), r.get("method"), fmt_ms(r.get("frame_ms")), fmt_ms(r.get("gpu_ms")),
                fmt_err(r.get("nrmse")), fmt_err(r.get("surface_error")), passes))
        print("\n" + table)
    for label, vrows in (("+layered", variant_rows["layered"]), ("cross+pairs", pair_rows),
                         ("cross+mips1", variant_rows["mips1"])):
        for r in vrows:
            name = r.get("method", "") + label if label == "+layered" else label
            passes = " ".join("%s %s" % (k, fmt_ms(v)) for k, v in (r.get("passes") or {}).items())
            print("%-28s %-12s %10s %10s %8s %8s  %s" % (
                r.get("scene"), name, fmt_ms(r.get("frame_ms")), fmt_ms(r.get("gpu_ms")),
                fmt_err(r.get("nrmse")), fmt_err(r.get("surface_error")), passes))
    if failed_scenes:
        print("bench failed on: %s" % " ".join(failed_scenes))
    return 0

if __name__ == "__main__":
    cmd = sys.argv[1]
    a = sys.argv[2:]
    if cmd == "run":
        sys.exit(run_suite(a[0], a[1], int(a[2]), float(a[3]), a[4], a[5], a[6], a[7]))
    if cmd == "meson":
        sys.exit(meson_results(a[0], a[1], a[2]))
    if cmd == "assemble":
        sys.exit(assemble(*a))
    if cmd == "expired":
        print(max(0, int(float(a[0]) - time.time())))
        sys.exit(0)
    sys.exit("unknown helper command %s" % cmd)
PYEOF

echo "gpu-check: $(date -u +%Y-%m-%dT%H:%M:%SZ), $(uname -srm), $(nproc) cores, build $BUILD, budget $BUDGET s"
{ git -C "$REPO" rev-parse HEAD 2>/dev/null || echo unknown; } >"$TMPD/checkout.txt"
if [ -f "$BUILD/gpu-check-pack.txt" ]; then
    echo "gpu-check: carried build: $(tr '\n' ';' <"$BUILD/gpu-check-pack.txt" | cut -c1-300)"
    built=$(awk '$1 == "built_from" {print $2}' "$BUILD/gpu-check-pack.txt")
    here=$(cat "$TMPD/checkout.txt")
    [ "$here" = unknown ] || [ "${built%+local-changes}" = "$here" ] ||
        echo "gpu-check: warning: the build was made from $built, this checkout is $here"
fi
if command -v nvidia-smi >/dev/null 2>&1; then
    nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader >"$TMPD/nvidia-smi.txt" 2>&1
    echo "gpu-check: nvidia-smi: $(head -3 "$TMPD/nvidia-smi.txt" | tr '\n' ' ')"
fi

# --------------------------------------------------------- 1. carried .debs --

if [ -n "$DEBS" ]; then
    say "debs: unpacking $DEBS into $DEBS_ROOT"
    t0=$SECONDS
    ok=1
    msg=
    if ! command -v dpkg >/dev/null 2>&1; then
        ok=0; msg="no dpkg on this machine"
    elif ! ls "$DEBS"/*.deb >/dev/null 2>&1; then
        ok=0; msg="no .deb files in $DEBS (tools/gpu-check.sh --prepare downloads them; carry the folder)"
    else
        mkdir -p "$DEBS_ROOT" || { ok=0; msg="cannot make $DEBS_ROOT"; }
        n=0
        for f in "$DEBS"/*.deb; do
            [ "$ok" = 1 ] || break
            dpkg -x "$f" "$DEBS_ROOT" || { ok=0; msg="dpkg -x $f failed"; }
            n=$((n + 1))
        done
        root=$(cd "$DEBS_ROOT" && pwd)
        if [ "$ok" = 1 ] && [ "$root" = / ]; then
            msg="$n packages into /, ldconfig"
            ldconfig || { ok=0; msg="ldconfig failed"; }
        elif [ "$ok" = 1 ]; then
            # Only what the system lacks: a folder of links to the unpacked
            # libraries whose names the system's loader cache does not know,
            # first on LD_LIBRARY_PATH. No system file changes.
            known=$(ldconfig -p 2>/dev/null | awk 'NR > 1 {print $1}' | sort -u)
            fb=$root/fallback-lib
            rm -rf "$fb" && mkdir -p "$fb"
            linked=
            nlinked=0
            for d in "$root/usr/lib/x86_64-linux-gnu" "$root/lib/x86_64-linux-gnu" "$root/usr/lib"; do
                [ -d "$d" ] || continue
                # Real files behind a soname link (libfoo.so.1.2.3) are
                # reached through the link.
                behind=" "
                for so in "$d"/*.so*; do
                    [ -L "$so" ] && behind="$behind$(basename "$(readlink "$so")") "
                done
                for so in "$d"/*.so*; do
                    [ -e "$so" ] || continue
                    name=$(basename "$so")
                    case $behind in *" $name "*) [ -L "$so" ] || continue ;; esac
                    if ! printf '%s\n' "$known" | grep -qxF "$name" && [ ! -e "$fb/$name" ]; then
                        ln -s "$so" "$fb/$name" && linked="$linked $name" && nlinked=$((nlinked + 1))
                    fi
                done
            done
            export LD_LIBRARY_PATH="$fb${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
            msg="$n packages into $root; $nlinked files the system lacks, used from $fb"
            echo "gpu-check: used from the .debs (the system has none of these):${linked:- none}"
        fi
        # Their validation layer (the tests turn it on), where the system
        # has none.
        sys_layer=0
        for d in /usr/share/vulkan/explicit_layer.d /etc/vulkan/explicit_layer.d /usr/local/share/vulkan/explicit_layer.d; do
            [ -f "$d/VkLayer_khronos_validation.json" ] && sys_layer=1
        done
        if [ "$ok" = 1 ] && [ "$root" != / ] && [ "$sys_layer" = 0 ] &&
            [ -f "$root/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json" ]; then
            lp=$root/usr/share/vulkan/explicit_layer.d
            for d in /usr/share/vulkan/explicit_layer.d /etc/vulkan/explicit_layer.d /usr/local/share/vulkan/explicit_layer.d; do
                [ -d "$d" ] && lp="$lp:$d"
            done
            export VK_LAYER_PATH="$lp${VK_LAYER_PATH:+:$VK_LAYER_PATH}"
            echo "gpu-check: the validation layer from the .debs: VK_LAYER_PATH=$VK_LAYER_PATH"
        fi
    fi
    # glvnd for the NVIDIA driver, into / as the device README does for
    # the loaders (a private root is not enough: the driver is dlopened by
    # name through the system's loader cache).
    if [ "$ok" = 1 ] && ls "$DEBS"/gl/*.deb >/dev/null 2>&1 &&
        ! ldconfig -p 2>/dev/null | grep -q 'libGLdispatch\.so\.0'; then
        if [ "$(id -u)" = 0 ]; then
            for f in "$DEBS"/gl/*.deb; do dpkg -x "$f" / || { ok=0; msg="dpkg -x $f / failed"; }; done
            ldconfig || ok=0
            [ "$ok" = 0 ] || msg="$msg; glvnd ($GL_PACKAGES) into /, ldconfig"
        else
            echo "gpu-check: warning: no libGLdispatch.so.0 here and not root: the NVIDIA driver may not load"
        fi
    fi
    echo "gpu-check: $msg"
    if [ "$ok" = 1 ]; then step debs ok $((SECONDS - t0)) "$msg"; else step debs failed $((SECONDS - t0)) "$msg"; STATUS=2; finish; fi
fi

# ------------------------------------------------- 2. loader and libraries --

say "libraries: the Vulkan loader, and what the xrad binaries need"
t0=$SECONDS
XRAD=$BUILD/tools/xrad
if [ ! -x "$XRAD" ]; then
    msg="$XRAD is missing: pass --build DIR (a meson build, or build-gpu made by --prepare and carried)"
    echo "gpu-check: $msg"
    step libraries failed 0 "$msg"
    STATUS=2
    finish
fi
missing=
# What the dynamic loader finds for the binary first (a stale ld.so.cache
# lists no loader that the default directories hold), then the cache.
if ! ldd "$XRAD" 2>/dev/null | grep -q 'libvulkan\.so\.1 => /' &&
    ! ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1' &&
    ! { [ -n "${LD_LIBRARY_PATH:-}" ] && printf '%s' "$LD_LIBRARY_PATH" | tr ':' '\n' |
        while read -r d; do [ -n "$d" ] && [ -e "$d/libvulkan.so.1" ] && echo y; done | grep -q y; }; then
    echo "gpu-check: no Vulkan loader (libvulkan.so.1) in ldconfig -p or LD_LIBRARY_PATH"
    missing=" libvulkan.so.1"
fi
checked=0
for f in "$XRAD" $(build_elves "$BUILD" | grep -v "^$XRAD\$"); do
    checked=$((checked + 1))
    for lib in $(ldd "$f" 2>&1 | awk '/=> not found/ {print $1}'); do
        case "$missing " in *" $lib "*) ;; *) missing="$missing $lib" ;; esac
    done
done
# ldd also reports "version `GLIBC_2.34' not found": the C library is too old.
old_libc=$(ldd "$XRAD" 2>&1 | grep "version .* not found" | head -3)
if [ -n "$missing" ] || [ -n "$old_libc" ]; then
    echo "gpu-check: missing on this machine, among $checked binaries:"
    pk=
    for lib in $missing; do
        p=$(package_of "$lib")
        if [ -z "$p" ]; then
            echo "  $lib  (package: 'dpkg -S $lib' on the machine that built xrad)"
            continue
        fi
        echo "  $lib  (Debian 12 package $p)"
        case " $pk " in *" $p "*) ;; *) pk="$pk $p" ;; esac
    done
    [ -z "$old_libc" ] || printf '%s\n' "$old_libc" | sed 's/^/  /'
    echo "gpu-check: bring them as .deb files: here, with network, 'tools/gpu-check.sh"
    echo "  --prepare' downloads every runtime package of the build into build-debs/"
    [ -z "$pk" ] || echo "  (or by hand: mkdir -p build-debs && cd build-debs && apt-get download$pk)"
    echo "  then carry build-debs and pass '--debs build-debs' on the GPU machine"
    echo "  (dpkg -x into a private root; its libraries are used only where the system has none)."
    [ -z "$old_libc" ] || echo "gpu-check: the C library here is older than the build's: build on an older Debian, or build here"
    step libraries failed $((SECONDS - t0)) "missing:$missing${old_libc:+ (and a newer glibc)}"
    STATUS=2
    finish
fi
layer_ok=0
for d in $(printf '%s' "${VK_LAYER_PATH:-}" | tr ':' ' ') /usr/share/vulkan/explicit_layer.d /etc/vulkan/explicit_layer.d /usr/local/share/vulkan/explicit_layer.d; do
    [ -f "$d/VkLayer_khronos_validation.json" ] && layer_ok=1
done
msg="loader and all libraries present ($checked binaries)"
if [ "$layer_ok" = 0 ]; then
    msg="$msg; no Khronos validation layer: the tests will fail (XRAD_VALIDATION=1); carry vulkan-validationlayers in --debs"
fi
echo "gpu-check: $msg"
step libraries ok $((SECONDS - t0)) "$msg"

# ------------------------------------------------------------- 3. device --

say "device: xrad devices${DEVICE:+ (wanted: $DEVICE)}"
t0=$SECONDS
DEV_ARGS=()
if [ "$DEVICE" != auto ]; then
    DEV_ARGS=(--device "$DEVICE")
    export XRAD_DEVICE=$DEVICE
fi
list_devices() {
    timeout 60 "$XRAD" devices "${DEV_ARGS[@]}" >"$TMPD/devices.txt" 2>"$TMPD/devices.err"
}
list_devices
rc=$?
# Where the GPU machine's NVIDIA driver keeps its Vulkan file (device README;
# GPU_CHECK_NVIDIA_ICD replaces it, to test this path elsewhere).
NV_ICD=${GPU_CHECK_NVIDIA_ICD:-/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json}
if [ "$rc" != 0 ] && [ -z "${VK_DRIVER_FILES:-}" ] && [ -f "$NV_ICD" ]; then
    echo "gpu-check: no device found ($(head -c 300 "$TMPD/devices.err" | tr '\n' ' ')); pointing the loader at $NV_ICD"
    export VK_DRIVER_FILES=$NV_ICD VK_ICD_FILENAMES=$NV_ICD
    export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
    echo "$NV_ICD" >"$TMPD/driver-files.txt"
    # The driver's library by bare name, where the loader cache lacks it.
    icdlib=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["ICD"]["library_path"])' "$NV_ICD" 2>/dev/null) || icdlib=
    case $icdlib in
    "" | /*) ;;
    *)
        if ! ldconfig -p | grep -qF "$icdlib"; then
            for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do
                [ -e "$d/$icdlib" ] && export LD_LIBRARY_PATH="${LD_LIBRARY_PATH:+$LD_LIBRARY_PATH:}$d" &&
                    echo "gpu-check: $icdlib from $d" && break
            done
        fi
        ;;
    esac
    list_devices
    rc=$?
fi
cat "$TMPD/devices.txt"
[ ! -s "$TMPD/devices.err" ] || sed 's/^/  stderr: /' "$TMPD/devices.err" | head -20
# "* NAME (padded) TYPE Vulkan x.y.z  N MiB device-local": the starred name.
chosen=$(sed -n '/^\* /{s/^\* //;s/ \{1,\}[^ ]\{1,\} \{1,\}Vulkan [0-9].*$//;p;q;}' "$TMPD/devices.txt")
if [ "$rc" != 0 ] || [ -z "$chosen" ]; then
    msg="no Vulkan device (xrad devices exit $rc)"
    [ "$DEVICE" = auto ] || msg="no Vulkan device named like '$DEVICE' (xrad devices exit $rc)"
    echo "gpu-check: $msg"
    [ ! -f "$NV_ICD" ] || echo "gpu-check: $NV_ICD: $(tr -d '\n' <"$NV_ICD" | head -c 300)"
    printf 'gpu-check: Vulkan driver files here:'
    for f in /usr/share/vulkan/icd.d/* /etc/vulkan/icd.d/* /usr/local/share/vulkan/icd.d/* /usr/local/nvidia/share/vulkan/icd.d/*; do
        [ -e "$f" ] && printf ' %s' "$f"
    done
    echo
    step device failed $((SECONDS - t0)) "$msg"
    STATUS=2
    finish
fi
echo "$chosen" >"$TMPD/device-name.txt"
echo "gpu-check: device: $chosen"
step device ok $((SECONDS - t0)) "$chosen"

# ------------------------------------------------- 4. the hemicube path --

say "probe: xrad render scenes/cornell-lowq.json --method progressive (the hemicube path)"
t0=$SECONDS
timeout 120 "$XRAD" render scenes/cornell-lowq.json --method progressive --width 64 --height 64 \
    --out "$TMPD/probe.png" --quiet "${DEV_ARGS[@]}" >"$TMPD/probe.txt" 2>&1
rc=$?
cat "$TMPD/probe.txt"
hpath=$(sed -n 's/.*hemicube path \([a-z-]*\)).*/\1/p' "$TMPD/probe.txt" | head -1)
if [ "$rc" = 0 ] && [ -n "$hpath" ]; then
    echo "$hpath" >"$TMPD/probe-path.txt"
    echo "gpu-check: hemicube path: $hpath"
    step probe ok $((SECONDS - t0)) "hemicube path $hpath"
else
    step probe failed $((SECONDS - t0)) "xrad render exit $rc"
    STATUS=1
fi

# --------------------------------------------------------------- 5. bench --

if [ "$DO_BENCH" = 1 ]; then
    say "bench: $SCENES, methods $METHODS, --repeat $REPEAT, cap $BENCH_TIMEOUT s"
    t0=$SECONDS
    bench_end=$((SECONDS + BENCH_TIMEOUT))
    failed=
    : >"$LOGDIR/bench.txt"
    i=0
    IFS=, read -r -a scene_arr <<<"$SCENES"
    for s in "${scene_arr[@]}"; do
        left=$((bench_end - SECONDS))
        if [ ! -f "$s" ]; then
            echo "gpu-check: no scene file $s" | tee -a "$LOGDIR/bench.txt"
            failed="$failed $s"
        elif [ "$left" -le 5 ]; then
            echo "gpu-check: $s not run: the bench's $BENCH_TIMEOUT s are spent" | tee -a "$LOGDIR/bench.txt"
            failed="$failed $s"
        else
            args=("$s" --methods "$METHODS" --repeat "$REPEAT" --cache "$CACHE"
                --json "$TMPD/bench-$i.json" "${DEV_ARGS[@]}")
            [ -z "$MAX_REF" ] || args+=(--max-reference-elements "$MAX_REF")
            echo "\$ xrad bench ${args[*]}" >>"$LOGDIR/bench.txt"
            bt0=$SECONDS
            timeout -k 10 "$left" "$XRAD" bench "${args[@]}" 2>&1 | tee -a "$LOGDIR/bench.txt"
            rc=$?
            if [ "$rc" != 0 ]; then
                [ "$rc" != 124 ] || echo "gpu-check: $s: stopped by the bench's cap" | tee -a "$LOGDIR/bench.txt"
                echo "gpu-check: $s: xrad bench exit $rc" | tee -a "$LOGDIR/bench.txt"
                rm -f "$TMPD/bench-$i.json"
                failed="$failed $s"
            fi
            echo "gpu-check: $s: $((SECONDS - bt0)) s" | tee -a "$LOGDIR/bench.txt"
        fi
        i=$((i + 1))
    done
    # Choices a GPU decides, beside the default loop, where the bench left
    # time: first the layered hemicube path for incremental and cross where
    # the start-up check chose multiview (the first GPU run spent 9.7 of
    # cross's 32 ms a frame on the host, recording about 300 render pass
    # instances on the multiview path, where the layered one draws a pass's
    # hemicubes in one instance); then cross's options (README "The cross
    # projection's work"): the pair list (on lavapipe it costs more than it
    # saves), then one ray a pair read through mipmapped back hemicubes.
    case ",$METHODS," in *,cross,*)
        for variant in layered pairs mips1; do
            venv=() vmethods=cross
            case $variant in
            layered) venv=(XRAD_HEMICUBE_PATH=layered) vmethods=incremental,cross
                     grep -qE '"hemicube_path":[[:space:]]*"multiview"' "$TMPD"/bench-*.json 2>/dev/null ||
                         continue ;;
            pairs) vargs=(--cross-pairs on) ;;
            mips1) vargs=(--back-mips on --cross-grid 1) ;;
            esac
            [ "$variant" != layered ] || vargs=()
            i=0
            for s in "${scene_arr[@]}"; do
                left=$((bench_end - SECONDS))
                if [ -f "$s" ] && [ "$left" -gt 5 ]; then
                    args=("$s" --methods "$vmethods" --repeat "$REPEAT" --cache "$CACHE" "${vargs[@]}"
                        --json "$TMPD/$variant-$i.json" "${DEV_ARGS[@]}")
                    [ -z "$MAX_REF" ] || args+=(--max-reference-elements "$MAX_REF")
                    echo "\$ ${venv[*]} xrad bench ${args[*]}" >>"$LOGDIR/bench.txt"
                    env "${venv[@]}" timeout -k 10 "$left" "$XRAD" bench "${args[@]}" \
                        >>"$LOGDIR/bench.txt" 2>&1 || rm -f "$TMPD/$variant-$i.json"
                fi
                i=$((i + 1))
            done
        done ;;
    esac
    echo "$failed" >"$TMPD/bench-failed.txt"
    if [ -z "$failed" ]; then
        step bench ok $((SECONDS - t0)) "${#scene_arr[@]} scenes"
    else
        step bench failed $((SECONDS - t0)) "failed:$failed"
        STATUS=1
    fi
fi

# --------------------------------------------------------------- 6. suite --

if [ "$DO_SUITE" = 1 ]; then
    left=$((BUDGET - SECONDS - 15))
    cap=$left
    [ -z "$SUITE_TIMEOUT" ] || cap=$SUITE_TIMEOUT
    say "suite: ${SUITES:-all}, $JOBS at a time, cap $cap s, device ${XRAD_DEVICE:-xrad default}"
    t0=$SECONDS
    if [ -z "$SUITE_TIMEOUT" ] && [ "$cap" -lt 20 ]; then
        msg="not run: only $cap s left of the $BUDGET s budget (--budget, --suite-timeout)"
        echo "gpu-check: $msg"
        step suite failed 0 "$msg"
        STATUS=1
    else
        echo "$cap" >"$TMPD/suite-cap.txt"
        runner=$RUNNER
        if [ "$runner" = auto ]; then
            runner=own
            if [ -f "$BUILD/build.ninja" ] && command -v meson >/dev/null 2>&1; then
                same=$(python3 -c '
import json, os, sys
i = json.load(open(os.path.join(sys.argv[1], "meson-info", "meson-info.json")))
print(int(os.path.realpath(i["directories"]["build"]) == os.path.realpath(sys.argv[1])
          and os.path.realpath(i["directories"]["source"]) == os.path.realpath(sys.argv[2])
          and i["meson_version"]["full"] == sys.argv[3]))' "$BUILD" "$REPO" "$(meson --version 2>/dev/null)" 2>/dev/null)
                [ "$same" = 1 ] && runner=meson
            fi
        fi
        skip=$SKIP
        if [ ! -e "$MODELS" ] && [ -d "$BUILD/assimp-models" ] && [ "$(id -u)" = 0 ] &&
            mkdir -p "$(dirname "$MODELS")" && ln -s "$(cd "$BUILD/assimp-models" && pwd)" "$MODELS"; then
            echo "gpu-check: $MODELS: the carried test models ($TEST_MODELS)"
        fi
        if [ ! -d "$MODELS" ]; then
            for t in models scene_files mesh_corners cli; do
                case ",$skip," in *,"$t",*) ;; *) skip=$(add_list "$skip" "$t") ;; esac
            done
            echo "gpu-check: leaving out models, scene_files, mesh_corners and cli: no $MODELS (Debian package assimp-testmodels)"
        fi
        echo "gpu-check: runner $runner"
        if [ "$runner" = meson ]; then
            margs=(-C "$BUILD" --no-rebuild --num-processes "$JOBS" --logbase gpu-check-testlog)
            IFS=, read -r -a suite_arr <<<"$SUITES"
            for x in "${suite_arr[@]}"; do [ -z "$x" ] || margs+=(--suite "$x"); done
            meson test "${margs[@]}" --list 2>/dev/null | grep -v '^ninja' >"$TMPD/suite-list.txt"
            # --skip: meson has no per-test exclusion; name the others.
            names=()
            if [ -n "$skip" ]; then
                while read -r t; do
                    short=${t##* / }
                    case ",$skip," in *",$short,"*) ;; *) names+=("$short") ;; esac
                done <"$TMPD/suite-list.txt"
            fi
            rm -f "$BUILD/meson-logs/gpu-check-testlog.json" "$BUILD/meson-logs/gpu-check-testlog.txt"
            timeout -s TERM -k 30 "$cap" meson test "${margs[@]}" "${names[@]}"
            rc=$?
            [ "$rc" != 124 ] || echo "gpu-check: the suite was stopped by its $cap s cap"
            python3 -c "$PY" meson "$BUILD/meson-logs/gpu-check-testlog.json" "$TMPD/suite-list.txt" "$TMPD/suite.json"
            cp "$BUILD/meson-logs/gpu-check-testlog.txt" "$LOGDIR/testlog.txt" 2>/dev/null
        else
            # The build suite compiles against the sources' headers, the
            # build tree and the -dev packages, none of which a carried
            # build has.
            for t in install layers headers; do
                case ",$skip," in *,"$t",*) ;; *) skip=$(add_list "$skip" "$t") ;; esac
            done
            echo "gpu-check: leaving out install, layers and headers: they build from the sources with the -dev packages (runner own)"
            deadline=$(python3 -c 'import sys, time; print(time.time() + float(sys.argv[1]))' "$cap")
            python3 -c "$PY" run "$BUILD" "$REPO" "$JOBS" "$deadline" "$SUITES" "$skip" \
                "$LOGDIR/testlog.txt" "$TMPD/suite.json"
            rc=$?
        fi
        if [ ! -f "$TMPD/suite.json" ]; then
            step suite failed $((SECONDS - t0)) "the $runner runner gave no results (exit $rc)"
            STATUS=1
        else
            if bad=$(python3 -c '
import json, sys
t = json.load(open(sys.argv[1]))["tests"]
n = lambda *r: sum(1 for x in t if x["result"] in r)
print("%d passed, %d failed, %d timed out, %d skipped, %d cut by the cap%s" % (
    n("OK"), n("FAIL"), n("TIMEOUT"), n("SKIP"), n("CUT", "NOTRUN"),
    "" if t else "; no test matched --suite"))
sys.exit(1 if n("FAIL", "TIMEOUT") or not t else 0)' "$TMPD/suite.json"); then
                step suite ok $((SECONDS - t0)) "$bad"
            else
                step suite failed $((SECONDS - t0)) "$bad"
                STATUS=1
            fi
        fi
    fi
fi

finish
