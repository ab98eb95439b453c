#!/bin/sh
# The whole test suite under AddressSanitizer and UndefinedBehaviorSanitizer,
# with leak detection on, in build-asan:
#   tools/sanitize.sh                  every test
#   tools/sanitize.sh --suite core     extra arguments go to `meson test`
#   tools/sanitize.sh --setup sync     ... also with synchronization validation
# Any sanitizer report fails its test. The Vulkan drivers stay loaded until
# exit (src/gpu/driver_pin.c), so their unload causes no false leak and no
# suppression list is needed, except for the fault-injection test, where
# lavapipe itself at times keeps its queue work after an injected device
# loss (tests/gpu/lsan-lost-device.supp). CC picks the compiler (default: cc, gcc).
set -eu
cd "$(dirname "$0")/.."

if [ -f build-asan/build.ninja ]; then
    meson setup --reconfigure build-asan
else
    meson setup build-asan -Db_sanitize=address,undefined -Db_lundef=false
fi
meson compile -C build-asan >build-asan/compile.log 2>&1 ||
    { tail -n 40 build-asan/compile.log; exit 1; }

# meson test would otherwise set its own ASAN_OPTIONS (no leak option);
# abort_on_error makes every report a failed test. UBSAN_OPTIONS comes from
# tests/meson.build (halt_on_error=1).
ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:abort_on_error=1:print_summary=1
# Tests that read it leave out the cases on the big thesis scenes whose code
# the small scenes run too (test_dynamic): the sanitizers look for memory and
# undefined behaviour, which does not grow with the element count, and
# those cases took a third of this run.
XRAD_TEST_SMALL=1
export ASAN_OPTIONS XRAD_TEST_SMALL
# Instrumented, the GPU tests take up to 2.3 times the CPU time they take in
# the plain build (lavapipe itself is not instrumented) and the CPU-only
# ones up to 4 times (a few seconds; issue 14's measurements). Each test's
# timeout is at least 3 times its time in the plain build on a busy
# machine, so 3 times that here. A --timeout-multiplier given to this
# script comes later and wins.
exec meson test -C build-asan --print-errorlogs --timeout-multiplier 3 "$@"
