#!/bin/bash
# Time to a target error on scenes/caustic.pbrt: path tracing, bidirectional path tracing,
# Metropolis light transport (pbrt-v4's defaults; its count is mutations per pixel) and
# stochastic progressive photon mapping (sppm: the count is its iterations, SPPM_RADIUS its
# initial radius, one photon per pixel per iteration), runs interleaved (path, bdpt, mlt, sppm,
# path, ...) at each sample count, errors against a bdpt reference of REF_SPP samples per
# pixel. Prints a table (CSV in $OUT/caustic.csv) and writes the images; the machine and date
# go in $OUT/machine.txt.
set -euo pipefail
PRISM=${PRISM:-target/release/prism}
OUT=${OUT:-bench-out/caustic}
RES=${RES:-128x96}
REF_SPP=${REF_SPP:-4096}
LADDER=${LADDER:-"4 16 64 256"}
SPPM_RADIUS=${SPPM_RADIUS:-0.05}
SCENE=scenes/caustic.pbrt
mkdir -p "$OUT"
# The scene with sppm as its integrator (its radius is a scene parameter).
sed "s/^Integrator .*/Integrator \"sppm\" \"integer maxdepth\" [8] \"float radius\" [$SPPM_RADIUS]/" "$SCENE" > "$OUT/caustic-sppm.pbrt"
{ date -u; lscpu | grep -E "Model name|Flags" | cut -c1-200; uptime; } > "$OUT/machine.txt"
if [ ! -f "$OUT/ref.exr" ]; then
  "$PRISM" render "$SCENE" --resolution "$RES" --spp "$REF_SPP" --integrator bdpt --seed 99 -o "$OUT/ref.exr"
fi
echo "integrator,spp,seconds,rmse,mae" > "$OUT/caustic.csv"
for spp in $LADDER; do
  for integ in ${INTEGRATORS:-path bdpt mlt sppm}; do
    case $integ in
      sppm) args=("$OUT/caustic-sppm.pbrt") ;;
      *) args=("$SCENE" --integrator "$integ") ;;
    esac
    line=$("$PRISM" render "${args[@]}" --resolution "$RES" --spp "$spp" \
      -o "$OUT/$integ-$spp.exr" 2>&1 | grep -o 'in [0-9.]* s' | head -1 | cut -d' ' -f2)
    err=$("$PRISM" compare "$OUT/$integ-$spp.exr" "$OUT/ref.exr" | awk '$1 == "RMSE" && NF == 2 {r=$2} $1 == "MAE" {m=$2} END {print r "," m}')
    echo "$integ,$spp,$line,$err" | tee -a "$OUT/caustic.csv"
  done
done
