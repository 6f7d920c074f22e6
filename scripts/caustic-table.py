#!/usr/bin/env python3
"""The Markdown tables of scripts/bench-caustic.sh from its CSV (integrator, count, wall, cpu,
rmse, mae): errors and times per count (— where an integrator did not run), then each
integrator's CPU seconds to a target MAE and RMSE, interpolated log-log between the two counts
whose errors bracket it (the first crossing).

Usage: caustic-table.py CSV TARGET_MAE TARGET_RMSE"""
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
targets = {"mae": float(sys.argv[2]), "rmse": float(sys.argv[3])}
integrators = list(dict.fromkeys(r["integrator"] for r in rows))
counts = list(dict.fromkeys(r["count"] for r in rows))
at = {(r["integrator"], r["count"]): r for r in rows}
print("| count | " + " | ".join(f"{i} wall / CPU [s] | {i} RMSE | {i} MAE" for i in integrators) + " |")
print("|---" * (1 + 3 * len(integrators)) + "|")
for c in counts:
    cells = []
    for i in integrators:
        r = at.get((i, c))
        cells += [f"{r['wall']} / {r['cpu']}", f"{float(r['rmse']):.3g}", f"{float(r['mae']):.3g}"] if r else ["—"] * 3
    print(f"| {c} | " + " | ".join(cells) + " |")

def time_to(i, metric, target):
    """CPU seconds at which the error first reaches target, log-log interpolated."""
    pts = [(float(at[(i, c)]["cpu"]), float(at[(i, c)][metric])) for c in counts if (i, c) in at]
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if e0 > target >= e1:
            f = math.log(e0 / target) / math.log(e0 / e1)
            return f"{math.exp(math.log(t0) + f * math.log(t1 / t0)):.2g}"
    if pts[0][1] <= target:
        return f"≤ {pts[0][0]:.2g}"
    return f"> {pts[-1][0]:.2g} (not reached)"

print()
print("| CPU seconds to | " + " | ".join(integrators) + " |")
print("|---" * (1 + len(integrators)) + "|")
for metric, target in targets.items():
    print(f"| {metric.upper()} {target} | " + " | ".join(time_to(i, metric, target) for i in integrators) + " |")
