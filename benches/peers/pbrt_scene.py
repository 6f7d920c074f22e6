"""A pbrt-v4 scene file, as prism reads it, turned into a Mitsuba 3 scene dictionary.

Only the small subset the peer scenes use is understood, and anything else is an error, so
the two renderers can never silently see different scenes:
  - before WorldBegin: `LookAt` (after `Scale -1 1 1` or alone), a perspective `Camera` with `fov`, and
    Film/PixelFilter/Sampler/Integrator lines (the driver sets resolution, filter, sampler and
    depth itself);
  - in the world: AttributeBegin/AttributeEnd, Translate, uniform Scale, `Texture` (spectrum
    checkerboard or imagemap), `Material` (diffuse, conductor, dielectric), `AreaLightSource
    "diffuse"`, and `Shape` trianglemesh or plymesh.

How each definition maps (pbrt-v4 / prism → Mitsuba 3):
  - Spectra given as samples become `irregular` spectra; `rgb` reflectances stay RGB, which
    both renderers lift to spectra by Jakob–Hanika sigmoid fits (prism fits each value, Mitsuba
    looks up its precomputed table: the fits differ slightly).
  - Area lights: prism, like pbrt-v4, scales a light's spectrum to unit luminance
    Y = ∫ S ȳ dλ / ∫ ȳ dλ before `scale`; the Mitsuba spectrum gets the same factor,
    computed here with Mitsuba's own CIE 1931 ȳ over 360–830 nm.
  - Conductors and dielectrics take their roughness as α directly (`remaproughness` false is
    required); α > 0 becomes Mitsuba's `roughconductor`/`roughdielectric` (GGX, visible-normal
    sampling). prism uses the height-correlated Smith G = 1/(1 + Λ(ωo) + Λ(ωi)) (Heitz 2014,
    eq. 99), Mitsuba the separable G1(ωo)·G1(ωi): the same D and Fresnel, slightly less energy
    in Mitsuba at grazing angles.
  - Lambertian and conductor surfaces reflect on both sides in prism: `twosided` in Mitsuba.
  - Meshes without normals are flat-shaded in prism; Mitsuba would compute smooth vertex normals
    for them, so they get `face_normals`.
  - Image textures: prism's v points up (pbrt), Mitsuba's bitmap has row 0 at v = 0, so its
    `to_uv` flips v. Both filter bilinearly with repeat wrapping and decode 8-bit sRGB.
  - Checkerboards: prism's tex1 is on squares where ⌊u·uscale⌋ + ⌊v·vscale⌋ is even. Mitsuba's
    checkerboard has four squares per unit of its uv; `to_uv` halves the scale, and which of
    color0/color1 takes tex1 is found by evaluating the Mitsuba texture (`_checker_parity`).
"""

import math
import os
import re

import numpy as np

_TOKEN = re.compile(r'"[^"]*"|\[|\]|[^\s\[\]"]+')


class PbrtError(ValueError):
    pass


def tokenize(text):
    out = []
    for line in text.splitlines():
        line = line.split("#", 1)[0]
        out += _TOKEN.findall(line)
    return out


def _parse_params(tokens, i):
    """`"type name" value` or `"type name" [ values ]` pairs from tokens[i:]; returns (dict, i)."""
    params = {}
    while i < len(tokens) and tokens[i].startswith('"') and " " in tokens[i]:
        kind, name = tokens[i].strip('"').split()
        i += 1
        if tokens[i] == "[":
            j = tokens.index("]", i)
            raw = tokens[i + 1:j]
            i = j + 1
        else:
            raw = [tokens[i]]
            i += 1
        values = [v.strip('"') if v.startswith('"') else v for v in raw]
        if kind in ("float", "point3", "point2", "normal", "rgb", "blackbody", "integer", "point", "normal3"):
            values = [float(v) for v in values]
        elif kind == "spectrum" and not raw[0].startswith('"'):
            values = [float(v) for v in values]
        elif kind == "bool":
            values = [v in ("true", True) for v in values]
        params[name] = (kind, values)
    return params, i


def _args(tokens, i, n):
    return [float(t) for t in tokens[i:i + n]], i + n


def parse(path):
    """The scene file as a list of statements: (directive, positional args, params, ctm, block)."""
    text = open(path).read()
    tokens = tokenize(text)
    base = os.path.dirname(os.path.abspath(path))
    header, world = [], []
    ctm_stack, ctm = [], np.eye(4)
    block_stack, block = [], {}
    in_world = False
    i = 0
    while i < len(tokens):
        d = tokens[i]
        i += 1
        if d == "WorldBegin":
            in_world, ctm = True, np.eye(4)
        elif d == "AttributeBegin":
            ctm_stack.append(ctm.copy())
            block_stack.append(dict(block))
        elif d == "AttributeEnd":
            if not ctm_stack:
                raise PbrtError("%s: AttributeEnd without AttributeBegin" % path)
            ctm, block = ctm_stack.pop(), block_stack.pop()
        elif d == "Translate":
            (x, y, z), i = _args(tokens, i, 3)
            t = np.eye(4)
            t[:3, 3] = [x, y, z]
            ctm = ctm @ t
        elif d == "Scale":
            (x, y, z), i = _args(tokens, i, 3)
            if in_world and not (x == y == z):
                raise PbrtError("%s: only uniform Scale is supported in the world" % path)
            if not in_world:
                header.append(("Scale", [x, y, z], {}))
            ctm = ctm @ np.diag([x, y, z, 1.0])
        elif d == "LookAt":
            a, i = _args(tokens, i, 9)
            header.append(("LookAt", a, {}))
        elif d in ("Camera", "Film", "PixelFilter", "Sampler", "Integrator", "Material", "AreaLightSource", "Shape"):
            kind = tokens[i].strip('"')
            params, i = _parse_params(tokens, i + 1)
            if not in_world:
                header.append((d, [kind], params))
            elif d == "Material":
                block["material"] = (kind, params)
            elif d == "AreaLightSource":
                block["light"] = (kind, params)
            else:
                world.append(("Shape", [kind], params, ctm.copy(), dict(block)))
        elif d == "Texture":
            name, cls, kind = (t.strip('"') for t in tokens[i:i + 3])
            params, i = _parse_params(tokens, i + 3)
            world.append(("Texture", [name, cls, kind], params))
        else:
            raise PbrtError("%s: directive %s is not in the subset the peer scenes use" % (path, d))
    return base, header, world


def _ply_has_normals(path):
    with open(path, "rb") as f:
        head = f.read(4096).split(b"end_header")[0].decode("ascii", "replace")
    return "property float nx" in head


def _write_ply(path, p, idx, uv=None, n=None):
    """An ASCII PLY of an inline trianglemesh (for Mitsuba, which does not read pbrt's)."""
    p = np.asarray(p).reshape(-1, 3)
    idx = np.asarray(idx, dtype=int).reshape(-1, 3)
    cols = [p]
    head = ["ply", "format ascii 1.0", "element vertex %d" % len(p)] + ["property float %s" % c for c in "xyz"]
    if n is not None:
        cols.append(np.asarray(n).reshape(-1, 3))
        head += ["property float nx", "property float ny", "property float nz"]
    if uv is not None:
        cols.append(np.asarray(uv).reshape(-1, 2))
        head += ["property float u", "property float v"]
    head += ["element face %d" % len(idx), "property list uchar int vertex_indices", "end_header"]
    with open(path, "w") as f:
        f.write("\n".join(head) + "\n")
        for row in np.hstack(cols):
            f.write(" ".join("%r" % float(v) for v in row) + "\n")
        for t in idx:
            f.write("3 %d %d %d\n" % tuple(t))


def _luminance(mi, spectrum):
    """Y = ∫ S ȳ dλ / ∫ ȳ dλ over 360–830 nm (1 nm steps) of a Mitsuba spectrum dict, with
    Mitsuba's own CIE 1931 ȳ."""
    import drjit as dr
    tex = mi.load_dict(spectrum)
    lam = np.arange(360.0, 831.0)
    if mi.variant().startswith("scalar"):
        s, y = [], []
        for l0 in lam:
            si = mi.SurfaceInteraction3f()
            si.wavelengths = mi.UnpolarizedSpectrum(float(l0))
            s.append(float(tex.eval(si)[0]))
            y.append(float(mi.cie1931_y(float(l0))))
    else:
        si = dr.zeros(mi.SurfaceInteraction3f, len(lam))
        si.wavelengths = mi.UnpolarizedSpectrum(mi.Float(lam))
        s = np.array(tex.eval(si)[0])
        y = np.array(mi.cie1931_y(mi.Float(lam)))
    return float(np.sum(np.asarray(s) * np.asarray(y)) / np.sum(y))


def _scaled(spec, factor):
    """`spec` times `factor`: sampled values are multiplied, other plugins take `scale`."""
    if spec["type"] == "irregular":
        vals = [float(v) * factor for v in spec["values"].split(",")]
        return dict(spec, values=", ".join("%r" % v for v in vals))
    if spec["type"] == "uniform":
        return dict(spec, value=spec["value"] * factor)
    return dict(spec, scale=factor)


def _spectrum(mi, kind, values):
    if kind == "rgb":
        return {"type": "rgb", "value": values}
    if kind == "blackbody":
        # Planck's law sampled every nanometre (Mitsuba's blackbody plugin takes no scale); its
        # units do not matter, the light's luminance normalisation divides them out.
        lam = np.arange(360.0, 831.0)
        c2 = 1.4387769e7  # h c / k_B [nm K]
        b = lam ** -5.0 / np.expm1(c2 / (lam * values[0]))
        b /= b.max()
        return {"type": "irregular", "wavelengths": ", ".join("%g" % x for x in lam),
                "values": ", ".join("%r" % float(x) for x in b)}
    if kind == "spectrum" and isinstance(values[0], str):
        if values[0] == "stdillum-D65":
            return {"type": "d65"}
        raise PbrtError("named spectrum %s has no Mitsuba counterpart here" % values[0])
    if kind in ("spectrum", "float"):
        if len(values) == 1:
            return {"type": "uniform", "value": values[0]}
        lam, val = values[0::2], values[1::2]
        if min(val) == max(val) and lam[0] <= 360.0 and lam[-1] >= 830.0:
            return {"type": "uniform", "value": val[0]}
        return {"type": "irregular", "wavelengths": ", ".join("%r" % x for x in lam),
                "values": ", ".join("%r" % x for x in val)}
    raise PbrtError("parameter of type %s is not a spectrum" % kind)


def _checker_parity(mi):
    """True when Mitsuba's checkerboard gives color0 on the square at uv ∈ [0, ½)², the square
    prism gives tex1 (⌊u s⌋ + ⌊v s⌋ = 0, even)."""
    t = mi.load_dict({"type": "checkerboard", "color0": {"type": "uniform", "value": 1.0},
                      "color1": {"type": "uniform", "value": 0.0}})
    si = mi.SurfaceInteraction3f()
    si.uv = mi.Point2f(0.25, 0.25)
    si.wavelengths = mi.UnpolarizedSpectrum(550.0)
    return float(np.array(t.eval(si)).ravel()[0]) > 0.5


def _texture(mi, base, kind, p):
    if kind == "checkerboard":
        su, sv = p.get("uscale", ("float", [1.0]))[1][0], p.get("vscale", ("float", [1.0]))[1][0]
        even, odd = (_spectrum(mi, *p[k]) for k in ("tex1", "tex2"))
        c0, c1 = (even, odd) if _checker_parity(mi) else (odd, even)
        return {"type": "checkerboard", "color0": c0, "color1": c1,
                "to_uv": mi.ScalarTransform4f().scale([su / 2.0, sv / 2.0, 1.0])}
    if kind == "imagemap":
        extra = set(p) - {"filename"}
        if extra:
            raise PbrtError("imagemap parameters %s are not supported here" % sorted(extra))
        flip = mi.ScalarTransform4f().translate([0.0, 1.0, 0.0]) @ mi.ScalarTransform4f().scale([1.0, -1.0, 1.0])
        return {"type": "bitmap", "filename": os.path.join(base, p["filename"][1][0]), "filter_type": "bilinear",
                "wrap_mode": "repeat", "raw": False, "to_uv": flip}
    raise PbrtError("texture %s is not supported here" % kind)


def _alpha(p, name):
    if p.get("remaproughness", ("bool", [True]))[1][0]:
        if p.get("roughness", ("float", [0.0]))[1][0] != 0.0:
            raise PbrtError("%s: give roughness as α with \"bool remaproughness\" false" % name)
    return p.get("roughness", ("float", [0.0]))[1][0]


def _bsdf(mi, kind, p, textures):
    def refl(name):
        k, v = p[name]
        return textures[v[0]] if k == "texture" else _spectrum(mi, k, v)
    if kind == "diffuse":
        return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": refl("reflectance")}}
    if kind == "conductor":
        a = _alpha(p, kind)
        b = {"type": "roughconductor" if a > 0 else "conductor", "eta": refl("eta"), "k": refl("k")}
        if a > 0:
            b.update({"distribution": "ggx", "alpha": a, "sample_visible": True})
        return {"type": "twosided", "bsdf": b}
    if kind == "dielectric":
        kind_eta, eta = p.get("eta", ("float", [1.5]))
        if kind_eta != "float":
            raise PbrtError("dielectric: only a constant \"float eta\" is supported here")
        a = _alpha(p, kind)
        b = {"type": "roughdielectric" if a > 0 else "dielectric", "int_ior": eta[0], "ext_ior": 1.0}
        if a > 0:
            b.update({"distribution": "ggx", "alpha": a, "sample_visible": True})
        return b
    raise PbrtError("material %s is not supported here" % kind)


def camera(mi, header, size, spp, sampler):
    look = [h for h in header if h[0] == "LookAt"]
    cam = [h for h in header if h[0] == "Camera"]
    if not look or not cam or cam[0][1][0] != "perspective":
        raise PbrtError("the scene needs LookAt and a perspective Camera")
    scales = [h for h in header if h[0] == "Scale"]
    if scales not in ([], [("Scale", [-1.0, 1.0, 1.0], {})]):
        raise PbrtError("the only camera transform supported besides LookAt is Scale -1 1 1")
    e = look[0][1]
    to_world = mi.ScalarTransform4f().look_at(origin=e[0:3], target=e[3:6], up=e[6:9])
    if not scales:
        # Mitsuba's look-at puts camera +x on the image's left, as pbrt's does after Scale -1 1 1;
        # pbrt's plain LookAt is its mirror image.
        to_world = to_world @ mi.ScalarTransform4f().scale([-1.0, 1.0, 1.0])
    fov = cam[0][2]["fov"][1][0]
    return {
        "type": "perspective", "fov": fov, "fov_axis": "smaller", "near_clip": 1e-3, "far_clip": 1e6,
        "to_world": to_world,
        "sampler": {"type": sampler, "sample_count": spp},
        "film": {"type": "hdrfilm", "width": size[0], "height": size[1], "rfilter": {"type": "box"},
                 "pixel_format": "rgb", "component_format": "float32"},
    }


def scene_dict(mi, path, workdir, size, spp, max_depth, sampler="independent"):
    """The Mitsuba scene for the pbrt file `path`; `max_depth` counts scattering events as prism
    and pbrt do (Mitsuba counts path segments: one more)."""
    base, header, world = parse(path)
    os.makedirs(workdir, exist_ok=True)
    d = {"type": "scene",
         "integrator": {"type": "path", "max_depth": max_depth + 1, "rr_depth": 3, "hide_emitters": False},
         "sensor": camera(mi, header, size, spp, sampler)}
    textures = {}
    n = 0
    for st in world:
        if st[0] == "Texture":
            (name, cls, kind), p = st[1], st[2]
            if cls != "spectrum":
                raise PbrtError("texture %s: only spectrum textures are supported here" % name)
            textures[name] = _texture(mi, base, kind, p)
            continue
        _, (kind,), p, ctm, block = st
        if kind == "plymesh":
            ply = os.path.join(base, p["filename"][1][0])
            shape = {"type": "ply", "filename": ply, "face_normals": not _ply_has_normals(ply)}
        elif kind == "trianglemesh":
            ply = os.path.join(workdir, "mesh%d.ply" % n)
            _write_ply(ply, p["P"][1], p["indices"][1], p.get("uv", (None, None))[1], p.get("N", (None, None))[1])
            shape = {"type": "ply", "filename": ply, "face_normals": "N" not in p}
        else:
            raise PbrtError("shape %s is not supported here" % kind)
        if not np.allclose(ctm, np.eye(4)):
            shape["to_world"] = mi.ScalarTransform4f(ctm.tolist())
        mat = block.get("material", ("diffuse", {"reflectance": ("float", [0.5])}))
        shape["bsdf"] = _bsdf(mi, mat[0], mat[1], textures)
        if "light" in block:
            lk, lp = block["light"]
            if lk != "diffuse" or lp.get("twosided", ("bool", [False]))[1][0]:
                raise PbrtError("only one-sided diffuse area lights are supported here")
            spec = _spectrum(mi, *lp.get("L", ("rgb", [1.0, 1.0, 1.0])))
            if spec["type"] == "rgb":
                raise PbrtError("give area lights a spectrum, not RGB")
            scale = lp.get("scale", ("float", [1.0]))[1][0] / _luminance(mi, spec)
            shape["emitter"] = {"type": "area", "radiance": _scaled(spec, scale)}
        d["shape%d" % n] = shape
        n += 1
    return d
