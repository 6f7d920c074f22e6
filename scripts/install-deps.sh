#!/usr/bin/env bash
# Installs the Debian 12 packages prism needs, only if something is missing. Runs apt-get as
# root, or through sudo; does nothing when everything is present.
set -euo pipefail

need=()
[ -f /usr/include/embree3/rtcore.h ] || need+=(libembree-dev)
pkg-config --exists OpenImageIO 2>/dev/null || need+=(libopenimageio-dev)
command -v pkg-config >/dev/null || need+=(pkg-config)
ls /usr/lib/llvm-*/lib/libclang.so* >/dev/null 2>&1 || ls /usr/lib/x86_64-linux-gnu/libclang*.so* >/dev/null 2>&1 || need+=(libclang-dev)
command -v c++ >/dev/null || need+=(g++)

if [ ${#need[@]} -eq 0 ]; then
  echo "install-deps: all system packages present"
else
  echo "install-deps: installing ${need[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${need[@]}"
fi
command -v cargo >/dev/null || { echo "install-deps: cargo not found; install Rust (rustup) first" >&2; exit 1; }
