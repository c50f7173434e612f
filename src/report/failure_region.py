"""What makes a response exceed its limit, as the file stores it: /responses/<r>/exceedance/failure_region (the
counted runs beyond the limit) or, for subset simulation, /rare_event/<r>/failure_region (every run beyond the
limit, any level). Per unit (a group, a list, an input) its importance; per input where the failing runs sit
(mean u, mean u², the design point) and how many sit at a truncation bound, which then sets P; and a figure of
the failing runs against each input's distribution."""
from collections import namedtuple

import numpy as np

from page import legend_outside, subplot_grid
from designs import design_of
from read import column_units, fail_side, held_rows, strings

BOUND_SETS_P = 0.5   # a share of the failing runs at a bound from which P depends on the cut-off
NEAR_BOUND = 0.01    # "near": within this share of the distribution's range (the file's near_bound)
ROUGH_RUNS = 20      # fewer failing runs than this, or than inputs, say little (chance moves each share)
FIGURE_INPUTS = 4

# g: the failure_region group; which: words for its runs; failed: failed runs that might have exceeded;
# failing, distribution: rows of /samples (the runs beyond the limit; the runs that show each input's
# distribution as sampled) and the words for the latter.
Region = namedtuple("Region", "name g which failed failing distribution distribution_words")

DEFINITIONS = ("Importance: how far the failing runs' inputs depart from each input's own distribution "
               "(relative entropy in standard normal space, less what chance alone gives), as a share over the "
               "inputs; a group or a list (a sea state's phases) is one unit. Mean u: where the failing runs sit "
               "in standard normal space, u = Phi^-1(F(x)) (0: the input's median, +2: its upper 2.3 %); mean u² "
               "well above 1 with mean u near 0: they sit on both sides. Design point: the input at u = mean u, "
               "the most likely failing value where the region is one-sided. Near a bound: the share of the "
               "failing runs within 1 % of the distribution's range of a truncation bound. This is about the runs "
               "beyond the limit; the drivers above are about the response's whole spread, so an input can matter "
               "here and little there.")


def failure_region_section(f, page, rows, counted):
    if "samples/responses" not in f or "samples/inputs" not in f:
        return
    names = strings(f["samples/responses"].attrs["columns"])
    regions = [r for r in (region_of(f, name, rows, counted) for name in names) if r is not None]
    if not regions:
        return  # no response with a limit: nothing to say
    page.heading("What makes each response exceed its limit", 3)
    page.paragraph(DEFINITIONS)
    for region in regions:
        region_block(f, page, region)


def region_of(f, name, rows, counted):
    """The stored failure region of response `name` and the runs it rests on; None without one (no limit, or
    no sampled inputs)."""
    values = f["samples/responses"]
    r = strings(values.attrs["columns"]).index(name)
    status = f["samples/status"][:]
    beyond = exceeded(values, r, values[:, r]) & (status == 0)
    design = design_of(f)
    if design.own_probability_group(f, name) is not None:  # the design's P is the answer: its failure region
        own = design.own_failure_region(f, name)
        if own is None:
            return None
        return Region(name, own.group, own.which_runs, own.failed, beyond & held_rows(f), own.reference,
                      own.reference_words)
    e = f["responses"][name].get("exceedance") if "responses" in f and name in f["responses"] else None
    if e is None or "failure_region" not in e:
        return None
    return Region(name, e["failure_region"], "counted runs beyond the limit", int(e["failed"][()]), beyond & rows,
                  rows, counted)


def exceeded(values, r, y):
    limit = values.attrs["limit"][r]
    if not np.isfinite(limit):
        return np.zeros(y.size, dtype=bool)
    with np.errstate(invalid="ignore"):
        return y > limit if fail_side(values, r) == "above" else y < limit


def no_runs_line(region):
    if region.failed:
        return (f"{region.name}: no successful run exceeds the limit; {region.failed} failed run"
                f"{'s' if region.failed != 1 else ''} might have.")
    return f"{region.name}: no successful run exceeds the limit (none failed): nothing yet says what makes it exceed."


def region_block(f, page, region):
    g = region.g
    runs = int(g.attrs["runs"])
    if runs == 0 or "unit_importance" not in g:
        page.paragraph(no_runs_line(region))
        return
    inputs = g["mean_u"].size
    effective = float(g.attrs.get("effective_runs", runs))  # fewer for subset simulation's chain states
    page.paragraph(f"{region.name}: the {runs} {region.which}"
                   + (f" ({region.failed} failed runs might also have exceeded it)." if region.failed else "."))
    page.table(["input or group", "importance", "mean u", "mean u²", "design point", "near a bound"],
               region_rows(f, g))
    if not np.isfinite(g["unit_importance"][:]).any():
        page.paragraph(f"{region.name}: no input departs from its own distribution beyond chance.")
    if effective < max(ROUGH_RUNS, inputs):
        chains = f" (as {effective:.0f} independent ones: chain states)" if effective < runs else ""
        page.note(f"Rough: {runs} runs beyond the limit{chains} for {inputs} inputs; chance alone moves each "
                  f"input's share (at least {max(ROUGH_RUNS, inputs)} would tell).")
    for words in bound_warnings(f, g, region):
        page.note(words)
    failing_inputs_figure(f, page, region)


def unit_inputs(g):
    """Each unit's input indices (columns of the per-input datasets), by importance, largest first."""
    index = {n: i for i, n in enumerate(strings(g["mean_u"].attrs["columns"]))}
    members = [[index[n] for n in m.split(", ") if n in index] for m in strings(g.attrs["unit_inputs"])]
    importance = g["unit_importance"][:]
    order = np.argsort(-np.nan_to_num(importance, nan=-1.0), kind="stable")
    return [(int(u), members[u]) for u in order]


def region_rows(f, g):
    units = strings(g["unit_importance"].attrs["columns"])
    si = column_units(f["samples/inputs"])
    importance, mean_u, mean_u2 = g["unit_importance"][:], g["mean_u"][:], g["mean_u2"][:]
    rows = []
    for u, members in unit_inputs(g):
        share = f"{importance[u]:.2f}" if np.isfinite(importance[u]) else "n/a"
        if len(members) != 1:
            rows.append([units[u], share, f"({len(members)} inputs: per input in the file)", "", "", ""])
            continue
        i = members[0]
        rows.append([units[u], share, f"{mean_u[i]:.2f}", f"{mean_u2[i]:.2f}",
                     f"{g['design_point'][i]:.4g} {si[i]}", near_text(g, i, si[i])])
    return rows


def near_text(g, i, unit):
    share = g["near_bound"][i]
    return "no bound" if not np.isfinite(share) else f"{100 * share:.0f} % (bound {g['bound'][i]:.6g} {unit})"


def bound_side(f, g, i, region):
    """'upper bound' or 'lower bound' where the failing runs sit on one side (mean u carries most of their
    spread), else one of two bounds."""
    one_sided = abs(g["mean_u"][i]) >= 0.5 * np.sqrt(g["mean_u2"][i])
    if not one_sided:
        return None
    column = f["samples/inputs"][:, i][region.distribution]
    return "upper bound" if g["bound"][i] >= np.nanmean(column) else "lower bound"


def bound_warnings(f, g, region):
    names, si = strings(g["mean_u"].attrs["columns"]), column_units(f["samples/inputs"])
    out = []
    for i in np.flatnonzero(np.nan_to_num(g["near_bound"][:], nan=0.0) >= BOUND_SETS_P):
        side = bound_side(f, g, i, region)
        where = (f"within 1 % of its {side} {g['bound'][i]:.6g} {si[i]}" if side else
                 f"within 1 % of the range of one of its bounds (most near {g['bound'][i]:.6g} {si[i]})")
        out.append(f"{100 * g['near_bound'][i]:.0f} % of the failing runs have {names[i]} {where}: P depends on "
                   "where that distribution is cut off, not only on the dynamics.")
    return out


def failing_inputs_figure(f, page, region):
    g = region.g
    top = [members[0] for _, members in unit_inputs(g) if len(members) == 1][:FIGURE_INPUTS]
    if not top or not region.failing.any():
        return
    x = f["samples/inputs"][:]
    names, si = strings(f["samples/inputs"].attrs["columns"]), column_units(f["samples/inputs"])
    fig, axes = subplot_grid(len(top) + 1, width=3.3, height=2.6, columns=len(top) + 1)
    axes[-1].set_visible(False)  # the legend's cell: the right axes' labels leave no room beside them
    twins = []
    for ax, i in zip(axes, top):
        spread, failing = x[region.distribution, i], x[region.failing, i]
        spread = spread[np.isfinite(spread)]
        bins = np.histogram_bin_edges(np.r_[spread, failing], bins=int(np.clip(2 * np.sqrt(spread.size), 8, 30)))
        ax.hist(spread, bins, color="0.65", label="the input's distribution as sampled (left axis)")
        twins.append(ax.twinx())  # a few failing runs beside many sampled ones: each on its own scale
        twins[-1].hist(failing, bins, color="tab:red", alpha=0.6, label="runs beyond the limit (right axis)")
        twins[-1].set_ylabel("runs beyond the limit", fontsize=8, color="tab:red")
        ax.axvline(g["design_point"][i], color="k", lw=1, label="design point (u = mean u)")
        if np.isfinite(g["near_bound"][i]):
            ax.axvline(g["bound"][i], color="tab:orange", ls="--", lw=1.2, label="the bound they are nearest")
        ax.set_xlabel(f"{names[i]} ({si[i]})", fontsize=8)
        ax.set_ylabel("runs", fontsize=8)
    handles, labels = axes[0].get_legend_handles_labels()
    more = twins[0].get_legend_handles_labels()
    legend_outside(axes[:-1], (handles[:1] + more[0] + handles[1:], labels[:1] + more[1] + labels[1:]))
    page.figure(fig, f"{region.name}: the {int(region.failing.sum())} {region.which} (red, right axis) against each "
                     f"input's distribution as sampled ({region.distribution_words}; grey, left axis), for its "
                     f"{len(top)} most important inputs; black: the design point", f"failure_region_{region.name}")
