#!/usr/bin/env bash
# Installs the Debian 12 packages prism needs, only those that are missing. Whether a package is
# present is asked of dpkg by its name, never inferred from a file another package may provide.
# Runs apt-get as root, or through sudo; does nothing when everything is present.
#
#   scripts/install-deps.sh            the default build: Embree 3, OpenImageIO, bindgen's libclang
#   scripts/install-deps.sh --embree4  also Embree 4 (see scripts/install-embree4.sh)
set -euo pipefail
cd "$(dirname "$0")/.."

# libclang-dev: bindgen (Embree bindings); g++: the OpenImageIO shim; pkg-config: finds OpenImageIO.
packages=(libembree-dev libopenimageio-dev libclang-dev pkg-config g++)

need=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [ "$status" = "install ok installed" ] || need+=("$p")
done

if [ ${#need[@]} -eq 0 ]; then
  echo "install-deps: all system packages present (${packages[*]})"
else
  echo "install-deps: installing ${need[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${need[@]}"
fi
command -v cargo >/dev/null || { echo "install-deps: cargo not found; install Rust (rustup) first" >&2; exit 1; }

if [ "${1:-}" = "--embree4" ]; then
  bash scripts/install-embree4.sh
fi
