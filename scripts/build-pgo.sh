#!/usr/bin/env bash
# A profile-guided release build of prism into target/pgo/release/prism (make pgo).
#
# Builds prism instrumented, renders the compatibility scenes (tests/data/compat) small to record
# which branches and calls are hot, then builds it again with that profile (rustc's
# -Cprofile-generate / -Cprofile-use). The images are the plain release build's, bit for bit;
# only the code's layout and inlining change (docs/benchmarks.md: 0.85-0.93x the render time on
# scenes outside the training set). Needs llvm-profdata of the LLVM that rustc is built on: the
# Debian package llvm-N for rustc's "LLVM version: N" (bookworm-security carries recent ones),
# installed when missing. Two release builds: about twice `cargo build --release`.
set -euo pipefail
cd "$(dirname "$0")/.."

major=$(rustc -vV | sed -n 's/^LLVM version: \([0-9]*\).*/\1/p')
profdata="/usr/lib/llvm-$major/bin/llvm-profdata"
if [ ! -x "$profdata" ]; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "build-pgo: installing llvm-$major (llvm-profdata for rustc's LLVM $major)"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "llvm-$major" || {
    echo "build-pgo: no Debian package llvm-$major; install llvm-profdata of LLVM $major as $profdata" >&2
    exit 1
  }
fi

target=target/pgo
raw="$target/profiles"
rm -rf "$raw" && mkdir -p "$raw"
RUSTFLAGS="-Cprofile-generate=$PWD/$raw" cargo build --release --target-dir "$target/generate"
for scene in tests/data/compat/*.pbrt; do
  "$target/generate/release/prism" render "$scene" --spp 8 --resolution 64x64 -o "$target/training.exr" \
    >"$target/training.log" 2>&1 || { cat "$target/training.log" >&2; exit 1; }
done
"$profdata" merge -o "$target/prism.profdata" "$raw"
RUSTFLAGS="-Cprofile-use=$PWD/$target/prism.profdata" cargo build --release --target-dir "$target"
echo "build-pgo: $target/release/prism"
