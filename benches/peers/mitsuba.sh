#!/usr/bin/env bash
# Peer benchmark: prism vs Mitsuba 3 (llvm_ad_spectral, scalar_spectral), time to equal noise on
# the Cornell box, a textured many-material scene and the 1M-triangle terrain.
# One command, from the repository root:  bash benches/peers/mitsuba.sh [driver options]
# (see `--help` of benches/peers/mitsuba_peer.py). It builds prism (release) and the terrain
# exporter, makes a Python virtual environment in target/peers/venv with mitsuba from PyPI, and
# writes target/peers/out/{run.json,peer.md} plus the images. A benchmark, not a test: CI does
# not run it.
#
# llvm_ad_spectral needs LLVM ≥ 16 at run time (Debian 12's LLVM 15 aborts): Debian 12 ships
# libllvm19 (bookworm/main, 1:19.1.7-3~deb12u1); this script installs it with apt-get when run as
# root and points Dr.Jit at it with DRJIT_LIBLLVM_PATH.
set -euo pipefail
cd "$(dirname "$0")/../.."
PEERS=target/peers
mkdir -p "$PEERS"

if [ ! -x "$PEERS/venv/bin/python" ]; then
    python3 -m venv "$PEERS/venv"
fi
"$PEERS/venv/bin/python" -c "import mitsuba, numpy" 2>/dev/null ||
    "$PEERS/venv/bin/pip" install --quiet "mitsuba>=3.6" numpy

LLVM_SO=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1
if [ ! -e "$LLVM_SO" ] && [ "$(id -u)" = 0 ]; then
    apt-get install -y -q libllvm19 >/dev/null || true
fi
if [ -e "$LLVM_SO" ]; then
    export DRJIT_LIBLLVM_PATH="$LLVM_SO"
else
    echo "mitsuba.sh: $LLVM_SO missing (apt-get install libllvm19); skipping llvm_ad_spectral" >&2
    set -- --variants scalar_spectral --converged-variant scalar_spectral "$@"
fi

cargo build --release --quiet
cargo build --release --quiet --example terrain_ply
echo "== machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(date -u +%F)" >&2
echo "== before: $(uptime)" >&2
"$PEERS/venv/bin/python" benches/peers/mitsuba_peer.py "$@"
echo "== after: $(uptime)" >&2
