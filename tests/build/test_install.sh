#!/bin/sh
# The installed library (issue 17.5): `meson install` of this build into a
# temporary prefix, then tests/build/installed_app.c compiled against it
# with nothing but `pkg-config --cflags --libs xrad` (the README's
# command), linked to the shared library and, with `pkg-config --static`,
# to the static one, and run: each binary prints "N passed, N failed".
# Also checks what was installed: the headers, both libraries, xrad.pc and
# the xrad tool, and that the shared library exports only xrad_ symbols.
# Usage: test_install.sh BUILD_ROOT APP.c CC [CC ARGS...]
set -u
build=$1
app=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fail=$((fail + 1)); }

if ! meson install -C "$build" --no-rebuild --destdir "$tmp/root" >"$tmp/install.log" 2>&1; then
    cat "$tmp/install.log"
    echo "0 passed, 1 failed"
    exit 1
fi
pc=$(find "$tmp/root" -name xrad.pc | head -1)
[ -n "$pc" ] && ok || bad "no xrad.pc installed"
prefix=$(sed -n 's/^prefix=//p' "$pc")
pcdir=$(dirname "$pc")
# The .pc names the real prefix; point it at the temporary one.
pkg() { PKG_CONFIG_PATH="$pcdir" pkg-config --define-variable=prefix="$tmp/root$prefix" "$@" xrad; }
for f in include/xrad/xrad.h include/xrad/xrad_version.h bin/xrad; do
    [ -e "$tmp/root$prefix/$f" ] && ok || bad "$prefix/$f not installed"
done
libdir=$(pkg --variable=libdir)
for f in libxrad.a libxrad.so; do
    [ -e "$libdir/$f" ] && ok || bad "$f not installed in $libdir"
done
other=$(nm -D --defined-only "$libdir/libxrad.so" | awk '{print $3}' | grep -v '^xrad_' | head -5)
[ -z "$other" ] && ok || bad "libxrad.so exports more than xrad_*: $other"

# Shared: what the README shows.
if "$@" -std=c11 -Wall -Werror -o "$tmp/app" "$app" $(pkg --cflags --libs) -lm 2>"$tmp/cc.log"; then
    ok
    if LD_LIBRARY_PATH="$libdir" ldd "$tmp/app" | grep -q "$libdir/libxrad.so"; then ok; else bad "app is not linked to the installed libxrad.so"; fi
    if LD_LIBRARY_PATH="$libdir" "$tmp/app"; then ok; else bad "the app against libxrad.so failed"; fi
else
    cat "$tmp/cc.log"
    bad "compiling against the installed library failed"
fi
# Static: the archive itself, and the private libraries pkg-config lists.
if "$@" -std=c11 -Wall -Werror -o "$tmp/app-static" "$app" $(pkg --cflags) "$libdir/libxrad.a" \
    $(pkg --static --libs | sed 's/-lxrad\b//') -lm -lstdc++ 2>"$tmp/cc.log"; then
    ok
    if ldd "$tmp/app-static" | grep -q libxrad; then bad "app-static loads libxrad.so"; else ok; fi
    if "$tmp/app-static"; then ok; else bad "the app against libxrad.a failed"; fi
else
    cat "$tmp/cc.log"
    bad "linking the static library with pkg-config --static failed"
fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ] && [ "$pass" -gt 0 ]
