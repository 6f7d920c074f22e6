"""Peer benchmark: prism against Mitsuba 3 on prism's built-in Cornell box.

Run through benches/peers/mitsuba.sh, which makes the virtual environment. In one run, on the
same machine and thread count, it
  1. renders (or reuses) prism's converged reference (Sobol, high spp);
  2. runs `prism bench` (Embree; independent and Sobol samplers) against that reference;
  3. renders the same scene with Mitsuba's scalar_spectral and llvm_ad_spectral variants and
     several of its samplers at each spp of a ladder, in one pass each, and measures the RMSE
     of every image against prism's reference with `prism compare`;
  4. renders Mitsuba's converged image and compares it with the reference (and prism's own
     image at the same spp, to separate noise from disagreement);
  5. reports the time each renderer needs to reach a target RMSE, as ratios to Mitsuba's.
Steps 2 and 3 run --rounds times, the renderers taking turns; each point's time is the median.
Outputs: OUT/peer.json (every point), OUT/peer.md (tables), OUT/*.exr.
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from cornell_scene import scene_dict  # noqa: E402


def run(cmd):
    print("+ " + " ".join(cmd), file=sys.stderr, flush=True)
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def compare(prism, a, b):
    return json.loads(run([prism, "compare", "--json", a, b]))


def prism_reference(a, out):
    """prism's converged image: Sobol, box filter, cached with its settings."""
    path = os.path.join(out, "prism_reference.exr")
    meta = {"spp": a.reference_spp, "size": a.size, "max_depth": a.max_depth, "seed": 65261, "sampler": "sobol"}
    meta_path = path + ".json"
    if os.path.exists(path) and os.path.exists(meta_path) and json.load(open(meta_path)) == meta:
        print("reference: reusing %s" % path, file=sys.stderr)
        return path
    t0 = time.time()
    run([a.prism, "render", "--spp", str(a.reference_spp), "--sampler", "sobol", "--filter", "box",
         "--max-depth", str(a.max_depth), "--resolution", "%dx%d" % (a.size, a.size), "--seed", "65261",
         "--threads", str(a.threads), "--accel", "embree", "-o", path])
    print("reference: %d spp in %.0f s" % (a.reference_spp, time.time() - t0), file=sys.stderr)
    json.dump(meta, open(meta_path, "w"))
    return path


def prism_ladder(a, ref, out):
    d = os.path.join(out, "prism")
    run([a.prism, "bench", "--accel", "embree", "--sampler", "independent,sobol", "--spp-ladder", a.prism_ladder,
         "--reference", ref, "--resolution", "%dx%d" % (a.size, a.size), "--max-depth", str(a.max_depth),
         "--threads", str(a.threads), "--out", d])
    pts = json.load(open(os.path.join(d, "bench.json")))
    return [{"renderer": "prism " + p["accel"] + " " + p["sampler"], "spp": p["spp"], "time_s": p["time_s"],
             "rmse": p["rmse"], "samples_per_s": p["samples_per_s"]} for p in pts]


def mitsuba_render(mi, scene, spp, pass_spp, seed0):
    """`spp` samples per pixel in passes of at most `pass_spp` (0: one pass); the box-filtered
    passes are averaged with equal weights. One pass is Mitsuba at its best: its ldsampler
    stratifies over all the pixel's samples only within a pass, and the LLVM variant's memory
    stays small (144 MB peak at 256 spp, 256², in one pass)."""
    import drjit as dr
    pass_spp = pass_spp or spp
    acc, done, k = None, 0, 0
    while done < spp:
        n = min(pass_spp, spp - done)
        img = mi.render(scene, spp=n, seed=seed0 + k)
        img = img * (n / spp)
        acc = img if acc is None else acc + img
        done += n
        k += 1
    dr.eval(acc)
    dr.sync_thread()
    return acc


# (variant, sampler, spp) whose LLVM kernels this process has compiled.
WARMED = set()


def pass_spp_of(a, variant):
    """The scalar variant always renders in one pass; the LLVM one as --llvm-pass-spp says."""
    return 0 if variant.startswith("scalar") else a.llvm_pass_spp


def mitsuba_ladder(a, variant, sampler, ref, out):
    import mitsuba as mi
    import drjit as dr
    mi.set_variant(variant)
    dr.set_thread_count(a.threads)
    d = scene_dict(mi, REPO, os.path.join(out, "scene"), (a.size, a.size), 1, a.max_depth, sampler)
    scene = mi.load_dict(d)
    pass_spp = pass_spp_of(a, variant)
    ladder = [int(s) for s in (a.llvm_ladder if variant.startswith("llvm") else a.scalar_ladder).split(",")]
    if sampler == "ldsampler":
        # Mitsuba rounds ldsampler's sample count up to a square power of two (4^k).
        ladder = [n for n in ladder if n & (n - 1) == 0 and n.bit_length() % 2 == 1]
    # Warm-up, in the first round only: the LLVM variant compiles a kernel per pass size on
    # first use (then caches it); compilation is a start-up cost, like prism's scene build, and
    # is not timed.
    t0 = time.time()
    for n in sorted({min(spp, pass_spp or spp) for spp in ladder}) if variant.startswith("llvm") else []:
        if (variant, sampler, n) not in WARMED:
            mitsuba_render(mi, scene, n, pass_spp, 999)
            WARMED.add((variant, sampler, n))
    print("%s: warm-up %.2f s" % (variant, time.time() - t0), file=sys.stderr)
    pts = []
    for spp in ladder:
        t0 = time.perf_counter()
        img = mitsuba_render(mi, scene, spp, pass_spp, 1000 * spp)
        t = time.perf_counter() - t0
        path = os.path.join(out, "%s_%s_%d.exr" % (variant, sampler, spp))
        mi.Bitmap(img).write(path)
        m = compare(a.prism, path, ref)
        pts.append({"renderer": "mitsuba %s %s" % (variant, sampler), "spp": spp, "time_s": t, "rmse": m["rmse"],
                    "samples_per_s": a.size * a.size * spp / t})
        print("%s %s %5d spp %8.3f s %6.3f M samples/s RMSE %.4e" % (
            variant, sampler, spp, t, pts[-1]["samples_per_s"] / 1e6, m["rmse"]), file=sys.stderr, flush=True)
    return pts


def time_to_target(points, target):
    """Time at which RMSE = target: log-log interpolation between the ladder points around it,
    or, outside the ladder, the 1/√t law from the nearest point (MC error ∝ t^-1/2)."""
    pts = sorted(points, key=lambda p: p["time_s"])
    for p, q in zip(pts, pts[1:]):
        if p["rmse"] >= target >= q["rmse"]:
            s = math.log(q["rmse"] / p["rmse"]) / math.log(q["time_s"] / p["time_s"])
            return p["time_s"] * (target / p["rmse"]) ** (1.0 / s), "interpolated"
    near = min(pts, key=lambda p: abs(math.log(p["rmse"] / target)))
    return near["time_s"] * (near["rmse"] / target) ** 2, "extrapolated"


def median_points(rounds, pixels):
    """One point per (renderer, spp): the median time over the rounds, with its range. On a
    shared machine one renderer's run can be slowed by 20% or more while another's is not;
    taking turns and the median keeps that out of the ratios. The images are the same in every
    round (fixed seeds), so the RMSE is."""
    by_key = {}
    for pts in rounds:
        for p in pts:
            by_key.setdefault((p["renderer"], p["spp"]), []).append(p)
    out = []
    for (renderer, spp), ps in by_key.items():
        times = sorted(p["time_s"] for p in ps)
        t = statistics.median(times)
        out.append({"renderer": renderer, "spp": spp, "time_s": t, "time_min_s": times[0], "time_max_s": times[-1],
                    "rmse": ps[0]["rmse"], "rmse_spread": max(p["rmse"] for p in ps) - min(p["rmse"] for p in ps),
                    "samples_per_s": pixels * spp / t})
    return out


def converged(a, ref, out):
    """Mitsuba's converged image against prism's reference, beside prism's own image at the same
    spp and a different seed: if Mitsuba agrees, both RMSEs are the same noise floor."""
    import mitsuba as mi
    import drjit as dr
    variant = a.converged_variant
    mi.set_variant(variant)
    dr.set_thread_count(a.threads)
    scene = mi.load_dict(scene_dict(mi, REPO, os.path.join(out, "scene"), (a.size, a.size), 1, a.max_depth))
    img = mitsuba_render(mi, scene, a.converged_spp, pass_spp_of(a, variant), 77)
    mpath = os.path.join(out, "mitsuba_converged.exr")
    mi.Bitmap(img).write(mpath)
    ppath = os.path.join(out, "prism_converged.exr")
    run([a.prism, "render", "--spp", str(a.converged_spp), "--sampler", "independent", "--filter", "box",
         "--max-depth", str(a.max_depth), "--resolution", "%dx%d" % (a.size, a.size), "--seed", "4242",
         "--threads", str(a.threads), "--accel", "embree", "-o", ppath])
    run([a.prism, "compare", mpath, ref, "--diff", os.path.join(out, "mitsuba_vs_prism_diff.png")])
    # Mean colour over the image: a systematic difference shows here, noise averages out.
    import numpy as np
    means = {}
    for name, p in [("mitsuba", mpath), ("prism", ppath), ("reference", ref)]:
        means[name] = [float(x) for x in np.array(mi.Bitmap(p)).reshape(-1, 3).mean(axis=0)]
    return {"spp": a.converged_spp, "variant": variant, "mitsuba_vs_ref": compare(a.prism, mpath, ref),
            "prism_vs_ref": compare(a.prism, ppath, ref), "mitsuba_vs_prism": compare(a.prism, mpath, ppath),
            "mean_rgb": means}


def markdown(points, conv, times_by_target):
    lines = ["| renderer | spp | time [s], median | range over rounds [s] | M samples/s | RMSE |",
             "|---|---|---|---|---|---|"]
    for p in points:
        lines.append("| %s | %d | %.3f | %.3f–%.3f | %.3f | %.3e |" % (
            p["renderer"], p["spp"], p["time_s"], p["time_min_s"], p["time_max_s"], p["samples_per_s"] / 1e6,
            p["rmse"]))
    for target, times in times_by_target.items():
        lines += ["", "Time to RMSE %.3g (linear sRGB, against prism's reference):" % target, "",
                  "| renderer | time [s] | how | time / best Mitsuba scalar_spectral | "
                  "time / best Mitsuba llvm_ad_spectral |", "|---|---|---|---|---|"]
        # Each Mitsuba variant at its best sampler.
        base = {}
        for v in ["scalar_spectral", "llvm_ad_spectral"]:
            ts = [t for r, (t, _) in times.items() if r.startswith("mitsuba " + v + " ")]
            base[v] = min(ts) if ts else None
        for r, (t, how) in times.items():
            ratio = ["%.2f" % (t / base[v]) if base[v] else "–" for v in ["scalar_spectral", "llvm_ad_spectral"]]
            lines.append("| %s | %.3f | %s | %s | %s |" % (r, t, how, ratio[0], ratio[1]))
    if conv:
        lines += ["", "Converged images at %d spp (Mitsuba %s; prism independent):" % (conv["spp"], conv["variant"]),
                  "", "| pair | RMSE | relMSE | MAE |", "|---|---|---|---|"]
        for k in ["mitsuba_vs_ref", "prism_vs_ref", "mitsuba_vs_prism"]:
            m = conv[k]
            lines.append("| %s | %.3e | %.3e | %.3e |" % (k.replace("_", " "), m["rmse"], m["rel_mse"], m["mae"]))
        lines += ["", "Mean linear sRGB over the image: " +
                  ", ".join("%s (%.5f, %.5f, %.5f)" % (k, *v) for k, v in conv["mean_rgb"].items())]
    return "\n".join(lines) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--prism", default=os.path.join(REPO, "target", "release", "prism"))
    p.add_argument("--out", default=os.path.join(REPO, "target", "peers", "out"))
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--size", type=int, default=256)
    p.add_argument("--max-depth", type=int, default=8, help="pbrt's convention: scattering events")
    p.add_argument("--reference-spp", type=int, default=2048)
    ladder = "4,8,16,32,64,128,256"
    p.add_argument("--prism-ladder", default=ladder)
    p.add_argument("--scalar-ladder", default=ladder)
    p.add_argument("--llvm-ladder", default=ladder)
    p.add_argument("--llvm-pass-spp", type=int, default=0,
                   help="render the LLVM variant in passes of at most this many spp (0: one pass)")
    p.add_argument("--variants", default="scalar_spectral,llvm_ad_spectral")
    p.add_argument("--mitsuba-samplers", default="independent,ldsampler,multijitter",
                   help="Mitsuba samplers (ldsampler: its low-discrepancy (0,2)-sequence sampler, at 4^k spp "
                        "only; multijitter: correlated multi-jittered sampling)")
    p.add_argument("--rounds", type=int, default=3,
                   help="the renderers take turns this many times; each point's time is the median")
    p.add_argument("--converged-spp", type=int, default=512)
    p.add_argument("--converged-variant", default="llvm_ad_spectral")
    p.add_argument("--target-rmse", default="0.05,0.02,0.01",
                   help="comma-separated RMSE targets (linear sRGB); each gets its own table")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    ref = prism_reference(a, a.out)
    rounds = []
    for r in range(a.rounds):
        print("== round %d of %d" % (r + 1, a.rounds), file=sys.stderr, flush=True)
        pts = prism_ladder(a, ref, a.out)
        for v in [v for v in a.variants.split(",") if v]:
            for sampler in a.mitsuba_samplers.split(","):
                pts += mitsuba_ladder(a, v, sampler, ref, a.out)
        rounds.append(pts)
    points = median_points(rounds, a.size * a.size)
    conv = converged(a, ref, a.out) if a.converged_spp > 0 else None
    renderers = list(dict.fromkeys(p["renderer"] for p in points))
    times_by_target = {}
    for target in [float(t) for t in a.target_rmse.split(",")]:
        times_by_target[target] = {r: time_to_target([p for p in points if p["renderer"] == r], target)
                                   for r in renderers}
    json.dump({"args": vars(a), "points": points, "converged": conv,
               "time_to_target": {str(t): {r: {"time_s": s, "how": h} for r, (s, h) in times.items()}
                                  for t, times in times_by_target.items()}},
              open(os.path.join(a.out, "peer.json"), "w"), indent=2)
    md = markdown(points, conv, times_by_target)
    open(os.path.join(a.out, "peer.md"), "w").write(md)
    print(md)


if __name__ == "__main__":
    main()
