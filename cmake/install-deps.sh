#!/bin/sh
# Installs the Debian packages Pliant needs, if they are missing
# (with the argument `fuzz`: also what the fuzz targets need).
# Uses sudo when not root.  Safe to run again: it installs nothing when all
# packages are present.
set -eu
# The viewer (pliant view, pliant render, make pictures): OpenGL, EGL with
# Mesa's software renderer for machines without a GPU, GLFW, libpng, ffmpeg;
# xvfb and xauth run the window tests without a screen.  The Python package
# (make test-python, docs/python.md): Python's headers and venv; NumPy, pytest,
# gymnasium and scikit-build-core come from PyPI into the venv.
PKGS="build-essential cmake pkg-config libsuitesparse-dev libmetis-dev libxml2-dev check \
zlib1g-dev libsiconos-numerics-dev libopenmpi-dev openmpi-bin \
libgl-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev libpng-dev ffmpeg xvfb xauth \
python3-dev python3-venv python3-pip"
# `install-deps.sh fuzz` (make fuzz): clang with libFuzzer, LLVM's coverage
# tools and clang's OpenMP runtime, only for the fuzz targets.
if [ "${1:-}" = fuzz ]; then
  PKGS="$PKGS clang llvm libclang-rt-dev libomp-dev"
fi
missing=""
for p in $PKGS; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing="$missing $p"
  fi
done
[ -z "$missing" ] && exit 0
echo "install-deps: installing$missing"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO=sudo; else
    echo "install-deps: need root or sudo to install:$missing" >&2; exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# shellcheck disable=SC2086
$SUDO apt-get install -y -qq --no-install-recommends $missing
