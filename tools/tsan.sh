#!/bin/sh
# The threads of the real-time loop under ThreadSanitizer (issue 17.10), in
# build-tsan: the scheduler test (a worker thread redistributes while the
# caller displays) and xrad view under Xvfb (its display and
# redistribution threads), as meson tests; any report fails its test
# (halt_on_error). Extra arguments go to `meson test`.
#
# Neither the Khronos validation layer nor the Vulkan driver is
# instrumented: their own threads and locks (the layer's rwlocks and
# worker threads, lavapipe's and LLVM's) are suppressed by library in
# tools/tsan.supp. Nothing of xrad's is suppressed.
set -eu
cd "$(dirname "$0")/.."

if [ ! -f build-tsan/build.ninja ]; then
    meson setup build-tsan -Db_sanitize=thread -Db_lundef=false >/dev/null
fi
meson compile -C build-tsan tests/schedule/test_scheduler tools/xrad \
    >build-tsan/compile.log 2>&1 || { tail -n 40 build-tsan/compile.log; exit 1; }
TSAN_OPTIONS="halt_on_error=1 suppressions=$PWD/tools/tsan.supp"
# 12 frames of cornell-lowq in the view test rather than 60 of
# cornell-large: the threads meet from the first frames on, in any scene,
# and CI's time is short. XRAD_VIEW_THREADS=1: the windows alone, without
# the renders the plain run compares them with (tests/cli/test_view.sh).
XRAD_VIEW_FRAMES=12
XRAD_VIEW_SCENE=cornell-lowq
XRAD_VIEW_THREADS=1
export TSAN_OPTIONS XRAD_VIEW_FRAMES XRAD_VIEW_SCENE XRAD_VIEW_THREADS
exec meson test -C build-tsan --no-rebuild --print-errorlogs scheduler view "$@"
