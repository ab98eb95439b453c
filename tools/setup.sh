#!/bin/sh
# Installs what xrad needs from Debian 12 (only what is missing), then
# configures and builds it in ./build. Safe to run again.
set -eu
cd "$(dirname "$0")/.."

packages="meson ninja-build pkg-config gcc g++ python3 glslang-tools libvulkan-dev \
mesa-vulkan-drivers vulkan-validationlayers libglfw3-dev libopenexr-dev libcjson-dev \
libpng-dev libstb-dev libassimp-dev assimp-testmodels libembree-dev xvfb xauth"

missing=""
for p in $packages; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
        missing="$missing $p"
done
if [ -n "$missing" ]; then
    echo "setup: installing$missing"
    sudo=""
    [ "$(id -u)" = 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $missing
fi

if [ -f build/build.ninja ]; then
    meson setup --reconfigure build >/dev/null
else
    meson setup build
fi
meson compile -C build
