"""The 3-D view of the tree moving: one self-contained block of the page (Debian's three.js inlined, the
poses as JSON), so it works from file:// and from a copied folder with no network. Each body is drawn by
its shape (box, cylinder, sphere) and a stick from its inboard joint through its centre of mass to its
children's joints; the base point's path; a ground grid with labelled axes; play/pause, a playback speed
and a time slider; stored samples ghosted. The camera frames every shape at every frame drawn."""
import json
import math
import os

import numpy as np

from read import strings, text

THREE = "/usr/share/javascript/three/three.min.js"  # Debian's libjs-three
ORBIT = "/usr/share/javascript/three/examples/js/controls/OrbitControls.js"
MAX_FRAMES = 400
MAX_GHOSTS = 20
SPEEDS = (0.25, 0.5, 1, 2, 4)  # playback against real time
SPEED_OPTIONS = "".join(f'<option value="{v:g}"{" selected" if v == 1 else ""}>{v:g}x</option>' for v in SPEEDS)
VIEWER_JS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "view3d.js")


def scene_of(f):
    m = f["motion"]
    return {"bodies": strings(m.attrs["bodies"]), "parents": [int(p) for p in m.attrs["parents"]],
            "shapes": strings(m.attrs["shapes"]), "dimensions": m["dimensions"][:].tolist(),
            "com_to_joint": m["com_to_joint"][:].tolist()}


def frames(count):
    """At most MAX_FRAMES output-time rows, evenly spread, the last one kept."""
    if count <= MAX_FRAMES:
        return np.arange(count)
    return np.unique(np.linspace(0, count - 1, MAX_FRAMES).round().astype(int))


def poses_from(com, orientation, rows, bodies):
    """(frames, 7n) poses from com_position (T, 3n) and orientation (T, 4n) rows."""
    com, q = com[rows], orientation[rows]
    out = np.empty((len(rows), 7 * bodies))
    for b in range(bodies):
        out[:, 7 * b:7 * b + 3] = com[:, 3 * b:3 * b + 3]
        out[:, 7 * b + 3:7 * b + 7] = q[:, 4 * b:4 * b + 4]
    return out


def runs_of(f):
    """(times, [(label, ghost, poses)]) or (None, why): what the file lets the view draw."""
    if "motion" not in f:
        return None, "this file has no /motion (written by an older treedyn): run its job again"
    n = len(f["motion"].attrs["bodies"])
    if "motion/pose" in f:  # a trajectory file
        t = f["time"][:]
        rows = frames(t.size)
        pose = f["motion/pose"][:][rows]
        label = f"sample {int(f['sample'].attrs['index'])}" if "sample" in f else "this run"
        return (t[rows], [(label, False, pose)]), None
    if not all(q in f.get("nominal", {}) for q in ("com_position", "orientation")):
        return None, ("the 3-D view needs the poses: add \"com_position\" and \"orientation\" to [output] quantities "
                      "(with store_trajectories = M to see M samples ghosted), or draw one run with `treedyn run "
                      "JOB` or `treedyn-ensemble JOB --sample K` and report that file")
    t = f["nominal/time"][:]
    rows = frames(t.size)
    runs = [("nominal", False, poses_from(f["nominal/com_position"][:], f["nominal/orientation"][:], rows, n))]
    stored = f.get("trajectories", {})
    if "com_position" in stored and "orientation" in stored:
        for k in range(min(stored["com_position"].shape[0], MAX_GHOSTS)):
            pose = poses_from(stored["com_position"][k], stored["orientation"][k], rows, n)
            if np.isfinite(pose).all():
                runs.append((f"sample {k}", True, pose))
    return (t[rows], runs), None


def rotations(q):
    """Unit quaternions (..., 4; q0 the scalar) as rotation matrices (..., 3, 3), body to inertial."""
    w, x, y, z = np.moveaxis(q, -1, 0)
    rows = [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
            2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]
    return np.stack(rows, -1).reshape(q.shape[:-1] + (3, 3))


def half_widths(shape, d, turn):
    """Half the extent along x, y and z of a shape drawn at its body's CoM and turned by `turn` (F, 3, 3)."""
    if shape == "box":
        return np.abs(turn) @ (0.5 * np.asarray(d))
    if shape == "sphere":
        return np.full((turn.shape[0], 3), float(d[0]))
    if shape == "cylinder":  # radius d[0], length d[2] along the body's z
        axis = turn[:, :, 2]
        return 0.5 * d[2] * np.abs(axis) + d[0] * np.sqrt(np.clip(1 - axis * axis, 0, 1))
    return np.zeros((turn.shape[0], 3))  # no shape: a dot at the CoM


def bounds_of(scene, poses):
    """The box (low, high) holding every body's shape, CoM and joint at every frame of every run: what the
    camera frames (the CoMs and joints alone leave a hanging container's bottom outside)."""
    low, high = np.full(3, np.inf), np.full(3, -np.inf)
    for pose in poses:
        pose = pose[np.isfinite(pose).all(axis=1)]
        for b, (shape, d, c) in enumerate(zip(scene["shapes"], scene["dimensions"], scene["com_to_joint"])):
            com, turn = pose[:, 7 * b:7 * b + 3], rotations(pose[:, 7 * b + 3:7 * b + 7])
            half = half_widths(shape, d, turn)
            joint = com + turn @ np.asarray(c)
            low = np.minimum(low, np.min(np.vstack([com - half, joint]), axis=0, initial=np.inf))
            high = np.maximum(high, np.max(np.vstack([com + half, joint]), axis=0, initial=-np.inf))
    return np.floor(low * 1e6) / 1e6, np.ceil(high * 1e6) / 1e6  # outward at the JSON's 6 decimals


def grid_step(low, high):
    """The ground grid's square: a round length (1, 2 or 5 x 10^k m) near a twelfth of the motion's size."""
    size = float(np.linalg.norm(high - low)) or 1.0
    unit = 10.0 ** math.floor(math.log10(size / 12))
    return next(m * unit for m in (1, 2, 5, 10) if m * unit >= size / 12)


def length_words(metres):
    return f"{metres * 1000:g} mm" if metres < 0.01 else f"{metres * 100:g} cm" if metres < 1 else f"{metres:g} m"


def finite_or_none(rows):
    """Nested lists with NaN and inf as None (JSON has neither; JSON.parse refuses them)."""
    return [[v if np.isfinite(v) else None for v in row] for row in np.round(rows, 6).tolist()]


def script_json(data):
    """JSON safe inside <script>: no '<', '>' or '&' can end or re-open the element."""
    text = json.dumps(data, separators=(",", ":"), allow_nan=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def payload(f):
    found, why = runs_of(f)
    if found is None:
        return None, why
    t, runs = found
    if t.size == 0:
        return None, "the file has no output time"
    scene = scene_of(f)
    low, high = bounds_of(scene, [pose for _, _, pose in runs])
    if not (np.isfinite(low).all() and np.isfinite(high).all()):
        return None, "no frame has finite poses"
    step = grid_step(low, high)
    data = {"title": text(f.attrs.get("title", "")), "times": np.round(t, 6).tolist(), "scene": scene,
            "bounds": [low.tolist(), high.tolist()], "grid": {"step": step, "label": length_words(step)},
            "runs": [{"label": label, "ghost": ghost, "pose": finite_or_none(pose)} for label, ghost, pose in runs]}
    return data, None


def view_section(f, page):
    page.heading("The motion in 3-D")
    data, why = payload(f)
    if data is None:
        page.paragraph(f"No 3-D view: {why}.")
        return
    if not os.path.exists(THREE):
        page.paragraph(f"No 3-D view: {THREE} is missing (apt-get install libjs-three).")
        return
    scripts = [THREE] + ([ORBIT] if os.path.exists(ORBIT) else []) + [VIEWER_JS]
    code = "".join(f"<script>{open(s, encoding='utf-8').read()}</script>\n" for s in scripts)
    blob = script_json(data)
    ghosts = sum(1 for r in data["runs"] if r["ghost"])
    page.paragraph(f"{data['runs'][0]['label']}" + (f" with {ghosts} stored samples ghosted" if ghosts else "")
                   + f", {len(data['times'])} frames from t = {data['times'][0]:g} to {data['times'][-1]:g} s. "
                   "Drag to turn, scroll to zoom; z is up. Bodies are drawn by their shapes (nominal dimensions) "
                   "with a stick from each joint through the centre of mass; the dashed line is the base point's "
                   f"path. The grid under the motion has {data['grid']['label']} squares; the axes at its corner "
                   f"are x (red), y (green) and z (blue), each {data['grid']['label']} long. The speed is the "
                   "playback's against real time."
                   + (" To see an extreme or failed sample move, rerun it with the command in the table above and "
                      "report that file." if "stats" in f else ""))
    page.raw('<div id="treedyn-view" style="position:relative;width:100%;height:480px;border:1px solid #bbb">'
             '</div><div style="margin:4px 0"><button id="treedyn-play">pause</button> '
             f'<select id="treedyn-speed" title="playback speed against real time">{SPEED_OPTIONS}</select> '
             '<input id="treedyn-time" type="range" min="0" value="0" style="width:62%;vertical-align:middle"> '
             '<span id="treedyn-clock"></span></div>'
             f'<script id="treedyn-motion" type="application/json">{blob}</script>\n{code}')
