#!/usr/bin/env bash
# Embree 4 ÷ Embree 3 ÷ obvhs, side by side in one run (run from the repository root):
#   1. builds prism and benches/accel_ratio twice, with Embree 3 (the default features) and with
#      Embree 4 (`--no-default-features --features embree4,oiio`);
#   2. runs the two accel_ratio binaries in turn, ABBA (1M triangles; coherent and incoherent
#      rays; 1 and 2 threads; embree, embree-watertight and obvhs in each), PASSES passes each;
#   3. runs the two prism binaries in turn, ABBA, `prism bench` on the Cornell box and the
#      1M-triangle terrain (embree and obvhs);
#   4. prints the ratios per adjacent pair of runs (median and range). obvhs is the same code in
#      both binaries: its ratio between the two is the measurement's own noise.
# ROUNDS (default 3) ABBA rounds, PASSES (default 2) passes per accel_ratio run, SPP (default
# 16) samples per pixel and THREADS (default: all cores) of each render; outputs in
# bench-out/embree4/.
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${ROUNDS:-3}
PASSES=${PASSES:-2}
SPP=${SPP:-16}
THREADS=${THREADS:-$(nproc)}
OUT=bench-out/embree4
mkdir -p "$OUT"
bash scripts/install-embree4.sh

# Prints the executable cargo built for target `name` from its JSON messages on stdin.
executable() {
  python3 -c '
import json, sys
name = sys.argv[1]
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m["target"]["name"] == name and m.get("executable"):
        print(m["executable"])' "$1" | tail -n1
}
# Both builds share target/: each binary is copied away before the other build replaces it
# (target/release/prism is one path for both feature sets; the rpaths are absolute).
declare -A RATIO PRISM
for v in 3 4; do
  if [ $v = 3 ]; then features=(); else features=(--no-default-features --features embree4,oiio); fi
  RATIO[$v]=$OUT/accel_ratio-e$v
  PRISM[$v]=$OUT/prism-e$v
  cp "$(cargo bench --no-run --bench accel_ratio "${features[@]}" --message-format=json | executable accel_ratio)" "${RATIO[$v]}"
  cp "$(cargo build --release "${features[@]}" --message-format=json | executable prism)" "${PRISM[$v]}"
  echo "== Embree $v: ${RATIO[$v]}, ${PRISM[$v]} (linked with $(ldd "${PRISM[$v]}" | grep -o -m1 'libembree[^ ]*'))"
done

echo "== machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)," \
  "$(grep -m1 -o -w -e avx512f /proc/cpuinfo || echo no-avx512f) $(grep -m1 -o -w -e avx2 /proc/cpuinfo || echo no-avx2)," \
  "$(date -u '+%F %H:%M UTC'), load $(cut -d' ' -f1-3 /proc/loadavg)" | tee "$OUT/machine.txt"

order() { if [ $(( $1 % 2 )) = 1 ]; then echo "3 4"; else echo "4 3"; fi; }
for r in $(seq 1 "$ROUNDS"); do
  for half in 1 2; do
    for v in $(order $(( 2 * r + half ))); do
      echo "== accel_ratio, Embree $v, round $r.$half"
      PRISM_BENCH_PASSES=$PASSES PRISM_BENCH_RAW=1 "${RATIO[$v]}" > "$OUT/ratio-e$v-$r-$half.txt"
    done
  done
done
for scene in cornell terrain; do
  for r in $(seq 1 "$ROUNDS"); do
    for half in 1 2; do
      for v in $(order $(( 2 * r + half ))); do
        echo "== prism bench builtin:$scene, Embree $v, round $r.$half"
        "${PRISM[$v]}" bench "builtin:$scene" --accel embree,obvhs --sampler independent --spp-ladder "$SPP" --threads "$THREADS" \
          --reference-spp 16 --resolution 192x144 --max-depth 5 --out "$OUT/$scene" > /dev/null
        cp "$OUT/$scene/bench.json" "$OUT/render-$scene-e$v-$r-$half.json"
      done
    done
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$OUT/machine.txt"

python3 - "$OUT" "$SPP" "$THREADS" <<'EOF' | tee "$OUT/summary.md"
import glob, json, os, statistics, sys
out = sys.argv[1]

def ratios(pairs):
    r = sorted(a / b for a, b in pairs)
    return f"{statistics.median(r):.2f}× ({r[0]:.2f}–{r[-1]:.2f})"

# accel_ratio: runs of the two builds in the same round half are adjacent; pair pass k of each.
raw = {}
for path in glob.glob(f"{out}/ratio-e*-*-*.txt"):
    v, r, half = os.path.basename(path)[len("ratio-e"):-4].split("-")
    for line in open(path):
        if line.startswith("pass\t"):
            _, k, query, threads, backend, mrays = line.rstrip("\n").split("\t")
            raw[(v, r, half, k, query, threads, backend)] = float(mrays)
slots = sorted({key[1:4] for key in raw})
rows = sorted({(key[4], key[5]) for key in raw}, key=lambda q: (q[0].split(",")[1], q[0], q[1]))
print("| query | threads | E3 embree | E4 embree | E4 ÷ E3 embree | E4 ÷ E3 embree-watertight |"
      " E4 ÷ E3 obvhs (noise) | E3 embree ÷ obvhs | E4 embree ÷ obvhs |")
print("|---|---|---|---|---|---|---|---|---|")
for query, threads in rows:
    get = lambda v, b, s: raw[(v, *s, query, threads, b)]
    med = lambda v, b: statistics.median(get(v, b, s) for s in slots)
    pair = lambda b: [(get("4", b, s), get("3", b, s)) for s in slots]
    within = lambda v: [(get(v, "embree", s), get(v, "obvhs", s)) for s in slots]
    print(f"| {query} | {threads} | {med('3', 'embree'):.2f} | {med('4', 'embree'):.2f} | {ratios(pair('embree'))} |"
          f" {ratios(pair('embree-watertight'))} | {ratios(pair('obvhs'))} | {ratios(within('3'))} | {ratios(within('4'))} |")
print(f"\n{len(slots)} pairs of passes (M rays/s: medians).\n")

print("| scene | E3 embree [M rays/s] | E4 embree [M rays/s] | E4 ÷ E3 embree | E4 ÷ E3 obvhs (noise) |"
      " E3 embree ÷ obvhs | E4 embree ÷ obvhs | build E3 / E4 embree [ms] |")
print("|---|---|---|---|---|---|---|---|")
for scene in ("cornell", "terrain"):
    runs = {}
    for path in glob.glob(f"{out}/render-{scene}-e*-*-*.json"):
        v, r, half = os.path.basename(path)[len(f"render-{scene}-e"):-5].split("-")
        for p in json.load(open(path)):
            runs[(v, r, half, p["accel"])] = p
    slots = sorted({key[1:3] for key in runs})
    rays = lambda v, a, s: runs[(v, *s, a)]["rays_per_s"] / 1e6
    pair = lambda a: [(rays("4", a, s), rays("3", a, s)) for s in slots]
    within = lambda v: [(rays(v, "embree", s), rays(v, "obvhs", s)) for s in slots]
    build = lambda v: 1e3 * statistics.median(runs[(v, *s, "embree")]["build_s"] for s in slots)
    med = lambda v: statistics.median(rays(v, "embree", s) for s in slots)
    print(f"| {scene} | {med('3'):.2f} | {med('4'):.2f} | {ratios(pair('embree'))} | {ratios(pair('obvhs'))} |"
          f" {ratios(within('3'))} | {ratios(within('4'))} | {build('3'):.0f} / {build('4'):.0f} |")
print(f"\n{len(slots)} pairs of runs per scene, {sys.argv[2]} samples per pixel, {sys.argv[3]} threads.")
EOF
