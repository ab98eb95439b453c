#!/bin/sh
# The public headers compile as C99 and as C++11 with -pedantic -Werror
# (issue 17): a user's C or C++ code includes them as they are. Each header
# alone, then all of them, in a translation unit that also calls into them
# so that C++ sees the extern "C" block.
# Usage: test_headers.sh SOURCE_ROOT BUILD_ROOT CC CXX
set -u
src=$1
build=$2
cc=$3
cxx=$4
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
flags="-Wall -Wextra -pedantic -Werror -I$src/include -I$build/include -fsyntax-only"
for h in "$src"/include/*.h; do
    name=$(basename "$h")
    printf '#include "%s"\nint main(void) { return xrad_version() == 0; }\n' "$name" >"$tmp/probe.c"
    cp "$tmp/probe.c" "$tmp/probe.cpp"
    for lang in c99 c++11; do
        if [ $lang = c99 ]; then
            out=$($cc -std=c99 $flags "$tmp/probe.c" 2>&1)
        else
            out=$($cxx -std=c++11 $flags "$tmp/probe.cpp" 2>&1)
        fi
        if [ $? -eq 0 ]; then
            pass=$((pass + 1))
        else
            echo "FAIL: $name as $lang:"
            echo "$out" | head -10
            fail=$((fail + 1))
        fi
    done
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ] && [ "$pass" -gt 0 ]
