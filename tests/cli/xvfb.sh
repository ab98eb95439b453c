# Sourced by the window tests (test_view.sh, test_embed.sh): xvfb_start DIR
# starts a virtual X server on a free display, installing it first where it
# is missing and we may, sets xvfb_pid (for the caller's cleanup) and
# exports DISPLAY; it exits 77 (meson: skipped) where none can start.
xvfb_start() {
    if ! command -v Xvfb >/dev/null 2>&1 && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq xvfb xauth >/dev/null 2>&1
    fi
    if ! command -v Xvfb >/dev/null 2>&1; then
        echo "SKIP: Xvfb is not installed and cannot be installed here (Debian: xvfb)"
        exit 77
    fi
    Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>"$1/display" 2>"$1/xvfb.log" &
    xvfb_pid=$!
    xvfb_wait=0
    while [ ! -s "$1/display" ] && [ $xvfb_wait -lt 100 ]; do
        sleep 0.1
        xvfb_wait=$((xvfb_wait + 1))
    done
    if [ ! -s "$1/display" ]; then
        echo "SKIP: Xvfb did not start:"
        sed 's/^/    /' "$1/xvfb.log" | head -5
        exit 77
    fi
    DISPLAY=":$(cat "$1/display")"
    export DISPLAY
}
