#!/usr/bin/env python3
"""Writes tests/data/images/float64.tif with OpenImageIO (PyPI: pip install OpenImageIO numpy),
so that prism's fallback to OpenImageIO is checked on a file the `image` crate cannot decode: a
16×8 RGB TIFF of 64-bit float samples, R = 0.25, G = 0.5, B = 2 for x < 8 and 0.125 beyond.
Run from the repository root only to regenerate it."""
import numpy as np
import OpenImageIO as oiio

w, h = 16, 8
pixels = np.empty((h, w, 3), np.float32)
pixels[:, :, 0] = 0.25
pixels[:, :, 1] = 0.5
pixels[:, :, 2] = np.where(np.arange(w) < 8, 2.0, 0.125)[None, :]
spec = oiio.ImageSpec(w, h, 3, oiio.DOUBLE)
path = "tests/data/images/float64.tif"
out = oiio.ImageOutput.create(path)
if out is None or not out.open(path, spec) or not out.write_image(pixels) or not out.close():
    raise SystemExit(f"writing {path}: {oiio.geterror()}")
