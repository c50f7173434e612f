"""The recorded quantities over time (after the answers, folded): mean ± std
bands clipped to each quantity's valid range, the quantile fan, min/max, the
nominal run and stored samples; histograms at the last output time over the
counted runs. Constant columns are listed, not drawn; orientations are drawn
as a rotation angle."""
import math

import numpy as np

from page import legend_outside, subplot_grid
from read import strings, units_of

MAX_GROUPS = 3      # column groups drawn per quantity unless --quantity asks for it
MAX_SPAGHETTI = 20  # stored sample trajectories drawn per figure
PER_FIGURE = 9      # subplots in one figure when the columns are not grouped by body

# Where a quantity's values can lie: a mean ± std band is clipped to it.
VALID_RANGE = {"joint_angle": (0.0, math.pi), "joint_reaction_magnitude": (0.0, math.inf)}
VALID_COLUMN_RANGE = {("energy", "kinetic"): (0.0, math.inf), ("com_offset", "horizontal"): (0.0, math.inf)}


def groups_of(columns):
    """Column indices grouped by the label before the last dot (a body, a point); one column per body
    (joint angles, tensions): figures of up to PER_FIGURE columns instead."""
    groups, order = {}, []
    for i, c in enumerate(columns):
        key = c.rsplit(".", 1)[0] if "." in c else ""
        if key not in groups:
            groups[key] = []
            order.append(key)
        groups[key].append(i)
    if all(len(g) == 1 for g in groups.values()) or (len(order) == 1 and len(columns) > PER_FIGURE):
        flat = [i for k in order for i in groups[k]]
        chunks = [flat[i:i + PER_FIGURE] for i in range(0, len(flat), PER_FIGURE)]
        return [(f"{columns[c[0]]} .. {columns[c[-1]]}" if len(chunks) > 1 else "", c) for c in chunks]
    return [(k, groups[k]) for k in order]


def select(groups, everything):
    """All groups, or at most MAX_GROUPS spread over them (first and last kept)."""
    if everything or len(groups) <= MAX_GROUPS:
        return groups, False
    picks = sorted({round(i * (len(groups) - 1) / (MAX_GROUPS - 1)) for i in range(MAX_GROUPS)})
    return [groups[i] for i in picks], True


def constant_columns(stats):
    """Columns whose every sample has one value at every output time (a fixed base, a zero spring)."""
    low, high = stats["min"][:], stats["max"][:]
    with np.errstate(invalid="ignore"):
        return {c for c in range(low.shape[1]) if np.nanmax(high[:, c]) == np.nanmin(low[:, c])}


def valid_range(quantity, column):
    name = column.rsplit(".", 1)[-1]
    return VALID_COLUMN_RANGE.get((quantity, name), VALID_RANGE.get(quantity, (-math.inf, math.inf)))


def drawn_groups(columns, constant, everything):
    groups = [(n, [c for c in idx if c not in constant]) for n, idx in groups_of(columns)]
    groups = [(n, idx) for n, idx in groups if idx]
    chosen, partial = select(groups, everything)
    return chosen, partial, len(groups)


def band_axes(ax, t, stats, c, pairs, probabilities, bounds):
    m, s = stats["mean"][:, c], stats["std"][:, c]
    quantiles = stats["quantiles"]
    for low, high in pairs:
        ax.fill_between(t, quantiles[low, :, c], quantiles[high, :, c], color="tab:orange", alpha=0.25, lw=0,
                        label=f"{probabilities[low]:g}-{probabilities[high]:g} quantiles")
    ax.fill_between(t, np.clip(m - s, *bounds), np.clip(m + s, *bounds), color="tab:blue", alpha=0.3, lw=0,
                    label="mean ± std" + (" (clipped to the valid range)" if np.isfinite(bounds).any() else ""))
    ax.plot(t, m, color="tab:blue", lw=1.2, label="mean")
    ax.plot(t, stats["min"][:, c], "k:", lw=0.7, label="min / max")
    ax.plot(t, stats["max"][:, c], "k:", lw=0.7)


def ensemble_quantity_figures(f, page, quantity, everything):
    """Returns the column groups drawn, for the histograms."""
    if quantity == "orientation":
        return orientation_figure(f, page)
    stats = f["stats"][quantity]
    t = f["stats/time"][:]
    columns = strings(stats["mean"].attrs["columns"])
    constant = constant_columns(stats)
    groups, partial, total = drawn_groups(columns, constant, everything)
    if constant:
        page.paragraph(f"{quantity}: not drawn, the same in every sample at every time: "
                       + ", ".join(f"{columns[c]} = {stats['min'][0, c]:.6g}" for c in sorted(constant)))
    p = list(stats["quantiles"].attrs["probabilities"])
    pairs = [(i, p.index(1 - q)) for i, q in enumerate(p) if q < 0.5 and (1 - q) in p]
    nominal = f["nominal"][quantity] if quantity in f.get("nominal", {}) else None
    stored = f["trajectories"][quantity] if "trajectories" in f and quantity in f["trajectories"] else None
    for name, indices in groups:
        fig, axes = subplot_grid(len(indices))
        for ax, c in zip(axes, indices):
            if stored is not None:
                for k in range(min(stored.shape[0], MAX_SPAGHETTI)):
                    ax.plot(t, stored[k, :, c], color="0.6", lw=0.5, alpha=0.6,
                            label="stored samples" if k == 0 else None)
            band_axes(ax, t, stats, c, pairs, p, valid_range(quantity, columns[c]))
            if nominal is not None:
                ax.plot(t, nominal[:, c], color="tab:red", lw=0.9, ls="--", label="nominal")
            ax.set_title(columns[c], fontsize=9)
            ax.set_xlabel("t (s)", fontsize=8)
            ax.set_ylabel(f"{quantity} ({units_of(stats['mean'], c)})", fontsize=8)
        legend_outside(axes)
        page.figure(fig, f"{quantity} {name}: over the successful samples, mean ± std band, quantile fan, min/max, "
                         "nominal" + (", stored samples" if stored is not None else ""), f"{quantity}_{name}")
    if partial:
        page.paragraph(f"{quantity}: {len(groups)} of {total} column groups shown; "
                       f"`treedyn report FILE --quantity {quantity}` draws all of them.")
    return groups


def rotation_angle_degrees(q):
    """2 acos(q0) of unit quaternions with q0 >= 0: the angle of the rotation from the reference orientation."""
    return np.degrees(2 * np.arccos(np.clip(np.abs(q), 0.0, 1.0)))


def orientation_figure(f, page):
    """Quaternions are drawn as each body's rotation angle from its reference orientation: their components'
    mean and std mislead (q and -q are one orientation, and the sign rule q0 >= 0 flips q1..q3)."""
    t = f["stats/time"][:]
    columns = strings(f["stats/orientation/mean"].attrs["columns"])
    bodies = [c.rsplit(".", 1)[0] for c in columns[::4]]
    nominal = f["nominal/orientation"][:] if "nominal" in f and "orientation" in f["nominal"] else None
    stored = f["trajectories/orientation"] if "trajectories" in f and "orientation" in f["trajectories"] else None
    fig, axes = subplot_grid(min(len(bodies), PER_FIGURE))
    for b, ax in enumerate(axes):
        if stored is not None:
            for k in range(min(stored.shape[0], MAX_SPAGHETTI)):
                ax.plot(t, rotation_angle_degrees(stored[k, :, 4 * b]), color="0.6", lw=0.5,
                        label="stored samples" if k == 0 else None)
        if nominal is not None:
            ax.plot(t, rotation_angle_degrees(nominal[:, 4 * b]), color="tab:red", lw=0.9, label="nominal")
        ax.set_title(bodies[b], fontsize=9)
        ax.set_xlabel("t (s)", fontsize=8)
        ax.set_ylabel("rotation angle (deg)", fontsize=8)
        ax.set_ylim(0, 180)
    legend_outside(axes)
    page.figure(fig, "orientation drawn as each body's rotation angle from its reference orientation, "
                     "2 acos(q0), in degrees (the quaternion components' mean and std are in /stats/orientation; "
                     "they are not drawn, as q and -q are one orientation)", "orientation_rotation_angle")
    return []


def histogram(ax, values, label, units):
    values = values[np.isfinite(values)]
    if values.size == 0:
        ax.text(0.5, 0.5, "no finite values", ha="center", transform=ax.transAxes)
    else:
        ax.hist(values, bins="auto" if values.size > 1 else 1, color="tab:blue", alpha=0.8)
    ax.set_xlabel(f"{label} ({units})", fontsize=8)
    ax.set_ylabel("runs", fontsize=8)


def final_value_histograms(f, page, quantity, groups, rows, counted):
    """One figure per quantity: its drawn columns' values at the last output time (at most PER_FIGURE)."""
    if "final" not in f["samples"] or quantity not in f["samples/final"] or not groups:
        return
    data = f["samples/final"][quantity]
    columns = strings(data.attrs["columns"])
    indices = [c for _, group in groups for c in group]
    shown = indices[:PER_FIGURE]
    values = data[:][rows]
    fig, axes = subplot_grid(len(shown), height=2.4)
    for ax, c in zip(axes, shown):
        histogram(ax, values[:, c], columns[c], units_of(data, c))
    more = f" (the first {len(shown)} of {len(indices)} columns drawn above)" if len(indices) > len(shown) else ""
    page.figure(fig, f"{quantity}: histograms of the values at the last output time over {counted}{more}",
                f"{quantity}_final_histograms")
