"""Where an image's error sits: RMSE against a reference, split into the pixels inside the
Cornell box's light, a 2-pixel band along its edge, and the rest of the image.

Usage (with the venv of mitsuba.sh, which has mitsuba and numpy):
  target/peers/venv/bin/python benches/peers/error_regions.py REF.exr IMG.exr [IMG.exr ...]

The light is where the reference's mean linear sRGB exceeds 1 (the walls stay below 0.5); its
interior is the light shrunk by one pixel, its edge band the light grown by two pixels minus
the interior. Each region's figure is √(Σ its squared errors / all pixels), so the three add
in quadrature to the RMSE. Inside the light the error is colour noise (wavelength sampling);
along the edge, the estimate of how much of the pixel the light covers; elsewhere mostly the
noise of indirect light.
"""

import sys

import numpy as np


def load(path):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    bmp = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    return np.array(bmp)


def grow(mask, r):
    out = mask.copy()
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            out |= np.roll(np.roll(mask, dy, 0), dx, 1)
    return out


def shrink(mask, r):
    return ~grow(~mask, r)


def regions(ref):
    light = ref.mean(axis=2) > 1.0
    interior = shrink(light, 1)
    band = grow(light, 2)
    return {"light": interior, "edge": band & ~interior, "rest": ~band}


def split(ref, img, masks):
    se = ((img - ref) ** 2).mean(axis=2)
    out = {"rmse": float(np.sqrt(se.mean()))}
    for k, m in masks.items():
        out[k] = float(np.sqrt(se[m].sum() / se.size))
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    ref = load(sys.argv[1])
    masks = regions(ref)
    print("pixels: " + ", ".join("%s %d" % (k, m.sum()) for k, m in masks.items()))
    print("| image | RMSE | light | edge | rest |\n|---|---|---|---|---|")
    for path in sys.argv[2:]:
        s = split(ref, load(path), masks)
        print("| %s | %.4f | %.4f | %.4f | %.4f |" % (path.split("/")[-1], s["rmse"], s["light"], s["edge"], s["rest"]))


if __name__ == "__main__":
    main()
