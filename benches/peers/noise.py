"""Noise and agreement of rendered images, measured the same way for every renderer.

Noise of one configuration = RMS(T(seed 1) − T(seed 2)) / √2 over all pixels and the three
linear sRGB channels, where T(x) = x / (1 + |x|) compresses bright pixels (the light, caustics)
so a few of them do not dominate. Two independent renders of the same estimator differ by noise
alone, with twice its variance, hence the √2: no reference image is needed, and neither
renderer is measured against the other's reference. Both renderers' images are rounded to
half floats first, since prism writes half-float OpenEXR.
"""

import math

import numpy as np


def tonemap(x):
    """x / (1 + |x|): the identity near 0, bounded by 1 (odd, so negative RGB stays negative)."""
    return x / (1.0 + np.abs(x))


def as_half(img):
    return np.asarray(img, dtype=np.float32)[..., :3].astype(np.float16).astype(np.float64)


def noise(a, b):
    """RMS(T(a) − T(b)) / √2 of two images of the same estimator with different seeds."""
    d = tonemap(as_half(a)) - tonemap(as_half(b))
    return float(np.sqrt(np.mean(d * d)) / math.sqrt(2.0))


def agreement(p1, p2, m1, m2):
    """How far two renderers' converged images are apart, beyond their noise.

    p1, p2: one renderer's images with two seeds; m1, m2: the other's. On linear RGB the mean of
    each pair has per-pixel noise variance mean((x1 − x2)²)/4, so the expected MSE between the
    two means from noise alone is the sum of the two; `excess_rmse` is what is left of the MSE
    above it (0 when all of the difference is noise)."""
    p1, p2, m1, m2 = (as_half(x) for x in (p1, p2, m1, m2))
    p, m = (p1 + p2) / 2.0, (m1 + m2) / 2.0
    mse = float(np.mean((p - m) ** 2))
    noise_mse = float(np.mean((p1 - p2) ** 2) / 4.0 + np.mean((m1 - m2) ** 2) / 4.0)
    return {
        "rmse": math.sqrt(mse),
        "noise_rmse": math.sqrt(noise_mse),
        "excess_rmse": math.sqrt(max(0.0, mse - noise_mse)),
        "mean_rgb_a": [float(v) for v in p.reshape(-1, 3).mean(axis=0)],
        "mean_rgb_b": [float(v) for v in m.reshape(-1, 3).mean(axis=0)],
        "mean_ratio_b_over_a": [float(v) for v in m.reshape(-1, 3).mean(axis=0) / p.reshape(-1, 3).mean(axis=0)],
    }


def time_to_noise(points, target):
    """Time at which noise = target, from (time_s, noise) points of one configuration: log–log
    interpolation between the two ladder points around it, else the 1/√t law of Monte Carlo
    error from the nearest point ("extrapolated")."""
    pts = sorted(points, key=lambda p: p["time_s"])
    for p, q in zip(pts, pts[1:]):
        if p["noise"] >= target >= q["noise"] and q["noise"] < p["noise"]:
            s = math.log(q["noise"] / p["noise"]) / math.log(q["time_s"] / p["time_s"])
            return p["time_s"] * (target / p["noise"]) ** (1.0 / s), "interpolated"
    near = min(pts, key=lambda p: abs(math.log(p["noise"] / target)))
    return near["time_s"] * (near["noise"] / target) ** 2, "extrapolated"
