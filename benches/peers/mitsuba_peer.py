"""Peer benchmark: prism against Mitsuba 3 on three scenes, time to equal noise.

Run through benches/peers/mitsuba.sh, which makes the virtual environment. The scenes:
  cornell   prism's built-in Cornell box (cornell_scene.py reads it from src/scene/cornell.rs);
  textured  scenes/peer_textured.pbrt: textures and five BSDF kinds (pbrt_scene.py translates it);
  terrain   prism's built-in 1M-triangle terrain, exported once as PLY meshes and a pbrt file
            (examples/terrain_ply.rs, into --cache) that both renderers read.
Both renderers use a box pixel filter (each sample counts in its own pixel only), the same
resolution, depth and Russian roulette start, and the same thread count.

In each of --rounds rounds, for each scene, prism renders every (sampler, spp) of the ladder
with seeds 1 and 2, then Mitsuba does the same for every (variant, sampler): the renderers take
turns (A B A B), so a busy spell on the shared machine hits both. A configuration's noise is
RMS(T(seed 1) − T(seed 2))/√2 on T(x) = x/(1+x)-mapped RGB (noise.py), the same for both
renderers; its time is the render alone (prism's --stats-json elapsed_s; Mitsuba's mi.render to
the end of evaluation), the median over rounds and seeds. Mitsuba's LLVM kernels are compiled in
an untimed warm-up render of each spp after each scene load.

Time to equal noise: the target is the noise Mitsuba's best configuration reaches at the top of
the ladder; every configuration's time to it is read off its ladder (noise.time_to_noise), and
the ratio published is prism's best sampler ÷ Mitsuba's best sampler, per variant.

With --converged-spp, each scene is also rendered at that spp by prism (Sobol) and Mitsuba
(--converged-variant, multijitter), two seeds each, and noise.agreement says how far the two
converged images are apart beyond their noise.

Outputs in --out: run.json (machine, ISA, versions, date, load, every point, the ratios),
peer.md (tables), and the images.
"""

import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import cornell_scene  # noqa: E402
import noise  # noqa: E402
import pbrt_scene  # noqa: E402

SCENES = ["cornell", "textured", "terrain"]


def run(cmd):
    print("+ " + " ".join(cmd), file=sys.stderr, flush=True)
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit("mitsuba_peer.py: %s failed (exit %d): %s" % (cmd[0], done.returncode, done.stderr.strip()))
    return done.stdout


def scene_file(a, name):
    """The pbrt file prism renders (None: prism's built-in Cornell box)."""
    if name == "cornell":
        return None
    if name == "textured":
        return os.path.join(REPO, "scenes", "peer_textured.pbrt")
    path = os.path.join(a.cache, "terrain", "terrain.pbrt")
    if not os.path.exists(path):
        run(["cargo", "run", "--release", "--quiet", "--example", "terrain_ply", "--", os.path.dirname(path)])
    return path


def mitsuba_scene(mi, a, name, sampler, workdir):
    size = (a.size, a.size)
    if name == "cornell":
        return mi.load_dict(cornell_scene.scene_dict(mi, REPO, workdir, size, 1, a.max_depth, sampler))
    return mi.load_dict(pbrt_scene.scene_dict(mi, scene_file(a, name), workdir, size, 1, a.max_depth, sampler))


def load_image(path):
    import mitsuba as mi
    import numpy as np
    return np.array(mi.Bitmap(path))


def prism_render(a, name, sampler, spp, seed, out):
    path = os.path.join(out, "%s_prism_%s_%d_seed%d.exr" % (name, sampler, spp, seed))
    stats = path + ".json"
    cmd = [a.prism, "render"] + ([scene_file(a, name)] if scene_file(a, name) else [])
    run(cmd + ["--spp", str(spp), "--sampler", sampler, "--filter", "box", "--max-depth", str(a.max_depth),
               "--resolution", "%dx%d" % (a.size, a.size), "--seed", str(seed), "--threads", str(a.threads),
               "--accel", "embree", "-o", path, "--stats-json", stats])
    return json.load(open(stats))["elapsed_s"], load_image(path)


def mitsuba_render(mi, scene, spp, seed):
    import drjit as dr
    t0 = time.perf_counter()
    img = mi.render(scene, spp=spp, seed=seed)
    dr.eval(img)
    dr.sync_thread()
    return time.perf_counter() - t0, img


def ladder_of(a, sampler):
    ladder = [int(s) for s in a.ladder.split(",")]
    if sampler == "ldsampler":
        # Mitsuba rounds ldsampler's sample count up to a power of four.
        ladder = [n for n in ladder if n & (n - 1) == 0 and n.bit_length() % 2 == 1]
    return ladder


def point(renderer, scene, spp, times, imgs, a, spp_rendered=None):
    """`spp_rendered`: what the sampler really took (Mitsuba's multijitter rounds 32 up to 35)."""
    n = spp_rendered or spp
    return {"scene": scene, "renderer": renderer, "spp": spp, "spp_rendered": n, "times_s": times,
            "noise": noise.noise(imgs[0], imgs[1]), "samples_per_s": a.size * a.size * n / statistics.median(times)}


def prism_round(a, name, out):
    pts = []
    for sampler in a.prism_samplers.split(","):
        for spp in ladder_of(a, sampler):
            res = [prism_render(a, name, sampler, spp, s, out) for s in (1, 2)]
            pts.append(point("prism " + sampler, name, spp, [t for t, _ in res], [i for _, i in res], a))
            print("%s prism %s %d spp: %.3f / %.3f s, noise %.5f" % (
                name, sampler, spp, res[0][0], res[1][0], pts[-1]["noise"]), file=sys.stderr, flush=True)
    return pts


def mitsuba_round(a, name, variant, out):
    import mitsuba as mi
    import drjit as dr
    mi.set_variant(variant)
    dr.set_thread_count(a.threads)
    samplers = a.llvm_samplers if variant.startswith("llvm") else a.scalar_samplers
    pts = []
    for sampler in samplers.split(","):
        scene = mitsuba_scene(mi, a, name, sampler, os.path.join(out, "mitsuba_scene_" + name))
        for spp in ladder_of(a, sampler):
            if variant.startswith("llvm"):
                mitsuba_render(mi, scene, spp, 999)  # compiles this spp's kernel: not timed
            res = [mitsuba_render(mi, scene, spp, s) for s in (1, 2)]
            imgs = [r[1] for r in res]
            mi.Bitmap(imgs[0]).write(os.path.join(out, "%s_%s_%s_%d_seed1.exr" % (name, variant, sampler, spp)))
            sampler_copy = scene.sensors()[0].sampler().clone()
            sampler_copy.set_sample_count(spp)
            pts.append(point("mitsuba %s %s" % (variant, sampler), name, spp, [t for t, _ in res], imgs, a,
                             sampler_copy.sample_count()))
            print("%s %s %s %d spp: %.3f / %.3f s, noise %.5f" % (
                name, variant, sampler, spp, res[0][0], res[1][0], pts[-1]["noise"]), file=sys.stderr, flush=True)
    return pts


def merge_rounds(rounds, a):
    """One point per (scene, renderer, spp): every round's times, the median as its time. The
    images are the same in every round (fixed seeds), so the noise is too."""
    by_key = {}
    for p in (p for r in rounds for p in r):
        by_key.setdefault((p["scene"], p["renderer"], p["spp"]), []).append(p)
    out = []
    for (scene, renderer, spp), ps in by_key.items():
        times = [t for p in ps for t in p["times_s"]]
        t = statistics.median(times)
        out.append({"scene": scene, "renderer": renderer, "spp": spp, "spp_rendered": ps[0]["spp_rendered"],
                    "time_s": t, "time_min_s": min(times),
                    "time_max_s": max(times), "noise": ps[0]["noise"],
                    "noise_spread": max(p["noise"] for p in ps) - min(p["noise"] for p in ps),
                    "samples_per_s": a.size * a.size * ps[0]["spp_rendered"] / t})
    return out


def ratios(points, scene, variants, top_spp):
    """Time to equal noise per configuration and prism's best ÷ each Mitsuba variant's best.
    The target is the lowest noise any Mitsuba configuration reaches at `top_spp`."""
    pts = [p for p in points if p["scene"] == scene]
    mits = [p for p in pts if p["renderer"].startswith("mitsuba") and p["spp"] == top_spp]
    if not mits:
        return None
    target = min(p["noise"] for p in mits)
    renderers = list(dict.fromkeys(p["renderer"] for p in pts))
    times = {r: noise.time_to_noise([p for p in pts if p["renderer"] == r], target) for r in renderers}
    prism_best = min((t, r) for r, (t, _) in times.items() if r.startswith("prism"))
    out = {"target_noise": target, "time_to_target": {r: {"time_s": t, "how": h} for r, (t, h) in times.items()},
           "prism_best": prism_best[1], "ratio": {}}
    for v in variants:
        ms = [(t, r) for r, (t, _) in times.items() if r.startswith("mitsuba %s " % v)]
        if ms:
            best = min(ms)
            out["ratio"][v] = {"mitsuba_best": best[1], "prism_over_mitsuba": prism_best[0] / best[0]}
    return out


def converged(a, name, out):
    import mitsuba as mi
    import drjit as dr
    n = a.converged_spp
    p = [prism_render(a, name, "sobol", n, s, out)[1] for s in (11, 12)]
    mi.set_variant(a.converged_variant)
    dr.set_thread_count(a.threads)
    scene = mitsuba_scene(mi, a, name, "multijitter", os.path.join(out, "mitsuba_scene_" + name))
    m = [mitsuba_render(mi, scene, n, s)[1] for s in (11, 12)]
    mi.Bitmap(m[0]).write(os.path.join(out, "%s_mitsuba_converged.exr" % name))
    res = noise.agreement(p[0], p[1], m[0], m[1])
    res.update({"spp": n, "variant": a.converged_variant})
    return res


def loadavg():
    return open("/proc/loadavg").read().split()[:3]


def machine(a):
    """CPU model and ISA from /proc/cpuinfo, threads, versions: the figures mean little without."""
    import mitsuba as mi
    import drjit as dr
    info = open("/proc/cpuinfo").read()
    model = next((line.split(":", 1)[1].strip() for line in info.splitlines() if line.startswith("model name")), "?")
    flags = next((line.split(":", 1)[1].split() for line in info.splitlines() if line.startswith("flags")), [])
    isa = {f: f in flags for f in ["sse4_2", "avx", "avx2", "fma", "avx512f", "avx512bw", "avx512vl"]}
    prism_version = run([a.prism, "--version"]).strip()
    return {"cpu": model, "isa": isa, "logical_cpus": os.cpu_count(), "threads": a.threads,
            "os": "%s %s" % (platform.system(), platform.release()), "python": platform.python_version(),
            "prism": prism_version, "mitsuba": mi.__version__, "drjit": dr.__version__,
            "drjit_libllvm": os.environ.get("DRJIT_LIBLLVM_PATH", "")}


def fmt_range(p):
    return "%.3f (%.3f–%.3f)" % (p["time_s"], p["time_min_s"], p["time_max_s"])


def markdown(run_info, points, ratio_by_scene, conv):
    m = run_info["machine"]
    isa = ", ".join(k for k, v in m["isa"].items() if v)
    lines = ["- machine: %s, %d logical CPUs, %d threads; ISA %s" % (m["cpu"], m["logical_cpus"], m["threads"], isa),
             "- %s; Mitsuba %s, Dr.Jit %s; %s" % (m["prism"], m["mitsuba"], m["drjit"], m["os"]),
             "- %s – %s UTC; load average before %s, after %s" % (
                 run_info["started_utc"], run_info["finished_utc"], " ".join(run_info["load_before"]),
                 " ".join(run_info["load_after"])), ""]
    for scene, r in ratio_by_scene.items():
        lines += ["### %s" % scene, "", "| renderer | spp | time [s], median (range) | M samples/s | noise |",
                  "|---|---|---|---|---|"]
        for p in (p for p in points if p["scene"] == scene):
            lines.append("| %s | %d | %s | %.3f | %.5f |" % (
                p["renderer"], p["spp"], fmt_range(p), p["samples_per_s"] / 1e6, p["noise"]))
        if r:
            lines += ["", "Time to noise %.5f:" % r["target_noise"], "", "| renderer | time [s] | how |",
                      "|---|---|---|"]
            for name, t in r["time_to_target"].items():
                lines.append("| %s | %.3f | %s |" % (name, t["time_s"], t["how"]))
            for v, q in r["ratio"].items():
                rng = q.get("per_round", [])
                lines += ["", "**%s ÷ %s: %.2f×** (rounds alone: %s)" % (
                    r["prism_best"], q["mitsuba_best"], q["prism_over_mitsuba"], ", ".join("%.2f" % x for x in rng))]
        if scene in conv:
            c = conv[scene]
            lines += ["", "Converged, %d spp × 2 seeds (prism Sobol, Mitsuba %s multijitter), linear sRGB: RMSE "
                      "%.3e between the renderers' means, %.3e expected from their noise, excess %.3e; mean RGB "
                      "Mitsuba ÷ prism %s" % (c["spp"], c["variant"], c["rmse"], c["noise_rmse"], c["excess_rmse"],
                                             " / ".join("%.4f" % x for x in c["mean_ratio_b_over_a"]))]
        lines.append("")
    return "\n".join(lines) + "\n"


def utc_now():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--prism", default=os.path.join(REPO, "target", "release", "prism"))
    p.add_argument("--out", default=os.path.join(REPO, "target", "peers", "out"))
    p.add_argument("--cache", default=os.path.join(REPO, "target", "peers", "cache"),
                   help="where the terrain's PLY meshes are written once")
    p.add_argument("--scenes", default=",".join(SCENES))
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--size", type=int, default=256)
    p.add_argument("--max-depth", type=int, default=8, help="pbrt's convention: scattering events")
    p.add_argument("--ladder", default="64,256",
                   help="spp of every configuration, seeds 1 and 2 each (powers of 4 suit Mitsuba's samplers)")
    p.add_argument("--prism-samplers", default="independent,sobol")
    p.add_argument("--variants", default="llvm_ad_spectral,scalar_spectral")
    p.add_argument("--llvm-samplers", default="independent,multijitter,ldsampler",
                   help="ldsampler: Mitsuba's (0,2)-sequence sampler, at 4^k spp only; multijitter: "
                        "correlated multi-jittered sampling")
    p.add_argument("--scalar-samplers", default="multijitter",
                   help="scalar_spectral is the slowest; by default only the sampler best for it before")
    p.add_argument("--rounds", type=int, default=2, help="the renderers take turns this many times per scene")
    p.add_argument("--converged-spp", type=int, default=0,
                   help="also compare converged images at this spp (0: skip)")
    p.add_argument("--converged-variant", default="llvm_ad_spectral")
    a = p.parse_args()
    for n in (int(x) for x in a.ladder.split(",")):
        if n & (n - 1) or n.bit_length() % 2 == 0:
            # Mitsuba's ldsampler takes only powers of four and its multijitter rounds others up.
            print("mitsuba_peer.py: %d spp is not a power of 4: ldsampler skips it" % n, file=sys.stderr)
    os.makedirs(a.out, exist_ok=True)
    scenes = [s for s in a.scenes.split(",") if s]
    for s in scenes:
        if s not in SCENES:
            sys.exit("mitsuba_peer.py: unknown scene %r (known: %s)" % (s, ", ".join(SCENES)))
    variants = [v for v in a.variants.split(",") if v]
    import mitsuba as mi
    mi.set_variant(variants[0] if variants else "scalar_spectral")
    info = {"machine": machine(a), "args": vars(a), "started_utc": utc_now(), "load_before": loadavg()}
    for s in scenes:
        scene_file(a, s)  # writes the terrain's files before any timing
    rounds = []
    for r in range(a.rounds):
        pts = []
        for s in scenes:
            print("== round %d of %d, %s" % (r + 1, a.rounds, s), file=sys.stderr, flush=True)
            pts += prism_round(a, s, a.out)
            for v in variants:
                pts += mitsuba_round(a, s, v, a.out)
        rounds.append(pts)
    points = merge_rounds(rounds, a)
    top = max(int(x) for x in a.ladder.split(","))
    ratio_by_scene = {s: ratios(points, s, variants, top) for s in scenes}
    for s, r in ratio_by_scene.items():
        # The same ratio from each round's own times: its spread shows how much the machine moved.
        per_round = [ratios(merge_rounds([pts], a), s, variants, top) for pts in rounds]
        for v in (r or {}).get("ratio", {}):
            r["ratio"][v]["per_round"] = [q["ratio"][v]["prism_over_mitsuba"] for q in per_round]
    conv = {s: converged(a, s, a.out) for s in scenes} if a.converged_spp > 0 else {}
    info.update({"finished_utc": utc_now(), "load_after": loadavg(), "points": points,
                 "time_to_equal_noise": ratio_by_scene, "converged": conv})
    json.dump(info, open(os.path.join(a.out, "run.json"), "w"), indent=2)
    md = markdown(info, points, ratio_by_scene, conv)
    open(os.path.join(a.out, "peer.md"), "w").write(md)
    print(md)


if __name__ == "__main__":
    main()
