"""The 3-D view of the tree moving: one self-contained block of the page (Debian's three.js inlined, the
poses as JSON), so it works from file:// and from a copied folder with no network. Each body is drawn by
its shape (box, cylinder, sphere) and a stick from its inboard joint through its centre of mass to its
children's joints; the base point's path; play/pause and a time slider; stored samples ghosted."""
import json
import os

import numpy as np

from read import strings, text

THREE = "/usr/share/javascript/three/three.min.js"  # Debian's libjs-three
ORBIT = "/usr/share/javascript/three/examples/js/controls/OrbitControls.js"
MAX_FRAMES = 400
MAX_GHOSTS = 20
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
    data = {"title": text(f.attrs.get("title", "")), "times": np.round(t, 6).tolist(), "scene": scene_of(f),
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
                   "path." + (" To see an extreme or failed sample move, rerun it with the command in the table "
                              "above and report that file." if "stats" in f else ""))
    page.raw('<div id="treedyn-view" style="position:relative;width:100%;height:480px;border:1px solid #bbb">'
             '</div><div style="margin:4px 0"><button id="treedyn-play">pause</button> '
             '<input id="treedyn-time" type="range" min="0" value="0" style="width:70%;vertical-align:middle"> '
             '<span id="treedyn-clock"></span></div>'
             f'<script id="treedyn-motion" type="application/json">{blob}</script>\n{code}')
