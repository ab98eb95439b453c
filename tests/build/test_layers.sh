#!/bin/sh
# The build enforces DESIGN.md's layers (issue 17.6): a layer's files are
# compiled with the include directories of its own layer and those below
# it alone (src/layers/LAYER/, one link per layer it may include). This
# test states the allowed layers itself, independently of those links, and
# checks by compiling probes that
#  - each layer's links are exactly the layers it may include;
#  - every header of a layer compiles alone with that layer's directories
#    (so it reaches nothing above it, and needs nothing it does not
#    include);
#  - an include of any layer above (or beside) it does not compile: the
#    probe fails, and fails for the missing file.
# Usage: test_layers.sh SOURCE_ROOT BUILD_ROOT CC [CC ARGS...]
set -u
src=$1
build=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fail=$((fail + 1)); }

# DESIGN.md "Layers": arrows point down; the CPU reference sits beside the
# GPU layers on scene and core.
allowed() {
    case $1 in
    core) echo "core" ;;
    scene) echo "core scene" ;;
    reference) echo "core scene reference" ;;
    gpu) echo "core scene gpu" ;;
    passes) echo "core scene gpu passes" ;;
    solvers) echo "core scene gpu passes solvers" ;;
    schedule) echo "core scene gpu passes solvers schedule" ;;
    render) echo "core scene gpu passes solvers schedule render" ;;
    esac
}
layers="core scene reference gpu passes solvers schedule render"

for layer in $layers; do
    want=$(allowed "$layer" | tr ' ' '\n' | sort | tr '\n' ' ')
    have=$(ls "$src/src/layers/$layer" 2>/dev/null | sort | tr '\n' ' ')
    if [ "$want" = "$have" ]; then ok; else bad "src/layers/$layer links '$have', DESIGN.md allows '$want'"; fi
    flags="-std=c11 -D_DEFAULT_SOURCE -fsyntax-only -I$src/include -I$build/include -I$src/spirv -I$build/spirv -I$src/src/layers/$layer"
    n=0
    for h in "$src/src/$layer"/*.h; do
        name=$(basename "$h")
        printf '#include "%s/%s"\n' "$layer" "$name" >"$tmp/probe.c"
        if "$@" $flags -c "$tmp/probe.c" -o /dev/null 2>"$tmp/err"; then
            ok
        else
            bad "$layer/$name does not compile alone with $layer's include directories:"
            head -5 "$tmp/err"
        fi
        n=$((n + 1))
    done
    [ "$n" -gt 0 ] || bad "layer $layer has no headers to probe"
    for other in $layers; do
        case " $(allowed "$layer") " in *" $other "*) continue ;; esac
        h=$(ls "$src/src/$other"/*.h | head -1)
        printf '#include "%s/%s"\n' "$other" "$(basename "$h")" >"$tmp/probe.c"
        if "$@" $flags -c "$tmp/probe.c" -o /dev/null 2>"$tmp/err"; then
            bad "$layer can include $other/$(basename "$h") (a higher or side layer)"
        elif grep -q "No such file" "$tmp/err"; then
            ok
        else
            bad "$layer's probe of $other failed, but not for the missing file:"
            head -5 "$tmp/err"
        fi
    done
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ] && [ "$pass" -gt 0 ]
