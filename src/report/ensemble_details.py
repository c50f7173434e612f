"""The supporting evidence after the answers: the responses' histograms over the counted runs and their
convergence with N, the sensitivity measures side by side, and every failed sample."""
import numpy as np

import matplotlib.pyplot as plt

from history import histogram
from page import subplot_grid
from read import folded_note, shown_inputs, strings, text

MAX_FAILED_ROWS = 50


def response_figures(f, page, rows, counted):
    if "samples/responses" not in f:
        return
    values = f["samples/responses"]
    names, units = strings(values.attrs["columns"]), strings(values.attrs["column_units"])
    data = values[:][rows]
    fig, axes = subplot_grid(len(names), height=2.6)
    for r, ax in enumerate(axes):
        histogram(ax, data[:, r], names[r], units[r])
        finite = int(np.count_nonzero(np.isfinite(data[:, r])))
        if finite < data.shape[0]:
            ax.set_title(f"{finite} of {data.shape[0]} finite (failed: NaN, never crossed: inf)", fontsize=8)
        if np.isfinite(values.attrs["limit"][r]):
            ax.axvline(values.attrs["limit"][r], color="tab:red", ls="--", lw=1)
    page.figure(fig, f"histograms of the responses over {counted}, their finite values (dashed: the limit)",
                "responses_histograms")
    if "responses" in f:
        convergence_figure(f, page, names, units)


def convergence_figure(f, page, names, units):
    fig, axes = plt.subplots(len(names), 2, figsize=(10, 2.7 * len(names)), squeeze=False, layout="constrained")
    for r in range(len(names)):
        c = f["responses"][names[r]]["convergence"][:]
        n, mean, sem = c[:, 0], c[:, 2], c[:, 3]
        ax = axes[r][0]
        ax.fill_between(n, mean - 2 * sem, mean + 2 * sem, color="tab:blue", alpha=0.3, lw=0)
        ax.plot(n, mean, "o-", color="tab:blue", ms=3)
        ax.set_xscale("log")
        ax.set_xlabel("samples", fontsize=8)
        ax.set_ylabel(f"mean {names[r]} ({units[r]})", fontsize=8)
        ax = axes[r][1]
        if np.isfinite(c[:, 4]).any():
            ax.fill_between(n, c[:, 5], c[:, 6], color="tab:red", alpha=0.2, lw=0)
            ax.plot(n, c[:, 4], "s-", color="tab:red", ms=3)
            ax.set_xscale("log")
            ax.set_xlabel("samples", fontsize=8)
            ax.set_ylabel(f"P({names[r]} limit exceeded)", fontsize=8)
        else:
            ax.set_visible(False)
    page.figure(fig, "convergence: each response's mean ± 2 standard errors (left) and the probability that it "
                     "exceeds its limit with its 95 % Wilson interval (right) against the number of samples "
                     "(the first m samples in index order)", "responses_convergence")


def sensitivity_figures(f, page):
    """Spearman, SRRC and (Saltelli) total Sobol' index of every input for every response, side by side."""
    if "sensitivity" not in f:
        return
    names = list(f["sensitivity"].keys())
    inputs = strings(f["sensitivity"][names[0]]["spearman"].attrs["columns"])
    shown, folded = shown_inputs(f["samples/inputs"]) if "samples/inputs" in f else (list(range(len(inputs))), {})
    if not shown:
        return
    inputs = [inputs[i] for i in shown]
    measures = [("Spearman", "spearman", "RdBu_r", -1), ("SRRC", "srrc", "RdBu_r", -1)]
    if "total_order" in f["sensitivity"][names[0]] and "group_total_order" not in f["sensitivity"][names[0]]:
        measures.append(("total Sobol'", "total_order", "Oranges", 0))  # a grouped design's are per group
    fig, axes = plt.subplots(1, len(measures), figsize=(2.2 + 1.6 * len(names) * len(measures),
                                                        1.2 + 0.35 * len(inputs)), squeeze=False,
                             layout="constrained")
    for ax, (title, key, cmap, low) in zip(axes[0], measures):
        v = np.array([f["sensitivity"][n][key][:][shown] for n in names])
        image = ax.imshow(v.T, cmap=cmap, vmin=low, vmax=1, aspect="auto")
        ax.set_xticks(range(len(names)), names, rotation=30, ha="right", fontsize=8)
        ax.set_yticks(range(len(inputs)), inputs if ax is axes[0][0] else [""] * len(inputs), fontsize=8)
        ax.set_title(title, fontsize=9)
        for i in range(len(names)):
            for j in range(len(inputs)):
                if np.isfinite(v[i, j]):
                    ax.text(i, j, f"{v[i, j]:.2f}", ha="center", va="center", fontsize=7,
                            color="white" if abs(v[i, j]) > 0.6 else "black")
        fig.colorbar(image, ax=ax, shrink=0.8)
    page.figure(fig, "every input (rows) against every response (columns): Spearman rank correlation, standardised "
                     "rank regression coefficient" + (" and total Sobol' index" if len(measures) > 2 else "") +
                     (". " + folded_note(folded) if folded else ""),
                "sensitivity_measures")


def failed_table(f, page):
    status = f["samples/status"][:]
    failed = np.flatnonzero((status == 1) | (status == 2))  # 3: not run in this merged file
    page.heading(f"Failed samples: {failed.size} of {int(np.count_nonzero(status != 3))}")
    if failed.size == 0:
        return
    reason, reached = f["samples/reason"], f["samples/time_reached"]
    inputs = f["samples/inputs"] if "samples/inputs" in f else None
    shown, folded = shown_inputs(inputs) if inputs is not None else ([], {})
    names = [strings(inputs.attrs["columns"])[i] for i in shown] if inputs is not None else []
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
