#!/bin/sh
# Runs one libFuzzer harness for a fixed time on a fresh copy of its seeds.
# Usage: run.sh FUZZER NAME SECONDS OUTDIR
#
# Seeds: tests/fuzz/corpus/NAME/, tests/fuzz/regressions/NAME/ and, for the
# scene parser, the shipped scenes/*.json (for the photometric readers,
# tests/data/photometry/*), copied into OUTDIR/corpus (which
# also collects what libFuzzer adds; it is rebuilt on every run, so runs are
# repeatable). Dictionary: tests/fuzz/NAME.dict when present; LeakSanitizer
# suppressions: tests/fuzz/NAME.lsan when present. A crashing,
# leaking or hanging input is written to OUTDIR/ and its path printed; save it
# in tests/fuzz/regressions/NAME/ so every build replays it. Prints
# libFuzzer's execution count; exits 0 when nothing was found, else 1 (never
# 77, which meson would read as "skipped").
#
# The mutations follow a fixed seed (FUZZ_SEED, default 1), so that a run
# tries the same inputs in the same order every time and a failure in CI
# is one anyone can repeat; FUZZ_SEED=0 lets libFuzzer pick one (explore).
# A CI run once stopped in assimp's OBJ reader after 2,077 inputs of a
# random seed, and the saved input alone ran clean (tests/fuzz/README.md).
set -u
if [ $# -ne 4 ]; then
    echo "usage: run.sh FUZZER NAME SECONDS OUTDIR" >&2
    exit 2
fi
fuzzer=$1 name=$2 seconds=$3 out=$4
root=$(cd "$(dirname "$0")/../.." && pwd)

rm -rf "$out/corpus"
mkdir -p "$out/corpus" || exit 1
seeds=0
copy_seeds() { # copy_seeds PREFIX FILE...
    prefix=$1
    shift
    for f in "$@"; do
        if [ -f "$f" ]; then
            cp "$f" "$out/corpus/$prefix$(basename "$f")" || exit 1
            seeds=$((seeds + 1))
        fi
    done
}
copy_seeds "" "$root/tests/fuzz/corpus/$name"/*
copy_seeds "regression-" "$root/tests/fuzz/regressions/$name"/*
case $name in
scene) copy_seeds "shipped-" "$root"/scenes/*.json ;;
photometry) copy_seeds "shipped-" "$root"/tests/data/photometry/* ;;
esac

dict=""
[ -f "$root/tests/fuzz/$name.dict" ] && dict="-dict=$root/tests/fuzz/$name.dict"
# OpenEXRCore prints every rejected file to stderr; close the harness's
# stderr (libFuzzer and the sanitizers keep reporting on a copy of it).
quiet=""
[ "$name" = exr ] && quiet="-close_fd_mask=2"

# Undefined behaviour stops the run like a crash does; leaks are reported.
UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS ASAN_OPTIONS
# Leaks in third-party code the harness cannot fix (NAME.lsan says which).
if [ -f "$root/tests/fuzz/$name.lsan" ] && [ -z "${LSAN_OPTIONS:-}" ]; then
    LSAN_OPTIONS="suppressions=$root/tests/fuzz/$name.lsan:print_suppressions=0"
    export LSAN_OPTIONS
fi

log="$out/fuzz-$name.log"
start=$(date +%s)
stamp="$out/.started-$name"
: >"$stamp"
echo "fuzz $name: $seeds seeds, $seconds s, seed ${FUZZ_SEED:-1}, log $log"
# shellcheck disable=SC2086 # $dict and $quiet are one word or none
"$fuzzer" -seed="${FUZZ_SEED:-1}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -error_exitcode=1 -timeout_exitcode=1 -print_final_stats=1 \
    -artifact_prefix="$out/" $dict $quiet "$out/corpus" >"$log" 2>&1
rc=$?
elapsed=$(($(date +%s) - start))

execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)
added=$(sed -n 's/^stat::new_units_added: *//p' "$log" | tail -n 1)
echo "fuzz $name: ${execs:-?} executions in $elapsed s (${rate:-?}/s), ${added:-?} new corpus inputs"
if [ "$rc" -ne 0 ]; then
    echo "fuzz $name: FAILED (libFuzzer exit $rc); end of the log:"
    tail -n 60 "$log"
    # Only this run's inputs: earlier ones stay until someone saves them.
    find "$out" -maxdepth 1 -type f -newer "$stamp" \( -name 'crash-*' -o -name 'leak-*' \
        -o -name 'timeout-*' -o -name 'oom-*' \) -exec echo "fuzz $name: input saved as" {} \;
    exit 1
fi
exit 0
