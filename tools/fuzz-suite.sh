#!/bin/sh
# Every libFuzzer harness for a short fixed time on its seeds (issue 7),
# as a meson test run in build-fuzz (clang, libFuzzer, ASan + UBSan):
#   tools/fuzz-suite.sh            suite 'robust' of the fuzz build
# Installs clang and its runtime from Debian when missing. The time per
# harness is fuzz_seconds in tests/fuzz/meson.build.
set -eu
cd "$(dirname "$0")/.."

missing=""
for p in clang libclang-rt-14-dev; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
        missing="$missing $p"
done
if [ -n "$missing" ]; then
    sudo=""
    [ "$(id -u)" = 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $missing
fi

# werror off: a clang-only warning must not stop the fuzzers (gcc keeps -Werror).
if [ ! -f build-fuzz/build.ninja ]; then
    CC=clang meson setup build-fuzz -Dfuzz=true -Db_sanitize=address,undefined \
        -Db_lundef=false -Dwerror=false >/dev/null
fi
meson compile -C build-fuzz >build-fuzz/compile.log 2>&1 ||
    { tail -n 40 build-fuzz/compile.log; exit 1; }
ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:abort_on_error=1
export ASAN_OPTIONS
exec meson test -C build-fuzz --suite robust --print-errorlogs "$@"
