#!/usr/bin/env bash
# Regenerates the figures in docs/benchmarks.md on this machine (run from the repository root):
#   1. criterion: BVH build and rays/s, Embree vs raw rtcIntersect1 vs obvhs, ~1M triangles;
#      then speed ratios embree / embree-watertight / obvhs in interleaved passes (accel_ratio);
#      then obvhs_huge_pages: obvhs ÷ Embree measured side by side (huge pages vs heap);
#   2. prism bench: the Cornell box's error against time per backend and sampler, with plots,
#      and each curve's time to RMSE 0.04 and 0.01;
#   3. prism bench on the built-in 1M-triangle terrain and on scenes/instanced_orchard.pbrt:
#      build time, rays/s and memory per triangle per backend.
# The peer comparison with Mitsuba 3 is a separate command: bash benches/peers/mitsuba.sh
# Embree 4 against Embree 3 (two builds, interleaved): bash scripts/bench-embree4.sh
# Outputs go to bench-out/; copy the tables and plots you want into docs/.
set -euo pipefail
mkdir -p bench-out
cargo build --release
echo "== machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(date -u +%F)"
cargo bench --bench accel -- --noplot 2>&1 | grep -E "^[a-z-]+/|time:|thrpt:" | tee bench-out/accel.txt
PRISM_BENCH_PASSES=16 cargo bench --bench accel_ratio 2>&1 | tee bench-out/accel_ratio.txt
PRISM_RATIO_PASSES=16 cargo bench --bench obvhs_huge_pages 2>&1 | grep -vE "^ *(Compiling|Finished|Running)" | tee bench-out/obvhs_huge_pages.txt
./target/release/prism bench --accel embree,obvhs --sampler independent,sobol \
    --spp-ladder "${SPP_LADDER:-1,4,16,64}" --reference-spp "${REF_SPP:-1024}" \
    --resolution "${RES:-128x128}" --max-depth 8 --target-rmse "${TARGETS:-0.04,0.01}" --out bench-out/cornell
./target/release/prism bench builtin:terrain --accel embree,obvhs --sampler independent \
    --spp-ladder 1,4 --reference-spp 64 --resolution 256x192 --max-depth 5 --out bench-out/terrain
./target/release/prism bench scenes/instanced_orchard.pbrt --accel embree,obvhs --sampler independent \
    --spp-ladder 1,4 --reference-spp 64 --resolution 240x135 --max-depth 5 --out bench-out/orchard
