#!/usr/bin/python3
"""Checks for the report tests (tests/app/report_test.cpp).

  report_checks.py pngs DIR     every PNG index.html references exists, decodes and is not blank
  report_checks.py strings FILE every string attribute and string dataset reads as str in h5py
Prints 'ok ...' and exits 0, or prints what is wrong and exits 1.
"""
import os
import re
import sys

import h5py
import numpy as np


def pngs(directory):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as image
    with open(os.path.join(directory, "index.html"), encoding="utf-8") as f:
        names = re.findall(r'<img src="([^"]+)"', f.read())
    bad = []
    for name in names:
        path = os.path.join(directory, name)
        if not os.path.exists(path):
            bad.append(f"{name}: missing")
            continue
        pixels = image.imread(path)
        if pixels.size == 0 or float(np.var(pixels[..., :3])) < 1e-4:
            bad.append(f"{name}: blank")
    if not names:
        bad.append("index.html references no figure")
    for b in bad:
        print(b)
    if not bad:
        print(f"ok {len(names)} figures")
    return 1 if bad else 0


def strings(path):
    bad = []

    def attributes(name, obj):
        for key, value in obj.attrs.items():
            values = value.tolist() if isinstance(value, np.ndarray) else [value]
            for v in values:
                if isinstance(v, bytes):
                    bad.append(f"{name or '/'} attribute {key}: bytes")
                    break
        string = isinstance(obj, h5py.Dataset) and h5py.check_string_dtype(obj.dtype)
        if string and string.length is not None:  # fixed length: h5py gives bytes
            bad.append(f"{name}: fixed-length strings")

    with h5py.File(path, "r") as f:
        attributes("", f)
        f.visititems(attributes)
    for b in bad:
        print(b)
    if not bad:
        print("ok strings")
    return 1 if bad else 0


if __name__ == "__main__":
    what, target = sys.argv[1], sys.argv[2]
    sys.exit(pngs(target) if what == "pngs" else strings(target))
