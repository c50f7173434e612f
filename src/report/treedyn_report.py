#!/usr/bin/python3
"""Figures and one HTML page from a treedyn HDF5 file (ensemble or trajectory).

Started by `treedyn report`, which has already checked the file and written
the text summary (DIR/summary.txt) with the same code as the end-of-run
summary of treedyn-ensemble. Reads only what one figure needs at a time.

Exit codes: 0 ok, 2 the file or the options were refused (one line on
stderr), 4 the output directory could not be written.
"""
import argparse
import html
import math
import os
import sys

MAX_GROUPS = 6      # column groups drawn per quantity unless --quantity asks for it
MAX_SPAGHETTI = 20  # stored sample trajectories drawn per figure
MAX_FAILED_ROWS = 50


def fail(message, code=2):
    print(f"error: {message}", file=sys.stderr)
    sys.exit(code)


def say(line):
    """One line on stdout, which may be a pipe closed early (`treedyn report
    F | head -1`): the report is written all the same, without a traceback."""
    try:
        print(line, flush=True)
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())


try:
    import numpy as np
    import h5py
except ImportError as e:
    fail(f"treedyn report needs numpy and h5py ({e.name} is missing): apt-get install python3-h5py")
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    fail("treedyn report needs matplotlib: apt-get install python3-matplotlib")


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def strings(v):
    return [text(x) for x in v]


def units_of(dataset, column=None):
    if column is not None and "column_units" in dataset.attrs:
        return text(dataset.attrs["column_units"][column])
    return text(dataset.attrs.get("units", ""))


PER_FIGURE = 9  # subplots in one figure when the columns are not grouped by body


def groups_of(columns):
    """Column indices grouped by the label before the last dot (a body, a
    point); one column per body (joint angles, tensions): figures of up to
    PER_FIGURE columns instead."""
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


class Page:
    def __init__(self, out_dir, title):
        self.out_dir, self.title, self.parts, self.figures = out_dir, title, [], 0

    def heading(self, words):
        self.parts.append(f"<h2>{html.escape(words)}</h2>")

    def paragraph(self, words):
        self.parts.append(f"<p>{html.escape(words)}</p>")

    def pre(self, words):
        self.parts.append(f"<pre>{html.escape(words)}</pre>")

    def table(self, header, rows):
        cells = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>" for r in rows)
        self.parts.append(f"<table><tr>{cells}</tr>{body}</table>")

    def figure(self, fig, caption):
        self.figures += 1
        name = f"figure_{self.figures:03d}.png"
        fig.savefig(os.path.join(self.out_dir, name), dpi=90, bbox_inches="tight")
        plt.close(fig)
        self.parts.append(f'<figure><img src="{name}" alt="{html.escape(caption)}">'
                          f"<figcaption>{html.escape(caption)}</figcaption></figure>")

    def write(self):
        style = ("body{font-family:sans-serif;max-width:1100px;margin:auto}img{max-width:100%}"
                 "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:2px 6px;font-size:90%}"
                 "figure{margin:1em 0}pre{background:#f4f4f4;padding:6px;overflow-x:auto}")
        page = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(self.title)}</title>"
                f"<style>{style}</style></head><body><h1>{html.escape(self.title)}</h1>"
                + "\n".join(self.parts) + "</body></html>\n")
        temporary = os.path.join(self.out_dir, f"index.html.tmp-{os.getpid()}")
        with open(temporary, "w", encoding="utf-8") as f:
            f.write(page)
        os.replace(temporary, os.path.join(self.out_dir, "index.html"))


def subplot_grid(count):
    columns = min(count, 3)
    rows = math.ceil(count / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 2.9 * rows), squeeze=False)
    for a in axes.flat[count:]:
        a.set_visible(False)
    return fig, list(axes.flat[:count])


def ensemble_quantity_figures(f, page, quantity, everything):
    stats = f["stats"][quantity]
    t = f["stats/time"][:]
    mean_set = stats["mean"]
    columns = strings(mean_set.attrs["columns"])
    groups, partial = select(groups_of(columns), everything)
    quantiles = stats["quantiles"]
    p = list(quantiles.attrs["probabilities"])
    pairs = [(i, p.index(1 - q)) for i, q in enumerate(p) if q < 0.5 and (1 - q) in p]
    nominal = f["nominal"][quantity] if quantity in f.get("nominal", {}) else None
    stored = f["trajectories"][quantity] if "trajectories" in f and quantity in f["trajectories"] else None
    for name, indices in groups:
        fig, axes = subplot_grid(len(indices))
        for ax, c in zip(axes, indices):
            m, s = mean_set[:, c], stats["std"][:, c]
            if stored is not None:
                for k in range(min(stored.shape[0], MAX_SPAGHETTI)):
                    ax.plot(t, stored[k, :, c], color="0.6", lw=0.5, alpha=0.6)
            for low, high in pairs:
                ax.fill_between(t, quantiles[low, :, c], quantiles[high, :, c], color="tab:orange", alpha=0.25,
                                lw=0, label=f"{p[low]:g}-{p[high]:g} quantiles")
            ax.fill_between(t, m - s, m + s, color="tab:blue", alpha=0.3, lw=0, label="mean ± std")
            ax.plot(t, m, color="tab:blue", lw=1.2, label="mean")
            ax.plot(t, stats["min"][:, c], "k:", lw=0.7, label="min / max")
            ax.plot(t, stats["max"][:, c], "k:", lw=0.7)
            if nominal is not None:
                ax.plot(t, nominal[:, c], color="tab:red", lw=0.9, ls="--", label="nominal")
            ax.set_title(columns[c], fontsize=9)
            ax.set_xlabel("t (s)")
            ax.set_ylabel(f"{quantity} ({units_of(mean_set, c)})")
        axes[0].legend(fontsize=7)
        page.figure(fig, f"{quantity} {name or ''}: mean ± std band, quantile fan, min/max, nominal"
                         + (", stored samples" if stored is not None else ""))
    if partial:
        page.paragraph(f"{quantity}: {len(groups)} of {len(groups_of(columns))} column groups shown; "
                       f"`treedyn report FILE --quantity {quantity}` draws all of them.")
    return groups


def histogram(ax, values, label, units):
    values = values[np.isfinite(values)]
    if values.size == 0:
        ax.text(0.5, 0.5, "no finite values", ha="center", transform=ax.transAxes)
    else:
        ax.hist(values, bins="auto" if values.size > 1 else 1, color="tab:blue", alpha=0.8)
    ax.set_xlabel(f"{label} ({units})")
    ax.set_ylabel("samples")


def final_value_histograms(f, page, quantity, groups):
    if "final" not in f["samples"] or quantity not in f["samples/final"]:
        return
    data = f["samples/final"][quantity]
    columns = strings(data.attrs["columns"])
    for name, indices in groups:
        fig, axes = subplot_grid(len(indices))
        for ax, c in zip(axes, indices):
            histogram(ax, data[:, c], columns[c], units_of(data, c))
        page.figure(fig, f"{quantity} {name}: histogram of the values at the last output time (per sample)")


def rare_event_section(f, page):
    """Subset simulation's answer: the probability, its cov and interval, the runs beside crude Monte Carlo's,
    and the exceedance curve its levels trace (P(g > b_j) = p0^(j+1) at each level's threshold)."""
    if "rare_event" not in f:
        return
    page.heading("Rare event (subset simulation)")
    for name, g in f["rare_event"].items():
        units = text(g.attrs["units"])
        side = ">" if text(g.attrs["fail_if"]) == "above" else "<"
        p, cov, runs = g["probability"][()], g["cov"][()], int(g["runs"][()])
        crude = g["crude_monte_carlo_runs"][()]
        page.table(["question", "answer"], [
            [f"P({name} {side} {g.attrs['limit']:.6g} {units})", f"{p:.4g}"],
            ["coefficient of variation (levels taken as uncorrelated)", f"{cov:.3g}"],
            ["95 % interval (lognormal with that cov)", f"[{g['interval'][0]:.4g}, {g['interval'][1]:.4g}]"],
            ["model runs (every proposal is a run)", f"{runs}"],
            ["crude Monte Carlo for the same cov, (1 - P) / (P cov²)", f"{crude:.3g}"],
            ["the threshold reached the limit", "yes" if int(g.attrs["reached_limit"]) else
             "no: max_levels ran out (raise it)"]])
        thresholds, conditional = g["thresholds"][:], g["conditional_probability"][:]
        page.table(["level", f"threshold ({units})", "conditional probability", "gamma", "acceptance rate", "runs"],
                   [[j, f"{thresholds[j]:.6g}", f"{conditional[j]:.4g}", f"{g['gamma'][j]:.3g}",
                     f"{g['acceptance_rate'][j]:.3g}", int(g["runs_per_level"][j])] for j in range(len(thresholds))])
        fig, ax = plt.subplots(figsize=(6, 3.5))
        ax.semilogy(thresholds, np.cumprod(conditional), "o-", color="tab:red")
        ax.set_xlabel(f"{name} ({units})")
        ax.set_ylabel(f"P({name} {side} threshold)")
        page.figure(fig, f"the exceedance curve the levels trace: at each level's threshold, the product of the "
                         f"conditional probabilities so far; the last point is the limit")


def response_figures(f, page):
    if "samples/responses" not in f:
        return
    values = f["samples/responses"]
    names = strings(values.attrs["columns"])
    units = strings(values.attrs["column_units"])
    rows = slice(None)
    counted = "every sample"
    if "samples/level" in f:  # subset simulation: level 0 is the Monte-Carlo sample
        rows = f["samples/level"][:] == 0
        counted = "level 0 of the subset simulation (its Monte-Carlo sample)"
    page.heading("Responses")
    fig, axes = subplot_grid(len(names))
    for r, ax in enumerate(axes):
        histogram(ax, values[:, r][rows], names[r], units[r])
        if "responses" in f and names[r] in f["responses"] and "exceedance" in f["responses"][names[r]]:
            ax.axvline(f["responses"][names[r]]["exceedance"].attrs["limit"], color="tab:red", ls="--", lw=1)
    page.figure(fig, f"histograms of the responses over {counted} (dashed: the limit)")
    if "responses" not in f:  # a merge of an incomplete set of parts
        page.paragraph("No /responses: the file holds only some of the samples (root attribute held_samples).")
        return
    rows = []
    for r, name in enumerate(names):
        g = f["responses"][name]
        e = g.get("exceedance")
        rows.append([name, f"{g['mean'][()]:.6g} ± {g['sem'][()]:.3g} {units[r]}", int(g["used"][()]),
                     int(g["failed"][()]),
                     "" if e is None else f"P = {e['probability'][()]:.4g} ({int(e['count'][()])} of "
                     f"{int(e['successful'][()])}), 95 % [{e['interval'][0]:.4g}, {e['interval'][1]:.4g}]"])
    page.table(["response", "mean ± standard error", "used", "failed", "exceedance of its limit"], rows)
    fig, axes = plt.subplots(len(names), 2, figsize=(10, 2.9 * len(names)), squeeze=False)
    for r in range(len(names)):
        c = f["responses"][names[r]]["convergence"][:]
        n, mean, sem = c[:, 0], c[:, 2], c[:, 3]
        ax = axes[r][0]
        ax.fill_between(n, mean - 2 * sem, mean + 2 * sem, color="tab:blue", alpha=0.3, lw=0)
        ax.plot(n, mean, "o-", color="tab:blue", ms=3)
        ax.set_xscale("log")
        ax.set_xlabel("samples")
        ax.set_ylabel(f"mean {names[r]} ({units[r]})", fontsize=8)
        ax = axes[r][1]
        if np.isfinite(c[:, 4]).any():
            ax.fill_between(n, c[:, 5], c[:, 6], color="tab:red", alpha=0.2, lw=0)
            ax.plot(n, c[:, 4], "s-", color="tab:red", ms=3)
            ax.set_xscale("log")
            ax.set_xlabel("samples")
            ax.set_ylabel(f"P({names[r]} limit exceeded)", fontsize=8)
        else:
            ax.set_visible(False)
    page.figure(fig, "convergence: each response's mean ± 2 standard errors (left) and the probability that it "
                     "exceeds its limit with its 95 % Wilson interval (right) against the number of samples")


def sensitivity_figures(f, page):
    if "sensitivity" not in f:
        return
    page.heading("Sensitivity")
    names = list(f["sensitivity"].keys())
    inputs = strings(f["sensitivity"][names[0]]["spearman"].attrs["columns"])
    rho = np.array([f["sensitivity"][n]["spearman"][:] for n in names])
    fig, ax = plt.subplots(figsize=(1.2 + 0.9 * len(names), 1.0 + 0.35 * len(inputs)))
    image = ax.imshow(rho.T, cmap="RdBu_r", vmin=-1, vmax=1, aspect="auto")
    ax.set_xticks(range(len(names)), names, rotation=45, ha="right", fontsize=8)
    ax.set_yticks(range(len(inputs)), inputs, fontsize=8)
    for i in range(len(names)):
        for j in range(len(inputs)):
            if np.isfinite(rho[i, j]):
                ax.text(i, j, f"{rho[i, j]:.2f}", ha="center", va="center", fontsize=7,
                        color="white" if abs(rho[i, j]) > 0.6 else "black")
    fig.colorbar(image, ax=ax, label="Spearman rank correlation")
    page.figure(fig, "Spearman rank correlation of every input (rows) with every response (columns)")
    for n in names:
        s = f["sensitivity"][n]
        if "total_order" not in s:
            continue
        first, total = s["first_order"][:], s["total_order"][:]
        first_ci, total_ci = s["first_order_ci"][:], s["total_order_ci"][:]
        order = np.argsort(-np.nan_to_num(total))[:20]
        fig, ax = plt.subplots(figsize=(7, 0.8 + 0.35 * len(order)))
        y = np.arange(len(order))
        for values, ci, shift, colour, label in ((first, first_ci, -0.2, "tab:blue", "first order"),
                                                 (total, total_ci, 0.2, "tab:orange", "total")):
            v = values[order]
            err = np.abs(np.array([v - ci[order, 0], ci[order, 1] - v]))
            ax.barh(y + shift, v, height=0.4, xerr=err, color=colour, label=label, capsize=2)
        ax.set_yticks(y, [inputs[i] for i in order], fontsize=8)
        ax.invert_yaxis()
        ax.set_xlabel("Sobol' index (95 % bootstrap interval)")
        ax.legend(fontsize=8)
        page.figure(fig, f"{n}: first-order and total Sobol' indices"
                         + (f" (top {len(order)} of {len(inputs)} inputs)" if len(inputs) > len(order) else ""))


def failed_table(f, page):
    status = f["samples/status"][:]
    failed = np.flatnonzero(status != 0)
    page.heading(f"Failed samples: {failed.size} of {status.size}")
    if failed.size == 0:
        return
    reason = f["samples/reason"]
    reached = f["samples/time_reached"]
    inputs = f["samples/inputs"] if "samples/inputs" in f else None
    names = strings(inputs.attrs["columns"]) if inputs is not None else []
    rows = []
    for k in failed[:MAX_FAILED_ROWS]:
        row = [int(k), int(status[k]), text(reason[k]), f"{reached[k]:.6g}"]
        if inputs is not None:
            row += [f"{v:.6g}" for v in inputs[k, :]]
        rows.append(row)
    page.table(["sample", "status", "reason", "time reached (s)"] + names, rows)
    if failed.size > MAX_FAILED_ROWS:
        page.paragraph(f"the first {MAX_FAILED_ROWS} shown; all are in /samples/status and /samples/reason")


PROVENANCE = ["start_utc", "end_utc", "host", "command_line", "job_path", "treedyn_version", "git_commit",
              "build_type", "compiler", "sundials_version", "hdf5_version", "eigen_version",
              "tomlplusplus_version", "mpi_library", "ranks", "rank_hosts"]


def provenance(f, page):
    page.heading("Provenance")
    rows = []
    for key in PROVENANCE:
        if key in f.attrs:
            v = f.attrs[key]
            rows.append([key, ", ".join(strings(v)) if isinstance(v, np.ndarray) else text(v)])
    page.table(["attribute", "value"], rows)


def trajectory_report(f, page, wanted):
    t = f["time"][:]
    if (not wanted or "joint_angle" in wanted) and "joint_angle" in f:
        d = f["joint_angle"]
        fig, ax = plt.subplots(figsize=(8, 3.5))
        names = strings(d.attrs["columns"])
        for c in range(min(d.shape[1], 10)):
            ax.plot(t, d[:, c], lw=0.9, label=names[c])
        ax.set_xlabel("t (s)")
        ax.set_ylabel(f"joint angle ({units_of(d)})")
        ax.legend(fontsize=7, ncol=2)
        page.figure(fig, "joint angles" + (f" (the first 10 of {d.shape[1]})" if d.shape[1] > 10 else ""))
    if (not wanted or "energy" in wanted) and "energy" in f:
        e = f["energy"]
        names = strings(e.attrs["columns"])
        fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.5))
        for c in range(e.shape[1]):
            a.plot(t, e[:, c], lw=0.9, label=names[c])
        a.set_xlabel("t (s)")
        a.set_ylabel(f"energy ({units_of(e)})")
        a.legend(fontsize=7)
        total = e[:, names.index("total")]
        b.plot(t, total - total[0], lw=0.9)
        b.set_xlabel("t (s)")
        b.set_ylabel(f"E(t) - E(0) ({units_of(e)})")
        page.figure(fig, "energy and its drift (a moving base, springs or dampers change it)")
    magnitude = None
    if "joint_reaction_magnitude" in f:
        magnitude = f["joint_reaction_magnitude"][:]
        names = strings(f["joint_reaction_magnitude"].attrs["columns"])
    elif "joint_reaction" in f:
        r = f["joint_reaction"][:]
        magnitude = np.linalg.norm(r.reshape(r.shape[0], -1, 3), axis=2)
        names = [c.rsplit(".", 1)[0] for c in strings(f["joint_reaction"].attrs["columns"])[::3]]
    if magnitude is not None and (not wanted or "joint_reaction" in wanted or "joint_reaction_magnitude" in wanted):
        fig, ax = plt.subplots(figsize=(8, 3.5))
        for c in range(min(magnitude.shape[1], 10)):
            ax.plot(t, magnitude[:, c], lw=0.9, label=names[c])
        ax.set_xlabel("t (s)")
        ax.set_ylabel("joint reaction magnitude (N)")
        ax.legend(fontsize=7, ncol=2)
        page.figure(fig, "magnitude of each joint's constraint force")
    paths = "point_position" if "point_position" in f else "com_position" if "com_position" in f else None
    if paths and (not wanted or paths in wanted):
        d = f[paths][:]
        names = strings(f[paths].attrs["columns"])
        fig, axes = plt.subplots(1, 3, figsize=(12, 3.8))
        for ax, (i, j, label) in zip(axes, ((0, 1, "x-y"), (0, 2, "x-z"), (1, 2, "y-z"))):
            for p in range(min(d.shape[1] // 3, 10)):
                ax.plot(d[:, 3 * p + i], d[:, 3 * p + j], lw=0.8, label=names[3 * p].rsplit(".", 1)[0])
            ax.set_xlabel(f"{'xyz'[i]} (m)")
            ax.set_ylabel(f"{'xyz'[j]} (m)")
            ax.set_title(label, fontsize=9)
            ax.set_aspect("equal", adjustable="datalim")
        axes[0].legend(fontsize=7)
        page.figure(fig, f"paths of the recorded {'points' if paths == 'point_position' else 'centres of mass'}, "
                         "three projections")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("file")
    parser.add_argument("--out", required=True)
    parser.add_argument("--quantity", action="append", default=[])
    a = parser.parse_args()
    try:
        f = h5py.File(a.file, "r")
    except OSError as e:
        fail(f"{a.file}: not an HDF5 file h5py can open ({e})")
    with f:
        title = text(f.attrs.get("title", "")) or os.path.basename(a.file)
        page = Page(a.out, f"treedyn report: {title}")
        summary_path = os.path.join(a.out, "summary.txt")
        if os.path.exists(summary_path):
            with open(summary_path, encoding="utf-8") as s:
                page.heading("Summary")
                page.pre(s.read())
        if "stats" in f:
            recorded = [text(q) for q in f["stats"].attrs["quantities"]] if "quantities" in f["stats"].attrs \
                else [q for q in f["stats"].keys() if q != "time"]
            for q in a.quantity:
                if q not in recorded:
                    fail(f"--quantity {q}: not recorded in {a.file}; recorded: {' '.join(recorded)}")
            rare_event_section(f, page)  # the answer first
            for q in a.quantity or recorded:
                page.heading(q)
                groups = ensemble_quantity_figures(f, page, q, bool(a.quantity))
                final_value_histograms(f, page, q, groups)
            response_figures(f, page)
            sensitivity_figures(f, page)
            failed_table(f, page)
        else:
            recorded = [k for k in f.keys() if isinstance(f[k], h5py.Dataset) and k not in ("time", "final_state")]
            recorded += [k for k in ("joint_reaction_magnitude",) if "joint_reaction" in f and k not in recorded]
            for q in a.quantity:
                if q not in recorded:
                    fail(f"--quantity {q}: not recorded in {a.file}; recorded: {' '.join(recorded)}")
            trajectory_report(f, page, set(a.quantity))
        provenance(f, page)
        try:
            page.write()
        except OSError as e:
            fail(f"{a.out}: cannot write the report ({e})", 4)
    say(f"wrote {os.path.join(a.out, 'index.html')} ({page.figures} figures)")


if __name__ == "__main__":
    main()
