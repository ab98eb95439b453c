#!/bin/sh
# The CPU-only tests (suites core, scene and reference, and the fuzz corpus
# replays of suite robust) under valgrind memcheck, in build-valgrind: any
# invalid access, use of uninitialised memory or definite leak fails a test.
#   tools/valgrind.sh                   those tests
#   tools/valgrind.sh --suite scene     extra arguments go to `meson test`
# The GPU tests are left out: under memcheck one runs about 80 times slower
# (gpu/display: 43 s instead of 0.5 s on lavapipe), and the dynamic loader
# reports invalid reads in its rpath handling while it loads the Vulkan
# drivers (glibc's dl-load.c, not xrad). tools/sanitize.sh covers them.
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
if [ $# -eq 0 ]; then
    set -- --suite core --suite scene --suite reference --suite robust
fi
exec meson test -C build-valgrind --print-errorlogs --wrapper "$wrapper" \
    --timeout-multiplier 20 "$@"
