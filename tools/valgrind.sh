#!/bin/sh
# The CPU-only tests (suites core, scene and reference, and the fuzz corpus
# replay) under valgrind memcheck, in build-valgrind: any invalid access,
# use of uninitialised memory or definite leak fails the test.
#   tools/valgrind.sh                   those tests
#   tools/valgrind.sh --suite scene     extra arguments go to `meson test`
# The GPU tests are left out (Mesa's drivers are not built for valgrind, and
# lavapipe's JIT makes a run take far too long); tools/sanitize.sh covers them.
set -eu
cd "$(dirname "$0")/.."

if ! command -v valgrind >/dev/null 2>&1; then
    echo "valgrind.sh: needs valgrind (Debian 12: apt-get install valgrind)" >&2
    exit 2
fi
if [ -f build-valgrind/build.ninja ]; then
    meson setup --reconfigure build-valgrind
else
    meson setup build-valgrind
fi
meson compile -C build-valgrind >build-valgrind/compile.log 2>&1 ||
    { tail -n 40 build-valgrind/compile.log; exit 1; }

wrapper="valgrind --quiet --error-exitcode=1 --leak-check=full \
--show-leak-kinds=definite,indirect --errors-for-leak-kinds=definite,indirect \
--track-origins=yes"
if [ $# -gt 0 ]; then
    exec meson test -C build-valgrind --print-errorlogs --wrapper "$wrapper" \
        --timeout-multiplier 20 "$@"
fi
rc=0
meson test -C build-valgrind --print-errorlogs --wrapper "$wrapper" \
    --timeout-multiplier 20 --suite core --suite scene --suite reference || rc=1
meson test -C build-valgrind --print-errorlogs --wrapper "$wrapper" \
    --timeout-multiplier 20 fuzz-replay-scene || rc=1
exit "$rc"
