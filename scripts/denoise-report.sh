#!/usr/bin/env bash
# Regenerates the figures of docs/denoising.md: for each compatibility scene, prism renders it
# at 4, 16, 64 and 256 spp with --denoise (raw and denoised images), and raw at 1024 and 4096
# spp, all with 2 threads and the scene's seed; each image's error against pbrt-v4's reference
# is the compatibility report's (RMSE of x/(1+x)-mapped RGB, `prism compare --json`'s
# compat_error). Writes the errors to $OUT/errors.csv, prints the markdown table of
# docs/denoising.md (with the spp at which the raw error falls to the denoised one, interpolated
# linearly in log error over log spp between the raw renders that bracket it), and writes
# side-by-side pictures (raw | denoised at 16 spp | pbrt-v4's reference) to docs/images/denoise/
# with oiiotool (Debian's openimageio-tools). Renders already present in $OUT are reused.
#
#   bash scripts/denoise-report.sh [SCENE...]     (default: shapes lights-area materials)
set -euo pipefail
cd "$(dirname "$0")/.."
PRISM=${PRISM:-target/release/prism}
COMPAT=${COMPAT:-../shared/scenes/compat}
OUT=${OUT:-target/denoise-report}
LADDER=(4 16 64 256)
read -r -a RAW_ONLY <<< "${RAW_ONLY:-1024 4096}"   # e.g. RAW_ONLY=1024 for a slow scene
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(shapes lights-area materials)
mkdir -p "$OUT" docs/images/denoise

render() { # scene spp [--denoise]
  local out="$OUT/$1-$2.exr"
  [ -f "$out" ] && { [ -z "${3:-}" ] || [ -f "$OUT/$1-$2.denoised.exr" ]; } && return 0
  "$PRISM" render "$COMPAT/$1.pbrt" --spp "$2" --threads 2 ${3:-} -o "$out" 2>>"$OUT/log.txt"
}
error() { # image reference
  "$PRISM" compare --json "$1" "$2" | python3 -c 'import json,sys; print("%.5f" % json.load(sys.stdin)["compat_error"])'
}

echo "scene,spp,raw,denoised" > "$OUT/errors.csv"
for s in "${scenes[@]}"; do
  ref="$COMPAT/ref/$s.pbrt-v4.exr"
  for n in "${LADDER[@]}"; do
    render "$s" "$n" --denoise
    echo "$s,$n,$(error "$OUT/$s-$n.exr" "$ref"),$(error "$OUT/$s-$n.denoised.exr" "$ref")" >> "$OUT/errors.csv"
  done
  for n in "${RAW_ONLY[@]}"; do
    render "$s" "$n"
    echo "$s,$n,$(error "$OUT/$s-$n.exr" "$ref")," >> "$OUT/errors.csv"
  done
  # The panel, sRGB-encoded.
  oiiotool "$OUT/$s-16.exr" "$OUT/$s-16.denoised.exr" "$ref" --mosaic:pad=4 3x1 \
    --colorconvert linear sRGB -o "docs/images/denoise/$s.png"
done

python3 - "$OUT/errors.csv" <<'PY'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("| scene | spp | raw error | denoised error | denoised ÷ raw | raw reaches the denoised error at |")
print("|---|---|---|---|---|---|")
for scene in dict.fromkeys(r["scene"] for r in rows):
    raw = sorted((int(r["spp"]), float(r["raw"])) for r in rows if r["scene"] == scene)
    for r in (r for r in rows if r["scene"] == scene and r["denoised"]):
        n, e_raw, e_den = int(r["spp"]), float(r["raw"]), float(r["denoised"])
        reach = f"> {raw[-1][0]} spp"
        for (n0, e0), (n1, e1) in zip(raw, raw[1:]):
            if e0 > e_den >= e1:
                t = (math.log(e_den) - math.log(e0)) / (math.log(e1) - math.log(e0))
                reach = f"{math.exp(math.log(n0) + t * (math.log(n1) - math.log(n0))):.0f} spp"
                break
        print(f"| {scene} | {n} | {e_raw:.5f} | {e_den:.5f} | {e_den / e_raw:.2f} | {reach} |")
    print(f"| {scene} | " + ", ".join(str(n) for n, _ in raw if n > 256) + " (raw only) | "
          + " / ".join(f"{e:.5f}" for n, e in raw if n > 256) + " | | | |")
PY
