"""A trajectory file (treedyn run, or one ensemble sample rerun alone): first whether it is a sample and
whether it failed, with why and its inputs; then its joint angles, energy, reactions and paths."""
import numpy as np

import matplotlib.pyplot as plt

from page import legend_outside
from read import strings, text, units_of
from view3d import view_section

MAX_LINES = 10


def sample_section(f, page):
    """What an analyst asks first about a rerun sample: did it fail, why, when, with which inputs."""
    if "sample" not in f:
        return
    s = f["sample"].attrs
    k, status = int(s["index"]), int(s["status"])
    if status != 0:
        page.note(f"Sample {k} FAILED: {text(s['reason'])}. The integration reached t = {s['time_reached']:g} s; "
                  f"everything below stops there.", "alarm")
    else:
        page.note(f"Sample {k} of the ensemble, integrated alone by the ensemble's own code path: it succeeded "
                  f"(its /final_state is the ensemble's /samples/final_state row, bit for bit: tested).", "good")
    if "sample/inputs" in f:
        d = f["sample/inputs"]
        page.table(["input", "value", "unit"], [[n, f"{v:.9g}", u] for n, v, u in
                                               zip(strings(d.attrs["columns"]), d[:], strings(d.attrs["column_units"]))])


def finite_rows(t, values):
    """The output times up to the last one with finite values (a failed sample's trajectory ends there)."""
    ok = np.all(np.isfinite(values.reshape(values.shape[0], -1)), axis=1)
    last = np.flatnonzero(ok)[-1] + 1 if ok.any() else 0
    return t[:last], values[:last]


def lines(page, t, values, names, ylabel, caption, name):
    fig, ax = plt.subplots(figsize=(8, 3.3), layout="constrained")
    t, values = finite_rows(t, values)
    marker = "o" if t.size < 3 else None  # a failed sample may have one or two output times
    for c in range(min(values.shape[1], MAX_LINES)):
        ax.plot(t, values[:, c], lw=0.9, marker=marker, label=names[c])
    ax.set_xlabel("t (s)")
    ax.set_ylabel(ylabel)
    legend_outside([ax])
    more = f" (the first {MAX_LINES} of {values.shape[1]})" if values.shape[1] > MAX_LINES else ""
    page.figure(fig, caption + more, name)


def energy_figure(page, t, e):
    names = strings(e.attrs["columns"])
    t, values = finite_rows(t, e[:])
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.3), layout="constrained")
    marker = "o" if t.size < 3 else None
    for c in range(values.shape[1]):
        a.plot(t, values[:, c], lw=0.9, marker=marker, label=names[c])
    a.set_xlabel("t (s)")
    a.set_ylabel(f"energy ({units_of(e)})")
    a.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    total = values[:, names.index("total")]
    if total.size:
        b.plot(t, total - total[0], lw=0.9, marker=marker)
    b.set_xlabel("t (s)")
    b.set_ylabel(f"E(t) - E(0) ({units_of(e)})")
    page.figure(fig, "energy and its drift (a moving base, springs or dampers change it)", "energy")


def reaction_magnitudes(f):
    if "joint_reaction_magnitude" in f:
        return f["joint_reaction_magnitude"][:], strings(f["joint_reaction_magnitude"].attrs["columns"])
    if "joint_reaction" in f:
        r = f["joint_reaction"][:]
        names = [c.rsplit(".", 1)[0] for c in strings(f["joint_reaction"].attrs["columns"])[::3]]
        return np.linalg.norm(r.reshape(r.shape[0], -1, 3), axis=2), names
    return None, []


def path_figure(f, page, t, paths):
    """The two coordinates that move most, so that a planar motion is not drawn as flat lines."""
    d = finite_rows(t, f[paths][:])[1]
    names = strings(f[paths].attrs["columns"])
    points = min(d.shape[1] // 3, MAX_LINES)
    spread = [np.ptp(d[:, i::3]) if d.size else 0.0 for i in range(3)]
    i, j = sorted(sorted(range(3), key=lambda a: -spread[a])[:2])
    fig, ax = plt.subplots(figsize=(6, 4.5), layout="constrained")
    for p in range(points):
        ax.plot(d[:, 3 * p + i], d[:, 3 * p + j], lw=0.8, label=names[3 * p].rsplit(".", 1)[0])
    ax.set_xlabel(f"{'xyz'[i]} (m)")
    ax.set_ylabel(f"{'xyz'[j]} (m)")
    ax.set_aspect("equal", adjustable="datalim")
    legend_outside([ax])
    what = "points" if paths == "point_position" else "centres of mass"
    page.figure(fig, f"paths of the recorded {what} in the {'xyz'[i]}-{'xyz'[j]} plane (the two coordinates "
                     f"that move most; the third spans {spread[3 - i - j]:.3g} m)", f"paths_{paths}")


def trajectory_report(f, page, wanted):
    t = f["time"][:]
    sample_section(f, page)
    view_section(f, page)
    if (not wanted or "joint_angle" in wanted) and "joint_angle" in f:
        d = f["joint_angle"]
        lines(page, t, d[:], strings(d.attrs["columns"]), f"joint angle ({units_of(d)})", "joint angles",
              "joint_angles")
    if (not wanted or "energy" in wanted) and "energy" in f:
        energy_figure(page, t, f["energy"])
    magnitude, names = reaction_magnitudes(f)
    if magnitude is not None and (not wanted or "joint_reaction" in wanted or "joint_reaction_magnitude" in wanted):
        lines(page, t, magnitude, names, "joint reaction magnitude (N)", "magnitude of each joint's constraint force",
              "joint_reaction_magnitudes")
    paths = "point_position" if "point_position" in f else "com_position" if "com_position" in f else None
    if paths and (not wanted or paths in wanted):
        path_figure(f, page, t, paths)
