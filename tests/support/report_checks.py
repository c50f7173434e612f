#!/usr/bin/python3
"""Checks for the report tests (tests/app/report_test.cpp).

  report_checks.py pngs DIR     every PNG index.html references exists, decodes and is not blank
  report_checks.py strings FILE every string attribute and string dataset reads as str in h5py
  report_checks.py motion FILE DIR  /motion of a trajectory file is a rigid tree that moves as its poses say
                                (each joint = CoM + A c, segment lengths constant, the root's joint on the
                                base point), and DIR/index.html's 3-D view carries those poses
  report_checks.py xdmf FILE.xmf FILE.h5  the XDMF file read back with meshio: its times, the poly-lines
                                connectivity and every step's points are the HDF5 file's /time, /motion/segments
                                and /motion/points
  report_checks.py view DIR     the 3-D view in headless Chromium, offline: no console error, the canvas
                                drawn at two frames and different between them
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


def rotate(q, v):
    """Unit quaternions q (..., 4: q0 scalar) applied to vectors v (..., 3)."""
    w, u = q[..., :1], q[..., 1:]
    t = 2 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def view_payload(directory):
    import json
    with open(os.path.join(directory, "index.html"), encoding="utf-8") as f:
        page = f.read()
    found = re.search(r'<script id="treedyn-motion" type="application/json">(.*?)</script>', page, re.S)
    def refuse(constant):  # JSON has no NaN or Infinity: JSON.parse would throw
        raise ValueError(f"{constant} in the view's JSON")
    return json.loads(found.group(1), parse_constant=refuse) if found else None, page


def motion(path, directory):
    bad = []
    with h5py.File(path, "r") as f:
        m = f["motion"]
        pose, points, segments = m["pose"][:], m["points"][:], m["segments"][:]
        c = m["com_to_joint"][:]
        n = c.shape[0]
        q = pose.reshape(pose.shape[0], n, 7)
        joints = q[:, :, :3] + rotate(q[:, :, 3:], np.broadcast_to(c, q[:, :, :3].shape))
        if not np.allclose(points[:, 0::2], joints, atol=1e-9):
            bad.append("a joint point is not CoM + A c")
        if not np.array_equal(points[:, 1::2], q[:, :, :3]):
            bad.append("a CoM point is not the pose's")
        lengths = np.linalg.norm(points[:, segments[:, 0]] - points[:, segments[:, 1]], axis=2)
        if not np.allclose(lengths, lengths[0], atol=1e-8):
            bad.append(f"a segment's length changes by {np.abs(lengths - lengths[0]).max():.3g} m")
        root = list(m.attrs["parents"]).index(-1)
        if "base" in f and not np.allclose(points[:, 2 * root], f["base"][:, :3], atol=1e-9):
            bad.append("the root's joint is not on the base point")
        data, _ = view_payload(directory)
        if data is None:
            bad.append("index.html has no 3-D view")
        else:
            rows = [int(np.argmin(np.abs(f["time"][:] - t))) for t in data["times"]]
            if not np.allclose(np.array(data["runs"][0]["pose"]), pose[rows], atol=1e-6):
                bad.append("the view's poses are not the file's")
    for b in bad:
        print(b)
    if not bad:
        print(f"ok motion of {n} bodies at {pose.shape[0]} times")
    return 1 if bad else 0


def chromium():
    import shutil
    return shutil.which("chromium") or shutil.which("chromium-browser")


def probe(directory, frame):
    """Headless Chromium, no network: the page's data-probe at this frame, and the console's errors."""
    import subprocess
    url = "file://" + os.path.abspath(os.path.join(directory, "index.html")) + f"#frame={frame}&probe"
    run = subprocess.run([chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
                          "--enable-unsafe-swiftshader", "--enable-logging=stderr", "--v=0",
                          "--host-resolver-rules=MAP * ~NOTFOUND", "--dump-dom", url],
                         capture_output=True, text=True, timeout=300)
    errors = [line for line in run.stderr.splitlines() if ":CONSOLE" in line and "GL Driver Message" not in line
              and ("ERROR" in line or "Uncaught" in line or "rror" in line)]
    found = re.search(r'data-probe="frame=(\d+) drawn=(\d+) of (\d+) hash=(\d+)"', run.stdout)
    return (None if not found else tuple(int(x) for x in found.groups())), errors


def view(directory):
    data, page = view_payload(directory)
    bad = []
    if data is None:
        bad.append("index.html has no 3-D view")
    if re.search(r'(src|href)="(https?:)?//', page):
        bad.append("the page loads something from the network")
    if not bad:
        frames = len(data["times"])
        seen = []
        for frame in (0, frames // 2):
            found, errors = probe(directory, frame)
            bad += [f"frame {frame}: console: {e}" for e in errors]
            if found is None:
                bad.append(f"frame {frame}: the view did not draw (no data-probe)")
            elif found[1] < 0.002 * found[2]:
                bad.append(f"frame {frame}: the canvas is blank ({found[1]} of {found[2]} pixels drawn)")
            else:
                seen.append(found)
        if len(seen) == 2 and seen[0][3] == seen[1][3]:
            bad.append("the canvas is the same at two frames")
    for b in bad:
        print(b)
    if not bad:
        print("ok view: " + "; ".join(f"frame {s[0]} drew {s[1]} of {s[2]} pixels" for s in seen))
    return 1 if bad else 0


def xdmf(xmf, path):
    """meshio reads the XML and every HDF5 or XML data item (meshio 7 has no HyperSlab item: the selection,
    start / stride / count per dimension as the XDMF model defines it, is applied here)."""
    import xml.etree.ElementTree as ET
    from meshio.xdmf.common import xdmf_to_meshio_type
    from meshio.xdmf.main import XdmfReader
    reader = XdmfReader(xmf)
    root = ET.parse(xmf).getroot()
    if root.get("Version") != "3.0":
        print(f"XDMF version {root.get('Version')}, not 3.0")
        return 1
    collection = root.find("Domain/Grid")
    steps = collection.findall("Grid")
    bad = []
    with h5py.File(path, "r") as f:
        t, points, segments = f["time"][:], f["motion/points"][:], f["motion/segments"][:]
        if collection.get("CollectionType") != "Temporal" or len(steps) != t.size:
            bad.append(f"{len(steps)} steps in a {collection.get('CollectionType')} collection for {t.size} times")
        for k, grid in enumerate(steps):
            topology, geometry = grid.find("Topology"), grid.find("Geometry")
            if float(grid.find("Time").get("Value")) != t[k]:
                bad.append(f"step {k}: time {grid.find('Time').get('Value')} is not {t[k]!r}")
            cells = reader._read_data_item(topology.find("DataItem"))
            if xdmf_to_meshio_type[topology.get("TopologyType")] != "line" or not np.array_equal(cells, segments):
                bad.append(f"step {k}: the poly-lines are not /motion/segments")
            slab = geometry.find("DataItem")
            selection, source = (reader._read_data_item(d) for d in slab.findall("DataItem"))
            start, stride, count = selection.astype(int)
            picked = source[tuple(slice(a, a + s * c, s) for a, s, c in zip(start, stride, count))]
            shape = [int(d) for d in slab.get("Dimensions").split()]
            if list(picked.shape) != shape or not np.array_equal(picked.reshape(-1, 3), points[k]):
                bad.append(f"step {k}: the points are not /motion/points[{k}]")
            if len(bad) > 5:
                break
    for b in bad:
        print(b)
    if not bad:
        print(f"ok xdmf: {len(steps)} steps of {points.shape[1]} points and {segments.shape[0]} poly-lines")
    return 1 if bad else 0


if __name__ == "__main__":
    what, target = sys.argv[1], sys.argv[2]
    if what == "xdmf":
        sys.exit(xdmf(target, sys.argv[3]))
    if what == "motion":
        sys.exit(motion(target, sys.argv[3]))
    sys.exit({"pngs": pngs, "strings": strings, "view": view}[what](target))
