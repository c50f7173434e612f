"""A trajectory file (treedyn run, or one ensemble sample rerun alone): first whether it is a sample and
whether it failed, with why, what to change and its inputs; then its joint angles, energy, reactions and
paths (a failed sample's time plots marked where it failed)."""
import numpy as np

import matplotlib.pyplot as plt

from page import legend_outside
from read import strings, text, units_of
from view3d import view_section

MAX_LINES = 10
FAILED_COLOUR = "#c62828"
# What to change, per failure kind (the first word of /sample's reason, src/integrate/settings.hpp's names),
# in the words `treedyn run` prints when an integration fails: "Loosen the tolerances, raise [integrator]
# max_steps, or check the model."
ADVICE = {
    "too_much_work": "raise [integrator] max_steps ({max_steps} steps per output interval here), loosen the "
                     "tolerances ({tolerances}), or check the model",
    "too_much_accuracy": "loosen the tolerances ({tolerances}): they ask for more than double precision can give",
    "error_test_failures": "loosen the tolerances ({tolerances}) or check the model: the step size fell to "
                           "nothing (repeated error-test failures)",
    "convergence_failures": "loosen the tolerances ({tolerances}), or check the model: the nonlinear solver "
                            "failed repeatedly",
    "nonfinite_state": "check the model (a NaN or infinity in the state or its derivative), or loosen the "
                       "tolerances ({tolerances})",
}
GENERAL_ADVICE = "loosen the tolerances ({tolerances}), raise [integrator] max_steps, or check the model"


def integrator_setting(f, key, default):
    """The job's [integrator] key as the file's job_text gives it, else the default treedyn uses."""
    try:
        import tomllib  # Python 3.11
        return tomllib.loads(text(f.attrs["job_text"])).get("integrator", {}).get(key, default)
    except (ImportError, KeyError, ValueError):
        return default


def advice(f, reason):
    """What to change to get past a failed integration: one sentence."""
    tolerances = (f"rtol = {f.attrs['relative_tolerance']:g}, atol = {f.attrs['absolute_tolerance']:g}"
                  if "relative_tolerance" in f.attrs and "absolute_tolerance" in f.attrs else "rtol, atol")
    words = ADVICE.get(reason.split(" ", 1)[0], GENERAL_ADVICE).format(
        tolerances=tolerances, max_steps=integrator_setting(f, "max_steps", 100000))
    rerun = text(f.attrs.get("command_line", ""))
    return f"What to change: {words}." + (f" Then rerun this sample: {rerun}" if rerun else "")


def failed_at(f):
    """The time a rerun sample's integration stopped, or None when it did not fail."""
    if "sample" in f and int(f["sample"].attrs["status"]) != 0:
        return float(f["sample"].attrs["time_reached"])
    return None


def sample_section(f, page):
    """What an analyst asks first about a rerun sample: did it fail, why, when, what to change, with which
    inputs."""
    if "sample" not in f:
        return
    s = f["sample"].attrs
    k, status = int(s["index"]), int(s["status"])
    if status != 0:
        page.note(f"Sample {k} FAILED: {text(s['reason'])}. The integration reached t = {s['time_reached']:g} s; "
                  f"everything below stops there (marked on the time plots).", "alarm")
        page.note(advice(f, text(s["reason"])), "warning")
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


def mark_failure(axes, failed):
    """A dashed vertical line where the integration stopped, labelled on the plot (left of it: every output
    time comes before it)."""
    if failed is None:
        return ""
    for ax in axes:
        ax.axvline(failed, color=FAILED_COLOUR, ls="--", lw=1.2)
        ax.text(failed, 0.98, f"failed at t = {failed:.4g} s ", transform=ax.get_xaxis_transform(),
                color=FAILED_COLOUR, fontsize=8, ha="right", va="top", rotation=90)
    return f"; the red dashed line: failed at t = {failed:.4g} s"


def lines(page, t, values, names, ylabel, caption, name, failed=None):
    fig, ax = plt.subplots(figsize=(8, 3.3), layout="constrained")
    t, values = finite_rows(t, values)
    marker = "o" if t.size < 3 else None  # a failed sample may have one or two output times
    for c in range(min(values.shape[1], MAX_LINES)):
        ax.plot(t, values[:, c], lw=0.9, marker=marker, label=names[c])
    ax.set_xlabel("t (s)")
    ax.set_ylabel(ylabel)
    legend_outside([ax])
    more = f" (the first {MAX_LINES} of {values.shape[1]})" if values.shape[1] > MAX_LINES else ""
    page.figure(fig, caption + more + mark_failure([ax], failed), name)


def energy_figure(page, t, e, failed=None):
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
    page.figure(fig, "energy and its drift (a moving base, springs or dampers change it)"
                + mark_failure([a, b], failed), "energy")


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
    t, failed = f["time"][:], failed_at(f)
    sample_section(f, page)
    view_section(f, page)
    if (not wanted or "joint_angle" in wanted) and "joint_angle" in f:
        d = f["joint_angle"]
        lines(page, t, d[:], strings(d.attrs["columns"]), f"joint angle ({units_of(d)})", "joint angles",
              "joint_angles", failed)
    if (not wanted or "energy" in wanted) and "energy" in f:
        energy_figure(page, t, f["energy"], failed)
    magnitude, names = reaction_magnitudes(f)
    if magnitude is not None and (not wanted or "joint_reaction" in wanted or "joint_reaction_magnitude" in wanted):
        lines(page, t, magnitude, names, "joint reaction magnitude (N)", "magnitude of each joint's constraint force",
              "joint_reaction_magnitudes", failed)
    paths = "point_position" if "point_position" in f else "com_position" if "com_position" in f else None
    if paths and (not wanted or paths in wanted):
        path_figure(f, page, t, paths)
