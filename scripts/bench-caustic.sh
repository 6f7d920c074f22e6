#!/bin/bash
# Time to a target error on a caustic scene (SCENE: scenes/caustic.pbrt, a glass sphere on a
# diffuse floor, or scenes/window.pbrt, a room lit through a glass pane): path tracing,
# bidirectional path tracing, Metropolis light transport (pbrt-v4's defaults; its count is
# mutations per pixel) and stochastic progressive photon mapping (sppm: the count is its
# iterations, SPPM_RADIUS its initial radius, one photon per pixel per iteration), runs
# interleaved (path, bdpt, mlt, sppm, path, ...) at each count of LADDER.
#
# Errors (RMSE, MAE on linear sRGB) are against a bdpt reference of REF_SPP samples per pixel,
# rendered as two independent halves (`--part 1/2`, `2/2`) and merged; the halves' own
# difference, printed first, says how converged it is (the merged reference's error is about
# half of it). Wall and CPU (user + system) seconds are the whole process's (`/usr/bin/time`).
# Writes $OUT/<scene>.csv, the images, $OUT/machine.txt (date, CPU, load) and prints a
# Markdown table with each integrator's CPU time to TARGET_MAE and TARGET_RMSE
# (scripts/caustic-table.py).
set -euo pipefail
PRISM=${PRISM:-target/release/prism}
SCENE=${SCENE:-scenes/caustic.pbrt}
NAME=$(basename "$SCENE" .pbrt)
OUT=${OUT:-bench-out/$NAME}
RES=${RES:-128x96}
REF_SPP=${REF_SPP:-4096}
LADDER=${LADDER:-"4 16 64 256"}
SPPM_RADIUS=${SPPM_RADIUS:-0.05}
TARGET_MAE=${TARGET_MAE:-0.03}
TARGET_RMSE=${TARGET_RMSE:-0.1}
mkdir -p "$OUT"
# The scene with sppm as its integrator (its radius is a scene parameter).
sed "s/^Integrator .*/Integrator \"sppm\" \"integer maxdepth\" [8] \"float radius\" [$SPPM_RADIUS]/" "$SCENE" > "$OUT/$NAME-sppm.pbrt"
{ date -u; lscpu | grep -E "Model name|Flags" | cut -c1-200; uptime; } > "$OUT/machine.txt"

# errors A B: "RMSE,MAE" of image A against B.
errors() {
  "$PRISM" compare "$1" "$2" | awk '$1 == "RMSE" && NF == 2 {r=$2} $1 == "MAE" {m=$2} END {print r "," m}'
}

if [ ! -f "$OUT/ref.exr" ]; then
  for part in 1 2; do
    "$PRISM" render "$SCENE" --resolution "$RES" --spp "$REF_SPP" --integrator bdpt --seed 99 \
      --part "$part/2" -o "$OUT/ref-$part.film"
    "$PRISM" merge "$OUT/ref-$part.film" -o "$OUT/ref-$part.exr" 2>/dev/null
  done
  "$PRISM" merge "$OUT/ref-1.film" "$OUT/ref-2.film" -o "$OUT/ref.exr"
fi
echo "reference halves ($((REF_SPP / 2)) spp each) against each other: RMSE,MAE $(errors "$OUT/ref-1.exr" "$OUT/ref-2.exr")" \
  | tee -a "$OUT/machine.txt"

# APPEND=1 adds rows to the CSV (e.g. a longer ladder for some integrators) instead of starting it.
[ -n "${APPEND:-}" ] || echo "integrator,count,wall,cpu,rmse,mae" > "$OUT/$NAME.csv"
for count in $LADDER; do
  for integ in ${INTEGRATORS:-path bdpt mlt sppm}; do
    case $integ in
      sppm) args=("$OUT/$NAME-sppm.pbrt") ;;
      *) args=("$SCENE" --integrator "$integ") ;;
    esac
    /usr/bin/time -f "%e %U %S" -o "$OUT/time.txt" "$PRISM" render "${args[@]}" --resolution "$RES" \
      --spp "$count" -o "$OUT/$integ-$count.exr" 2>/dev/null
    times=$(awk '{printf "%.2f,%.2f", $1, $2 + $3}' "$OUT/time.txt")
    echo "$integ,$count,$times,$(errors "$OUT/$integ-$count.exr" "$OUT/ref.exr")" | tee -a "$OUT/$NAME.csv"
  done
done
uptime >> "$OUT/machine.txt"

python3 scripts/caustic-table.py "$OUT/$NAME.csv" "$TARGET_MAE" "$TARGET_RMSE"
