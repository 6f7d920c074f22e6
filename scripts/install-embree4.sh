#!/usr/bin/env bash
# Provides Embree 4 for `cargo build --no-default-features --features embree4,oiio`.
#
# A system Embree >= 4.3 known to pkg-config (`embree4`, e.g. Debian 13's libembree-dev) is used
# as it is. Otherwise (Debian 12 ships only Embree 3) Intel's Embree 4.4.0 release build is taken
# from the PyPI wheel embreex4==4.4.0.post1: downloaded with `pip download --no-deps`, checked
# against a pinned sha256, and its two libraries (libembree4 and the oneTBB 2021.12 it was built
# with) unpacked into target/embree4/lib, with a libembree4.so symlink for the linker and the
# Apache-2.0 licence and NOTICE texts of Embree and oneTBB (licenses/embree4/) beside them.
# build.rs links that directory with an rpath. Idempotent: does nothing when it is in place.
set -euo pipefail
cd "$(dirname "$0")/.."

WHEEL=embreex4-4.4.0.post1-cp311-cp311-manylinux_2_27_x86_64.manylinux_2_28_x86_64.whl
SHA256=ddc6887b38cc742a9ada3b04ce6157ce321c67325bfd9b758854ee0eabd74435
EMBREE_SO=libembree4-4aef3270.so.4
TBB_SO=libtbb-dcf63f8c.so.12
DEST=target/embree4
STAMP="$DEST/installed-from"

if command -v pkg-config >/dev/null && pkg-config --atleast-version=4.3 embree4 2>/dev/null; then
  echo "install-embree4: using the system Embree $(pkg-config --modversion embree4) (pkg-config embree4)"
  exit 0
fi

if [ -f "$STAMP" ] && [ "$(cat "$STAMP")" = "$WHEEL $SHA256" ] && [ -e "$DEST/lib/libembree4.so" ]; then
  echo "install-embree4: Embree 4.4.0 already in $DEST/lib"
  exit 0
fi

die() { echo "install-embree4: $*" >&2; exit 1; }
[ "$(uname -m)" = x86_64 ] || die "the embreex4 wheel holds x86-64 libraries only; install a system Embree 4 instead"
if ! python3 -m pip --version >/dev/null 2>&1; then
  # Debian's pip (python3-pip) downloads wheels; only installing into the system is refused.
  command -v apt-get >/dev/null || die "python3 with pip is needed to download the wheel"
  echo "install-embree4: installing python3-pip"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq python3-pip
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "install-embree4: downloading $WHEEL from PyPI"
# The platform and interpreter are pinned, so the same wheel is chosen whatever python3 is.
python3 -m pip download --quiet --no-deps --only-binary=:all: --platform manylinux_2_28_x86_64 \
  --python-version 3.11 --implementation cp --abi cp311 "embreex4==4.4.0.post1" -d "$tmp"
[ -f "$tmp/$WHEEL" ] || die "pip did not download $WHEEL (got: $(ls "$tmp"))"
got=$(sha256sum "$tmp/$WHEEL" | cut -d' ' -f1)
[ "$got" = "$SHA256" ] || die "sha256 of $WHEEL is $got, expected $SHA256; refusing to install it"

python3 -m zipfile -e "$tmp/$WHEEL" "$tmp/wheel"
rm -rf "$DEST"
mkdir -p "$DEST/lib"
cp "$tmp/wheel/embreex4.libs/$EMBREE_SO" "$tmp/wheel/embreex4.libs/$TBB_SO" "$DEST/lib/"
chmod 0755 "$DEST/lib/$EMBREE_SO" "$DEST/lib/$TBB_SO"
ln -s "$EMBREE_SO" "$DEST/lib/libembree4.so"
cp licenses/embree4/* "$DEST/lib/"
echo "$WHEEL $SHA256" > "$STAMP"
echo "install-embree4: Embree 4.4.0 and oneTBB 2021.12 in $DEST/lib (with their licence and NOTICE texts)"
