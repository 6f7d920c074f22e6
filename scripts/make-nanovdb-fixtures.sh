#!/usr/bin/env bash
# Writes the NanoVDB test files under tests/data/nanovdb/ with the real OpenVDB/NanoVDB
# libraries (Debian's python3-openvdb writes .vdb, libnanovdb-tools' nanovdb_convert turns it
# into .nvdb), so that prism's reader is checked against files it did not write. The values are
# closed forms that src/media/nanovdb/tests.rs evaluates again; run this only to regenerate them.
#
#   density.nvdb (ZIP)  "density": 40³ voxels over index [-8, 31]³ of
#                         f = 4u(1−u)(0.25 + 0.75v)(1.5 − w), u = (i+8)/39, v = (j+8)/39, w = (k+8)/39
#                       rounded to float32, except an empty 8³ leaf at [8,15]×[0,7]×[16,23] (no leaf:
#                       background 0), voxels with (i + 2j + 3k) mod 11 = 0 left inactive (0), and an
#                       active 8³ tile of 0.625 at [16,23]×[16,23]×[0,7]; voxel size 0.05, the index
#                       origin at world (0.3, −0.2, 0.1).
#                       "temperature": T = 1000 + 50i + 20j + 10k over [0, 23]³, the same map.
#   tiles.nvdb (ZIP)    "density": background 0.125, a root tile of 0.25 over [−4096, −1]×[0, 4095]²,
#                       an upper-node tile of 0.5 over [128, 255]×[0, 127]², voxels (1, 2, 3) = 0.75 and
#                       (−1, −1, −1) = 0.875; unit voxels. "velocity": a Vec3f grid (refused by prism).
#   plain.nvdb (NONE)   "density": g = (i + 8j + 64k)/512 over [0, 7]³, voxel size 0.5, origin (1, 2, 3).
set -euo pipefail
cd "$(dirname "$0")/.."
missing=()
for pkg in python3-openvdb libnanovdb-tools; do
  dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
done
if ((${#missing[@]})); then
  echo "install first: apt-get install ${missing[*]}" >&2
  exit 1
fi
out=tests/data/nanovdb
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
/usr/bin/python3 - "$tmp" <<'PY'
import sys
import pyopenvdb as vdb

tmp = sys.argv[1]

def transform(voxel, origin):
    t = vdb.createLinearTransform(voxelSize=voxel)
    t.translate(origin)
    return t

# density.vdb: the sparse analytic density and a temperature grid beside it.
density = vdb.FloatGrid(0.0)
density.name = "density"
density.gridClass = vdb.GridClass.FOG_VOLUME
density.transform = transform(0.05, (0.3, -0.2, 0.1))
density.fill((16, 16, 0), (23, 23, 7), 0.625, True)
acc = density.getAccessor()
for k in range(-8, 32):
    for j in range(-8, 32):
        for i in range(-8, 32):
            if 8 <= i <= 15 and 0 <= j <= 7 and 16 <= k <= 23:
                continue
            if 16 <= i <= 23 and 16 <= j <= 23 and 0 <= k <= 7:
                continue
            if (i + 2 * j + 3 * k) % 11 == 0:
                continue
            u, v, w = (i + 8) / 39.0, (j + 8) / 39.0, (k + 8) / 39.0
            acc.setValueOn((i, j, k), 4.0 * u * (1.0 - u) * (0.25 + 0.75 * v) * (1.5 - w))
temperature = vdb.FloatGrid(0.0)
temperature.name = "temperature"
temperature.gridClass = vdb.GridClass.FOG_VOLUME
temperature.transform = transform(0.05, (0.3, -0.2, 0.1))
acc = temperature.getAccessor()
for k in range(0, 24):
    for j in range(0, 24):
        for i in range(0, 24):
            acc.setValueOn((i, j, k), 1000.0 + 50.0 * i + 20.0 * j + 10.0 * k)
vdb.write(f"{tmp}/density.vdb", grids=[density, temperature])

# tiles.vdb: root and upper-node tiles, a non-zero background, and a grid of another type.
tiles = vdb.FloatGrid(0.125)
tiles.name = "density"
tiles.fill((-4096, 0, 0), (-1, 4095, 4095), 0.25, True)
tiles.fill((128, 0, 0), (255, 127, 127), 0.5, True)
acc = tiles.getAccessor()
acc.setValueOn((1, 2, 3), 0.75)
acc.setValueOn((-1, -1, -1), 0.875)
velocity = vdb.Vec3SGrid()
velocity.name = "velocity"
velocity.getAccessor().setValueOn((0, 0, 0), (1.0, 2.0, 3.0))
vdb.write(f"{tmp}/tiles.vdb", grids=[tiles, velocity])

# plain.vdb: one leaf, for the uncompressed codec.
plain = vdb.FloatGrid(0.0)
plain.name = "density"
plain.gridClass = vdb.GridClass.FOG_VOLUME
plain.transform = transform(0.5, (1.0, 2.0, 3.0))
acc = plain.getAccessor()
for k in range(8):
    for j in range(8):
        for i in range(8):
            acc.setValueOn((i, j, k), (i + 8 * j + 64 * k) / 512.0)
vdb.write(f"{tmp}/plain.vdb", grids=[plain])
PY
nanovdb_convert -f -z "$tmp/density.vdb" "$out/density.nvdb"
nanovdb_convert -f -z "$tmp/tiles.vdb" "$out/tiles.nvdb"
nanovdb_convert -f "$tmp/plain.vdb" "$out/plain.nvdb"
nanovdb_print "$out/density.nvdb" "$out/tiles.nvdb" "$out/plain.nvdb" || true
ls -l "$out"
