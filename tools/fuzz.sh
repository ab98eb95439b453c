#!/bin/sh
# Fuzzes one parser: tools/fuzz.sh NAME SECONDS
#
# NAME is a harness in tests/fuzz/ (fuzz_NAME.c; `scene` is the scene
# parser's). Builds it in build-fuzz with clang, libFuzzer, AddressSanitizer
# and UndefinedBehaviorSanitizer, then runs it for SECONDS on a fresh copy of
# its seeds (tests/fuzz/run.sh; FUZZ_SEED picks the mutations, default 1,
# 0 random). Prints libFuzzer's execution count. Exits 0
# when nothing was found; non-zero on a crash, leak, hang or undefined
# behaviour, with the input saved under build-fuzz/tests/fuzz/out-NAME/ (copy
# it to tests/fuzz/regressions/NAME/ so every build replays it).
set -eu
cd "$(dirname "$0")/.."

if [ $# -ne 2 ]; then
    names=$(for f in tests/fuzz/fuzz_*.c; do n=${f#tests/fuzz/fuzz_}; printf '%s ' "${n%.c}"; done)
    echo "usage: tools/fuzz.sh NAME SECONDS   (harnesses: $names)" >&2
    exit 2
fi
name=$1 seconds=$2
if [ ! -f "tests/fuzz/fuzz_$name.c" ]; then
    echo "fuzz.sh: no harness tests/fuzz/fuzz_$name.c" >&2
    exit 2
fi
case $seconds in
'' | *[!0-9]*)
    echo "fuzz.sh: SECONDS must be a whole number, not '$seconds'" >&2
    exit 2
    ;;
esac
if ! command -v clang >/dev/null 2>&1; then
    echo "fuzz.sh: needs clang with libFuzzer (Debian 12: apt-get install clang libclang-rt-14-dev)" >&2
    exit 2
fi

# werror off: a clang-only warning elsewhere in the tree must not stop the
# fuzzer from building (the gcc build keeps -Werror).
if [ ! -f build-fuzz/build.ninja ]; then
    CC=clang meson setup build-fuzz -Dfuzz=true -Db_sanitize=address,undefined \
        -Db_lundef=false -Dwerror=false
fi
ninja -C build-fuzz "tests/fuzz/fuzz_$name" >build-fuzz/compile.log 2>&1 ||
    { tail -n 40 build-fuzz/compile.log; exit 1; }
tests/fuzz/run.sh "build-fuzz/tests/fuzz/fuzz_$name" "$name" "$seconds" \
    "build-fuzz/tests/fuzz/out-$name"
