#!/usr/bin/python3
"""Checks for the report tests (tests/app/report_test.cpp).

  report_checks.py pngs DIR     every PNG index.html references exists, decodes and is not blank
  report_checks.py strings FILE every string attribute and string dataset reads as str in h5py
  report_checks.py motion FILE DIR  /motion of a trajectory file is a rigid tree that moves as its poses say
                                (each joint = CoM + A c, segment lengths constant, the root's joint on the
                                base point), and DIR/index.html's 3-D view carries those poses, a bounding box
                                that holds every shape at every frame (touched on each side) and a grid step
  report_checks.py xdmf FILE.xmf FILE.h5  the XDMF file read back with meshio's TimeSeriesReader: its steps'
                                times, the poly-lines and every step's points (the geometry and the "position"
                                vector) are the HDF5 file's /time, /motion/segments and /motion/points; no
                                hyperslab (ParaView's Xdmf3 readers and meshio read none)
  pvbatch report_checks.py paraview FILE.xmf FILE.h5  the same in ParaView's three XDMF readers (XDMFReader,
                                Xdmf3ReaderT, Xdmf3ReaderS), each in its own pvbatch, stderr kept
  report_checks.py view DIR     the 3-D view in headless Chromium, offline: no console error, the canvas
                                drawn at two frames and different between them, the bounds inside the
                                picture, and one second of playing at 4x and 1x reaching the time it should
Prints 'ok ...' and exits 0, or prints what is wrong and exits 1.
"""
import os
import re
import sys

import h5py
import numpy as np


def verdict(bad, ok):
    """Each problem on a line of its own, else the `ok` line; the exit code."""
    for b in bad:
        print(b)
    if not bad:
        print(ok)
    return 1 if bad else 0


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
    return verdict(bad, f"ok {len(names)} figures")


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
    return verdict(bad, "ok strings")


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
            bad += bounds_problems(data, m, q[rows], c)
    return verdict(bad, f"ok motion of {n} bodies at {pose.shape[0]} times")


def surface_points(shape, d):
    """Points on a shape's surface in its body frame (CoM at 0) whose box is the shape's: a box's corners,
    a sphere's six poles, a cylinder's rims (its box is reached at a rim point, sampled finely)."""
    d = np.asarray(d, dtype=float)
    if shape == "box":
        return np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * d / 2
    if shape == "sphere":
        return np.vstack([np.eye(3), -np.eye(3)]) * d[0]
    if shape == "cylinder":
        a = np.linspace(0, 2 * np.pi, 720, endpoint=False)
        rim = np.column_stack([d[0] * np.cos(a), d[0] * np.sin(a), np.zeros_like(a)])
        return np.vstack([rim + [0, 0, d[2] / 2], rim - [0, 0, d[2] / 2]])
    return np.zeros((1, 3))


def bounds_problems(data, m, q, c):
    """The view's bounds hold every shape's surface, CoM and joint at every frame it draws, and each of its
    six faces is touched (within 0.5 % of the size): it frames the whole motion and not much more."""
    if "bounds" not in data or "grid" not in data:
        return ["the view's JSON has no bounds or grid"]
    low, high = (np.array(b) for b in data["bounds"])
    shapes, dimensions = [str(s) for s in m.attrs["shapes"]], m["dimensions"][:]
    points = [q[:, :, :3].reshape(-1, 3), (q[:, :, :3] + rotate(q[:, :, 3:], np.broadcast_to(c, q[:, :, :3].shape))
                                           ).reshape(-1, 3)]
    for b, (shape, d) in enumerate(zip(shapes, dimensions)):
        surface = surface_points(shape, d)
        turned = rotate(q[:, b, None, 3:], np.broadcast_to(surface, (q.shape[0],) + surface.shape))
        points.append((turned + q[:, b, None, :3]).reshape(-1, 3))
    points = np.vstack(points)
    size = np.linalg.norm(high - low)
    bad = []
    if (points < low - 1e-6).any() or (points > high + 1e-6).any():
        worst = max((low - points).max(), (points - high).max())
        bad.append(f"a shape reaches {worst:.3g} m outside the view's bounds {data['bounds']}")
    loose = np.concatenate([points.min(axis=0) - low, high - points.max(axis=0)])
    if (loose > 5e-3 * size).any():
        bad.append(f"the view's bounds {data['bounds']} are {loose.max():.3g} m wider than the shapes")
    step = data["grid"]["step"]
    if not (size / 30 <= step <= size / 2) or not data["grid"]["label"].endswith("m"):
        bad.append(f"grid step {step} m ({data['grid']['label']!r}) for a motion {size:.3g} m across")
    return bad


def chromium():
    import shutil
    return shutil.which("chromium") or shutil.which("chromium-browser")


def probe(directory, frame, speed=None):
    """Headless Chromium, no network: the page's data-probe at this frame (and playback speed), and the
    console's errors."""
    import subprocess
    url = "file://" + os.path.abspath(os.path.join(directory, "index.html")) + f"#frame={frame}&probe"
    url += f"&speed={speed:g}" if speed else ""
    run = subprocess.run([chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
                          "--enable-unsafe-swiftshader", "--enable-logging=stderr", "--v=0",
                          "--host-resolver-rules=MAP * ~NOTFOUND", "--dump-dom", url],
                         capture_output=True, text=True, timeout=300)
    errors = [line for line in run.stderr.splitlines() if ":CONSOLE" in line and "GL Driver Message" not in line
              and ("ERROR" in line or "Uncaught" in line or "rror" in line)]
    found = re.search(r'data-probe="frame=(\d+) drawn=(\d+) of (\d+) hash=(\d+) framed=(\d) speed=([0-9.]+) '
                      r'after_1s=([-0-9.e]+)"', run.stdout)
    return (None if not found else tuple(float(x) for x in found.groups())), errors


def played_for_a_second(times, frame, speed):
    """view3d.js's advance(1): the frame time reached; past the last frame it starts again at the first."""
    t = times[frame] + speed
    return times[0] if t > times[-1] else times[np.flatnonzero(np.asarray(times) <= t)[-1]]


def view(directory):
    data, page = view_payload(directory)
    bad = []
    if data is None:
        bad.append("index.html has no 3-D view")
    if re.search(r'(src|href)="(https?:)?//', page):
        bad.append("the page loads something from the network")
    speeds = re.findall(r'<option value="([0-9.]+)"', page)
    if speeds != ["0.25", "0.5", "1", "2", "4"]:
        bad.append(f"playback speeds {speeds}")
    if not bad:
        frames = len(data["times"])
        seen = []
        for frame, speed in ((0, 4), (frames // 2, None)):
            found, errors = probe(directory, frame, speed)
            bad += [f"frame {frame}: console: {e}" for e in errors]
            if found is None:
                bad.append(f"frame {frame}: the view did not draw (no data-probe)")
                continue
            if found[4] != 1:
                bad.append(f"frame {frame}: a corner of the motion's bounds is outside the picture")
            expected = played_for_a_second(data["times"], frame, speed or 1)
            if found[5] != (speed or 1) or abs(found[6] - expected) > 1e-9:
                bad.append(f"frame {frame}: a second at {found[5]:g}x reaches t = {found[6]:g}, not {expected:g}")
            if found[1] < 0.002 * found[2]:
                bad.append(f"frame {frame}: the canvas is blank ({found[1]:.0f} of {found[2]:.0f} pixels drawn)")
            else:
                seen.append(found)
        if len(seen) == 2 and seen[0][3] == seen[1][3]:
            bad.append("the canvas is the same at two frames")
    if bad:
        return verdict(bad, "")
    return verdict(bad, "ok view: " + "; ".join(f"frame {s[0]:.0f} drew {s[1]:.0f} of {s[2]:.0f} pixels, a second "
                                                f"at {s[5]:g}x reaches t = {s[6]:g} s" for s in seen))


def xdmf(xmf, path):
    """meshio's TimeSeriesReader takes the mesh (points, poly-lines) from the first step and the time and node
    vectors from every step; its XdmfReader reads each step's geometry item (what ParaView draws)."""
    import xml.etree.ElementTree as ET
    from meshio.xdmf import TimeSeriesReader
    from meshio.xdmf.main import XdmfReader
    text = open(xmf, encoding="utf-8").read()
    bad = ["a hyperslab, which meshio and ParaView's Xdmf3 readers do not read"] if "HyperSlab" in text else []
    with h5py.File(path, "r") as f:
        t, points, segments = f["time"][:], f["motion/points"][:], f["motion/segments"][:]
    try:
        reader = TimeSeriesReader(xmf)
        first, cells = reader.read_points_cells()
    except Exception as e:  # noqa: BLE001 (meshio raises KeyError, ReadError, ...: any is the answer)
        print(f"meshio's TimeSeriesReader cannot read it: {type(e).__name__} {e}")
        return 1
    with reader:
        if not np.array_equal(first, points[0]) or [c.type for c in cells] != ["line"] or \
                not np.array_equal(cells[0].data, segments):
            bad.append("the first step's points or poly-lines are not /motion/points[0] and /motion/segments")
        if reader.num_steps != t.size:
            bad.append(f"{reader.num_steps} steps for {t.size} times")
        for k in range(min(reader.num_steps, t.size)):
            tk, point_data, _ = reader.read_data(k)
            if tk != t[k] or not np.array_equal(point_data.get("position"), points[k]):
                bad.append(f"step {k}: time {tk!r} or its position vectors are not /time and /motion/points[{k}]")
            if len(bad) > 5:
                break
    geometry = XdmfReader(xmf)
    for k, grid in enumerate(ET.fromstring(text).find("Domain/Grid").findall("Grid")[:t.size]):
        if not np.array_equal(geometry._read_data_item(grid.find("Geometry/DataItem")), points[k]):
            bad.append(f"step {k}: the geometry is not /motion/points[{k}]")
            break
    return verdict(bad, f"ok xdmf: {t.size} steps of {points.shape[1]} points and {segments.shape[0]} poly-lines")


def paraview_reader(xmf, path, name):
    """In pvbatch: every time step's points and poly-lines as one ParaView XDMF reader gives them."""
    from paraview import simple
    from paraview.vtk.util.numpy_support import vtk_to_numpy
    reader = getattr(simple, name)(**({"FileNames": [xmf]} if name == "XDMFReader" else {"FileName": [xmf]}))
    times = np.array(reader.TimestepValues)
    with h5py.File(path, "r") as f:
        t, points, segments = f["time"][:], f["motion/points"][:], f["motion/segments"][:]
    bad = [] if np.array_equal(times, t) else [f"{name}: {times.size} time steps, not /time's {t.size}"]
    for k, tk in enumerate(times[:t.size]):
        reader.UpdatePipeline(tk)  # not simple.UpdatePipeline(time=tk), which drops a time of 0
        d = reader.GetClientSideObject().GetOutputDataObject(0)
        while d.IsA("vtkMultiBlockDataSet"):
            d = d.GetBlock(0)
        xyz = vtk_to_numpy(d.GetPoints().GetData()) if d.GetNumberOfPoints() else np.zeros((0, 3))
        lines = vtk_to_numpy(d.GetCells().GetConnectivityArray()).reshape(-1, 2) if d.GetNumberOfCells() else None
        if not np.array_equal(xyz, points[k]) or not np.array_equal(lines, segments):
            bad.append(f"{name}: t = {tk:g}: {d.GetNumberOfPoints()} points, {d.GetNumberOfCells()} lines, not "
                       "/motion's")
            break
    return verdict(bad, f"ok {name}: {times.size} time steps of {points.shape[1]} points and {segments.shape[0]} lines")


def paraview(xmf, path):
    """Each reader in a pvbatch of its own (one that aborts does not hide the others); any stderr is an error."""
    import subprocess
    bad, said = 0, []
    for name in ("XDMFReader", "Xdmf3ReaderT", "Xdmf3ReaderS"):
        run = subprocess.run(["pvbatch", os.path.abspath(__file__), "paraview-reader", os.path.abspath(xmf),
                              os.path.abspath(path), name], capture_output=True, text=True, timeout=600)
        errors = [line for line in run.stderr.splitlines() if line.strip()]
        said.append(run.stdout.strip())
        if run.returncode != 0 or errors or not run.stdout.startswith("ok"):
            bad += 1
            print(f"{name}: exit {run.returncode}: {run.stdout.strip()} {' | '.join(errors[:3])}")
    if not bad:
        print("ok paraview: " + "; ".join(said))
    return 1 if bad else 0


if __name__ == "__main__":
    what, target = sys.argv[1], sys.argv[2]
    if what == "xdmf":
        sys.exit(xdmf(target, sys.argv[3]))
    if what == "paraview":
        sys.exit(paraview(target, sys.argv[3]))
    if what == "paraview-reader":
        sys.exit(paraview_reader(target, sys.argv[3], sys.argv[4]))
    if what == "motion":
        sys.exit(motion(target, sys.argv[3]))
    sys.exit({"pngs": pngs, "strings": strings, "view": view}[what](target))
