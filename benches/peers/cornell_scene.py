"""prism's built-in Cornell box (src/scene/cornell.rs) as a Mitsuba 3 scene dictionary.

The geometry and the measured spectra are read from the Rust source itself, so the two renderers
see the same numbers: the reflectance tables (400-700 nm every 4 nm, held flat to 360 and 830 nm
exactly as prism extends them), the light's emission (400/500/600/700 nm, zero outside), the 16
quads in the order prism adds them, and the camera (35 mm lens on a 25 mm sensor).
"""

import math
import os
import re

# Material of each quad, in the order the quads appear in add_cornell_box().
QUAD_MATERIALS = ["white"] * 3 + ["green", "red"] + ["white"] * 10 + ["light"]


def _array(src, name):
    m = re.search(r"const %s: \[f32; (\d+)\] = \[(.*?)\];" % name, src, re.S)
    if not m:
        raise ValueError("cornell.rs: no table %s" % name)
    values = [float(v) for v in m.group(2).replace("\n", " ").split(",") if v.strip()]
    if len(values) != int(m.group(1)):
        raise ValueError("cornell.rs: %s has %d values, declared %s" % (name, len(values), m.group(1)))
    return values


def _const(src, name):
    m = re.search(r"const %s: f32 = ([0-9.]+);" % name, src)
    if not m:
        raise ValueError("cornell.rs: no constant %s" % name)
    return float(m.group(1))


def read_cornell(repo):
    """Spectra (wavelengths, values), quads and light scale from src/scene/cornell.rs."""
    with open(os.path.join(repo, "src", "scene", "cornell.rs")) as f:
        src = f.read()
    start, step = _const(src, "REFL_START"), _const(src, "REFL_STEP")
    spectra = {}
    for name in ["WHITE", "GREEN", "RED"]:
        v = _array(src, name)
        lam = [360.0] + [start + step * i for i in range(len(v))] + [830.0]
        spectra[name.lower()] = (lam, [v[0]] + v + [v[-1]])
    m = re.search(r"const LIGHT: \[\(f32, f32\); 4\] = \[(.*?)\];", src, re.S)
    pairs = re.findall(r"\(([0-9.]+), ([0-9.]+)\)", m.group(1))
    spectra["light"] = ([float(a) for a, _ in pairs], [float(b) for _, b in pairs])
    body = src[src.index("pub fn add_cornell_box"):]
    num = r"\s*(-?[0-9.]+)\s*"
    point = r"\[%s,%s,%s\]" % (num, num, num)
    quads = []
    for q in re.finditer(r"\[\s*%s,\s*%s,\s*%s,\s*%s\s*\]" % (point, point, point, point), body):
        c = [float(x) for x in q.groups()]
        quads.append([c[0:3], c[3:6], c[6:9], c[9:12]])
    if len(quads) != len(QUAD_MATERIALS):
        raise ValueError("cornell.rs: found %d quads, expected %d" % (len(quads), len(QUAD_MATERIALS)))
    return spectra, quads, _const(src, "LIGHT_SCALE")


def _obj(path, quads):
    """Two triangles per quad, (0,1,2) and (0,2,3) as prism splits them."""
    with open(path, "w") as f:
        for q in quads:
            for p in q:
                f.write("v %r %r %r\n" % tuple(p))
        for i in range(len(quads)):
            b = 4 * i + 1
            f.write("f %d %d %d\nf %d %d %d\n" % (b, b + 1, b + 2, b, b + 2, b + 3))


def _spectrum(lam, val, scale=1.0):
    return {
        "type": "irregular",
        "wavelengths": ", ".join("%g" % x for x in lam),
        "values": ", ".join("%r" % (x * scale) for x in val),
    }


def scene_dict(mi, repo, workdir, size, spp, max_depth, sampler="independent"):
    """The Mitsuba scene. `max_depth` is pbrt's/prism's (scattering events): Mitsuba counts path
    segments, so its max_depth is one more. Russian roulette starts where prism's does (after 3
    scattering events); Mitsuba's survival probability min(max β·η², 0.95) differs slightly from
    prism's min(max β, 1), which changes noise, not the expected image."""
    spectra, quads, light_scale = read_cornell(repo)
    os.makedirs(workdir, exist_ok=True)
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth + 1, "rr_depth": 3, "hide_emitters": False},
        "sensor": {
            "type": "perspective",
            "fov": 2.0 * math.degrees(math.atan(12.5 / 35.0)),
            "fov_axis": "x",
            "near_clip": 1.0,
            "far_clip": 1e5,
            # Mitsuba's camera maps +x to the left of the image, which already puts the red wall
            # (x ≈ 550 mm) on the left, as prism's mirrored pbrt-style camera does.
            "to_world": mi.ScalarTransform4f().look_at(origin=[278, 273, -800], target=[278, 273, 0], up=[0, 1, 0]),
            "sampler": {"type": sampler, "sample_count": spp},
            "film": {
                "type": "hdrfilm",
                "width": size[0],
                "height": size[1],
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
                "component_format": "float32",
            },
        },
    }
    for name in ["white", "green", "red", "light"]:
        mine = [q for q, m in zip(quads, QUAD_MATERIALS) if m == name]
        path = os.path.join(workdir, "cornell_%s.obj" % name)
        _obj(path, mine)
        shape = {"type": "obj", "filename": path, "face_normals": True}
        if name == "light":
            # One-sided emitter facing down, black surface, as in prism.
            shape["bsdf"] = {"type": "diffuse", "reflectance": {"type": "uniform", "value": 0.0}}
            shape["emitter"] = {"type": "area", "radiance": _spectrum(*spectra["light"], scale=light_scale)}
        else:
            # prism's Lambertian reflects on both sides (it flips the shading frame to wo's side);
            # every surface here is seen from its front anyway.
            shape["bsdf"] = {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": _spectrum(*spectra[name])}}
        d["shape_" + name] = shape
    return d
