#!/usr/bin/env bash
# Provides Intel Open Image Denoise 2 for `prism render --denoise` (loaded at run time, so prism
# builds and runs without it).
#
# Debian 12 has no OIDN package. Intel's OIDN 2.5.1 release build is taken from the PyPI wheel
# pyoidn==2.5.1.0: downloaded with `pip download --no-deps`, checked against a pinned sha256,
# and the four libraries the CPU device needs (libOpenImageDenoise, its core, its CPU device
# module, and the oneTBB it was built with) unpacked into target/oidn/lib, with the
# libOpenImageDenoise.so.2 and libtbb.so.12 names the libraries ask for and the Apache-2.0
# licence and notice texts of OIDN and oneTBB (licenses/oidn/) beside them. The wheel's GPU
# device modules (CUDA, HIP, SYCL) are left out. prism finds the directory by itself
# (PRISM_OIDN_LIB names another library). Idempotent: does nothing when it is in place.
set -euo pipefail
cd "$(dirname "$0")/.."

WHEEL=pyoidn-2.5.1.0-py3-none-manylinux2014_x86_64.whl
SHA256=32ad13368f8de1ef63001942ad05b02a00cd732d1206d97f352d3a3f606d823e
LIBS=(libOpenImageDenoise.so.2.5.1 libOpenImageDenoise_core.so.2.5.1 libOpenImageDenoise_device_cpu.so.2.5.1 libtbb.so.12.19)
DEST=target/oidn
STAMP="$DEST/installed-from"

if [ -f "$STAMP" ] && [ "$(cat "$STAMP")" = "$WHEEL $SHA256" ] && [ -e "$DEST/lib/libOpenImageDenoise.so.2" ]; then
  echo "install-oidn: Open Image Denoise 2.5.1 already in $DEST/lib"
  exit 0
fi

die() { echo "install-oidn: $*" >&2; exit 1; }
[ "$(uname -m)" = x86_64 ] || die "the pyoidn wheel holds x86-64 libraries only; install OIDN 2 otherwise and set PRISM_OIDN_LIB"
if ! python3 -m pip --version >/dev/null 2>&1; then
  # Debian's pip (python3-pip) downloads wheels; only installing into the system is refused.
  command -v apt-get >/dev/null || die "python3 with pip is needed to download the wheel"
  echo "install-oidn: installing python3-pip"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq python3-pip
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "install-oidn: downloading $WHEEL from PyPI (88 MB)"
# The platform is pinned, so the same wheel is chosen whatever python3 is.
python3 -m pip download --quiet --no-deps --only-binary=:all: --platform manylinux2014_x86_64 \
  "pyoidn==2.5.1.0" -d "$tmp"
[ -f "$tmp/$WHEEL" ] || die "pip did not download $WHEEL (got: $(ls "$tmp"))"
got=$(sha256sum "$tmp/$WHEEL" | cut -d' ' -f1)
[ "$got" = "$SHA256" ] || die "sha256 of $WHEEL is $got, expected $SHA256; refusing to install it"

python3 -m zipfile -e "$tmp/$WHEEL" "$tmp/wheel"
rm -rf "$DEST"
mkdir -p "$DEST/lib"
for lib in "${LIBS[@]}"; do
  cp "$tmp/wheel/pyoidn/oidn/lib/$lib" "$DEST/lib/"
  chmod 0755 "$DEST/lib/$lib"
done
# The names the libraries are loaded by (their sonames and NEEDED entries); their RPATH
# $ORIGIN/../lib finds each other in this directory.
ln -s libOpenImageDenoise.so.2.5.1 "$DEST/lib/libOpenImageDenoise.so.2"
ln -s libtbb.so.12.19 "$DEST/lib/libtbb.so.12"
cp licenses/oidn/* "$DEST/lib/"
echo "$WHEEL $SHA256" > "$STAMP"
echo "install-oidn: Open Image Denoise 2.5.1 (CPU device) and oneTBB in $DEST/lib (with their licence and notice texts)"
