"""The supporting evidence after the answers: the responses' histograms (the counted runs, and the others
outlined) and their convergence with N, the rank measures side by side, and every failed sample."""
import numpy as np

import matplotlib.pyplot as plt

from page import subplot_grid
from designs import design_of
from read import column_units, folded_note, held_rows, shown_inputs, strings, text

MAX_FAILED_ROWS = 50
MAX_BINS = 60


def response_figures(f, page, rows, counted):
    if "samples/responses" not in f:
        return
    values = f["samples/responses"]
    names, units = strings(values.attrs["columns"]), column_units(values)
    data = values[:]
    others = held_rows(f) & ~rows  # drawn too, outlined: every run the extremes table lists is inside the axes
    fig, axes = subplot_grid(len(names), height=2.6)
    for r, ax in enumerate(axes):
        response_histogram(ax, data[rows, r], data[others, r], f"{names[r]} ({units[r]})")
        if np.isfinite(values.attrs["limit"][r]):
            ax.axvline(values.attrs["limit"][r], color="tab:red", ls="--", lw=1)
    outlined = f"; outlined, {design_of(f).other_runs_words(f, int(others.sum()))}" if others.any() else ""
    page.figure(fig, f"histograms of the responses' finite values: filled, {counted}{outlined} (dashed: the limit)",
                "responses_histograms")
    if "responses" in f:
        convergence_figure(f, page, names, units)


def response_histogram(ax, counted, others, label):
    finite, other = counted[np.isfinite(counted)], others[np.isfinite(others)]
    both = np.r_[finite, other]
    if both.size == 0:
        ax.text(0.5, 0.5, "no finite values", ha="center", transform=ax.transAxes)
    else:
        bins = np.histogram_bin_edges(both, bins="auto" if both.size > 1 else 1)
        bins = bins if bins.size <= MAX_BINS + 1 else np.linspace(both.min(), both.max(), MAX_BINS + 1)
        ax.hist(finite, bins, color="tab:blue", alpha=0.8)
        if other.size:
            ax.hist(other, bins, histtype="step", color="0.25", lw=1)
        if other.size > 2 * finite.size:  # the counted runs stay readable beside many more others
            ax.set_yscale("log")
    if finite.size < counted.size:
        ax.set_title(f"{finite.size} of {counted.size} counted runs finite (failed: NaN, never crossed: inf)",
                     fontsize=8)
    ax.set_xlabel(label, fontsize=8)
    ax.set_ylabel("runs", fontsize=8)


def probability_panels(f, names):
    """The responses whose P the convergence figure draws: with a limit, and not one whose P the design answers
    itself (a subset simulation's: its level 0 alone is not the answer)."""
    design = design_of(f)
    return [np.isfinite(f["responses"][n]["convergence"][:, 4]).any() and design.own_probability_group(f, n) is None
            for n in names]


def own_answer_note(f, names):
    """Where the P the design answers itself is, for the convergence figure's caption."""
    design = design_of(f)
    own = [n for n in names if design.own_probability_group(f, n) is not None]
    return f" ({', '.join(own)}: the P in the answers is the design's own, not the counted runs')" if own else ""


def convergence_figure(f, page, names, units):
    with_p = probability_panels(f, names)
    columns = 2 if any(with_p) else 1
    fig, axes = plt.subplots(len(names), columns, figsize=(5 * columns, 2.7 * len(names)), squeeze=False,
                             layout="constrained")
    for r in range(len(names)):
        c = f["responses"][names[r]]["convergence"][:]
        n, mean, sem = c[:, 0], c[:, 2], c[:, 3]
        ax = axes[r][0]
        ax.fill_between(n, mean - 2 * sem, mean + 2 * sem, color="tab:blue", alpha=0.3, lw=0)
        ax.plot(n, mean, "o-", color="tab:blue", ms=3)
        ax.set_xscale("log")
        ax.set_xlabel("samples", fontsize=8)
        ax.set_ylabel(f"mean {names[r]} ({units[r]})", fontsize=8)
        if columns == 2 and with_p[r]:
            ax = axes[r][1]
            ax.fill_between(n, c[:, 5], c[:, 6], color="tab:red", alpha=0.2, lw=0)
            ax.plot(n, c[:, 4], "s-", color="tab:red", ms=3)
            ax.set_xscale("log")
            ax.set_xlabel("samples", fontsize=8)
            ax.set_ylabel(f"P({names[r]} limit exceeded)", fontsize=8)
        elif columns == 2:
            axes[r][1].set_visible(False)
    page.figure(fig, "convergence: each response's mean ± 2 standard errors" +
                (" (left) and the probability that it exceeds its limit with its 95 % Wilson interval (right)"
                 if columns == 2 else "") + " against the number of samples: the first m in index order, of "
                "which the counted runs count" + own_answer_note(f, names), "responses_convergence")


def sensitivity_figures(f, page):
    """Spearman and SRRC of every input shown one by one for every response, side by side; the SRRC only
    where the rank regression could be computed."""
    if "sensitivity" not in f:
        return
    names = list(f["sensitivity"].keys())
    inputs = strings(f["sensitivity"][names[0]]["spearman"].attrs["columns"])
    shown, folded = shown_inputs(f["samples/inputs"]) if "samples/inputs" in f and \
        "column_targets" in f["samples/inputs"].attrs else (list(range(len(inputs))), {})
    if not shown:
        return
    inputs = [inputs[i] for i in shown]
    measures = [("Spearman", "spearman")]
    srrc = np.array([f["sensitivity"][n]["srrc"][:][shown] for n in names])
    if np.isfinite(srrc).any():
        measures.append(("SRRC", "srrc"))
    else:
        s = f["sensitivity"][names[0]]
        page.paragraph(f"No SRRC map: the rank regression needs more runs than inputs ({len(s['srrc'])} inputs, "
                       f"{int(s.attrs.get('rank_samples', 0))} runs).")
    fig, axes = plt.subplots(1, len(measures), figsize=(2.2 + 1.6 * len(names) * len(measures),
                                                        1.2 + 0.35 * len(inputs)), squeeze=False,
                             layout="constrained")
    for ax, (title, key) in zip(axes[0], measures):
        measure_map(ax, np.array([f["sensitivity"][n][key][:][shown] for n in names]), names, inputs,
                    ax is axes[0][0])
        ax.set_title(title, fontsize=9)
    page.figure(fig, "every input (rows) against every response (columns): Spearman rank correlation" +
                (" and standardised rank regression coefficient" if len(measures) > 1 else "") +
                ", over the counted runs (n/a: not defined, e.g. a constant response)" +
                (". " + folded_note(folded) if folded else ""), "sensitivity_measures")


def measure_map(ax, v, names, inputs, labelled):
    image = ax.imshow(v.T, cmap="RdBu_r", vmin=-1, vmax=1, aspect="auto")
    ax.set_xticks(range(len(names)), names, rotation=30, ha="right", fontsize=8)
    ax.set_yticks(range(len(inputs)), inputs if labelled else [""] * len(inputs), fontsize=8)
    for i in range(len(names)):
        for j in range(len(inputs)):
            ax.text(i, j, f"{v[i, j]:.2f}" if np.isfinite(v[i, j]) else "n/a", ha="center", va="center",
                    fontsize=7, color="white" if np.isfinite(v[i, j]) and abs(v[i, j]) > 0.6 else "black")
    ax.figure.colorbar(image, ax=ax, shrink=0.8)


def failed_table(f, page):
    status = f["samples/status"][:]
    failed = np.flatnonzero((status == 1) | (status == 2))  # 3: not run in this merged file
    page.heading(f"Failed samples: {failed.size} of {int(np.count_nonzero(status != 3))}")
    if failed.size == 0:
        return
    reason, reached = f["samples/reason"], f["samples/time_reached"]
    inputs = f["samples/inputs"] if "samples/inputs" in f else None
    shown, folded = shown_inputs(inputs) if inputs is not None else ([], {})
    names = [f"{strings(inputs.attrs['columns'])[i]} ({column_units(inputs)[i]})" for i in shown] \
        if inputs is not None else []
    rows = []
    for k in failed[:MAX_FAILED_ROWS]:
        row = [int(k), int(status[k]), text(reason[k]), f"{reached[k]:.6g}"]
        if inputs is not None:
            row += [f"{v:.6g}" for v in inputs[k, :][shown]]
        rows.append(row)
    page.table(["sample", "status", "reason", "time reached (s)"] + names, rows)
    if folded:
        page.paragraph(folded_note(folded))
    if failed.size > MAX_FAILED_ROWS:
        page.paragraph(f"the first {MAX_FAILED_ROWS} shown; all are in /samples/status and /samples/reason")
