"""The answers an analyst came for, first on the page: what the failed runs change, each response's mean and
probability of exceeding its limit with a verdict on N (and the design's own verdict), the ranked drivers
(drivers.py), what makes each response exceed its limit (failure_region.py), the warnings that matter,
input-vs-response scatter plots over every run, and the extreme and failed samples with the commands that
rerun them."""
import math
import shlex

import numpy as np

import matplotlib.pyplot as plt

from drivers import drivers_section
from failure_region import exceeded, failure_region_section
from page import legend_outside, subplot_grid
from rankings import primary_ranking, rank_ranking, visible_units
from designs import counted_rows, design_of
from read import column_units, fail_side, folded_note, held_rows, shown_inputs, strings, text

MEAN_PRECISION = 0.05         # "N is enough" for a mean: 95 % half-width within 5 % of |mean|
PROBABILITY_PRECISION = 0.20  # ... for P(exceeded): 95 % half-width within 20 % of P
LAST_TIME_SHARE = 0.1         # an extremum at the last output time in more runs than this: too short
SCATTER_DRIVERS = 4
EXTREME_ROWS = 5
POSITIVE_TARGETS = ("mass", "length", "inertia", "stiffness", "damping", "frequency")
NOT_RUN = 3  # /samples/status of a row a merge of some parts does not hold


def answers_section(f, page, file_name):
    """The opening section of an ensemble page."""
    page.heading("Answers")
    rows, counted = counted_rows(f)
    failure_banner(f, page)
    design_of(f).answer(f, page)
    if "samples/responses" not in f:
        page.paragraph("No [[ensemble.response]] in this job: name one (quantity, column, reduce, and a limit "
                       "for a probability) to get means, probabilities and drivers here.")
        return
    page.paragraph(f"Counted runs: {counted}.")
    if "stop_reason" in f.attrs and text(f.attrs["stop_reason"]):
        page.paragraph(f"Stopping rule: {text(f.attrs['stop_reason'])}.")
    response_table(f, page)
    for warning in last_time_warnings(f, rows) + outside_range_warnings(f):
        page.note(warning)
    drivers_section(f, page, rows)
    failure_region_section(f, page, rows, counted)
    design_of(f).after_failure_region(f, page)
    scatter_figures(f, page, rows)
    extreme_samples(f, page, file_name)


def failure_banner(f, page):
    status = f["samples/status"][:]
    not_run = int(np.count_nonzero(status == NOT_RUN))
    if not_run:
        page.note(f"{not_run} of {status.size} samples are not in this file (a merge of some parts: status 3); "
                  f"everything below counts the {status.size - not_run} it holds.")
    ran = status[status != NOT_RUN]
    failed = int(np.count_nonzero(ran != 0))
    if failed == 0:
        page.note(f"All {ran.size} samples integrated successfully.", "good")
        return
    share = failed / ran.size
    invalid = int(np.count_nonzero(ran == 2))
    words = (f"{failed} of {ran.size} samples failed ({share:.1%}): {failed - invalid} integrations failed, "
             f"{invalid} sampled models were invalid. Every statistic below counts the successful ones only, "
             f"so a failure that depends on the inputs biases them; see 'Failed samples' for why.")
    page.note(" ".join([words] + failure_effects(f)), "alarm" if share > 0.01 else "warning")


def failure_effects(f):
    """What the failed runs change: each P with the failed counted runs taken either way (the file's
    with_failed), and the design's own answers (the base points Saltelli's indices rest on)."""
    if "samples/responses" not in f or "responses" not in f:
        return []
    values = f["samples/responses"]
    names, units = strings(values.attrs["columns"]), column_units(values)
    design = design_of(f)
    out = []
    for r, name in enumerate(names):
        e = f["responses"][name].get("exceedance")
        if e is None or design.own_probability_group(f, name) is not None or int(e["failed"][()]) == 0 or \
                "with_failed" not in e:
            continue
        n, failed = int(e["successful"][()]), int(e["failed"][()])
        out.append(f"{probability_name(values, r, name, units[r])} = {e['probability'][()]:.4g} rests on {n} of "
                   f"{n + failed} counted runs; with the {failed} failed ones counted as not exceeding or as "
                   f"exceeding it would be {e['with_failed'][0]:.4g} to {e['with_failed'][1]:.4g}.")
    return out + design.failure_effects(f, names)


def probability_name(values, r, name, unit):
    side = ">" if fail_side(values, r) == "above" else "<"
    return f"P({name} {side} {values.attrs['limit'][r]:.6g} {unit})"


def mean_verdict(mean, sem, used, per_used=1.0):
    """`per_used`: counted runs per run with a finite value (a response that is often +inf, never crossed)."""
    if used < 10 or not np.isfinite(sem):
        return f"no: {used} runs with a finite value"
    half = 1.96 * sem
    if mean == 0:
        return f"no relative precision (the mean is 0): ±{half:.3g} (95 %)"
    if half <= MEAN_PRECISION * abs(mean):
        return f"yes: ±{half / abs(mean):.1%} (95 %)"
    need = math.ceil(per_used * used * (half / (MEAN_PRECISION * abs(mean))) ** 2)
    return f"not for ±{MEAN_PRECISION:.0%}: ±{half / abs(mean):.0%} now; about {need} counted runs would do"


def probability_verdict(count, n, p, low, high):
    if n == 0:
        return "no successful run"
    if count == 0:
        return f"no exceedance in {n} runs: P < {high:.2g} (95 %); for a smaller P use subset simulation"
    half = (high - low) / 2
    if half <= PROBABILITY_PRECISION * p:
        return f"yes: ±{half / p:.0%} (95 %)"
    need = math.ceil(n * (half / (PROBABILITY_PRECISION * p)) ** 2)
    return (f"not for ±{PROBABILITY_PRECISION:.0%}: ±{half / p:.0%} now ({count} exceedances); about {need} counted "
            f"runs would do")


def response_table(f, page):
    values = f["samples/responses"]
    names, units = strings(values.attrs["columns"]), column_units(values)
    if "responses" not in f:
        page.paragraph("No /responses: the file holds only some of the samples (root attribute held_samples).")
        return
    sensitivity = [f["sensitivity"][n] if "sensitivity" in f and n in f["sensitivity"] else None for n in names]
    own = design_of(f).verdict_column(f, sensitivity)
    accuracy = integration_verdicts(f)
    table = [response_row(f, values, r, name, units[r]) + ([own.verdict(sensitivity[r])] if own else []) +
             ([accuracy[r]] if accuracy else []) for r, name in enumerate(names)]
    page.table(["response", "mean ± standard error", "runs used", f"is N enough for the mean "
                f"(±{MEAN_PRECISION:.0%})?", "probability of exceeding the limit (Wilson interval)",
                f"is N enough for P (±{PROBABILITY_PRECISION:.0%})?"] + ([own.header] if own else []) +
               (["is the integration accurate enough?"] if accuracy else []), table)
    meaning = design_of(f).counted_runs_meaning(f)
    if meaning:
        page.paragraph(meaning)
    for r, verdict in enumerate(accuracy):
        if verdict.startswith("too loose"):
            page.note(f"{names[r]}: the integration is {verdict}.", "alarm")
    if accuracy:
        g = f["integration_check"]
        page.paragraph(f"The integration check: pilot samples {', '.join(str(k) for k in g['samples'][:])} run "
                       f"again with rtol {float(g.attrs['rerun_rtol']):.0e} and atol {float(g.attrs['rerun_atol']):.0e}"
                       f" (the job's {float(g.attrs['rtol']):.0e} and {float(g.attrs['atol']):.0e}); each response's "
                       "largest change against its spread over the pilot: above 0.1 too loose, below 0.001 far "
                       "tighter than the answer needs.")


def response_row(f, values, r, name, unit):
    g = f["responses"][name]
    mean, sem, used = g["mean"][()], g["sem"][()], int(g["used"][()])
    infinite = int(g["not_finite"][()]) if "not_finite" in g else 0
    runs = f"{used} ({int(g['failed'][()])} failed" + (f", {infinite} not finite: never crossed, not in the mean)"
                                                       if infinite else ")")
    row = [name, f"{mean:.6g} ± {sem:.3g} {unit}" + (" (over the finite ones)" if infinite else ""), runs,
           mean_verdict(mean, sem, used, (used + infinite) / used if used else 1.0), "", ""]
    e = g.get("exceedance")
    design = design_of(f)
    own = design.own_probability_group(f, name) if e is not None else None
    if own is not None:  # the design's P is the answer, not the counted runs' exceedance
        row[4] = (f"{probability_name(values, r, name, unit)} = {own['probability'][()]:.4g}: "
                  f"{design.own_probability_words(f)}")
        row[5] = f"cov {own['cov'][()]:.3g}, 95 % [{own['interval'][0]:.3g}, {own['interval'][1]:.3g}]"
    elif e is not None:
        p, count, n = e["probability"][()], int(e["count"][()]), int(e["successful"][()])
        low, high = e["interval"][0], e["interval"][1]
        row[4] = (f"{probability_name(values, r, name, unit)} = {p:.4g} ({count} of {n}), 95 % [{low:.3g}, "
                  f"{high:.3g}]")
        if int(e["failed"][()]) and "with_failed" in e:
            row[4] += (f"; with the {int(e['failed'][()])} failed runs counted either way: "
                       f"{e['with_failed'][0]:.4g} to {e['with_failed'][1]:.4g}")
        row[5] = probability_verdict(count, n, p, low, high)
    return row


def integration_verdicts(f):
    """Per response, what the pilot's tolerance check says (/integration_check, as the text summary words it);
    empty when the file has none."""
    if "integration_check" not in f:
        return []
    return strings(f["integration_check"].attrs["verdicts"])


def last_time_warnings(f, rows):
    """A max/min response whose extremum comes at the last output time in many runs: the run is too short."""
    values = f["samples/responses"]
    out = []
    last = f["stats/time"][-1]
    for r, name in enumerate(strings(values.attrs["columns"])):
        reduce = text(values.attrs["reduce"][r])
        if reduce not in ("max", "min"):
            continue
        quantity, column = text(values.attrs["quantity"][r]), text(values.attrs["column"][r])
        group = f"samples/arg{reduce}_time"
        if group not in f or quantity not in f[group]:
            continue
        data = f[group][quantity]
        c = strings(data.attrs["columns"]).index(column)
        times = data[:, c][rows]
        times = times[np.isfinite(times)]
        at_end = int(np.count_nonzero(times >= last))
        if times.size and at_end > LAST_TIME_SHARE * times.size:
            out.append(f"{name}: in {at_end} of {times.size} runs the {reduce}imum of {quantity} {column} comes at "
                       f"the last output time (t = {last:g} s), so it may still be growing: the run is too short "
                       f"for this response (lengthen [output] end_time).")
    return out


def outside_range_warnings(f):
    """Normal marginals on a quantity that must be positive: their mass at or below zero."""
    if "samples/inputs" not in f or "column_distributions" not in f["samples/inputs"].attrs:
        return []
    d = f["samples/inputs"]
    modes = strings(d.attrs["column_modes"]) if "column_modes" in d.attrs else ["set"] * d.shape[1]
    out = []
    for name, law, mode in zip(strings(d.attrs["columns"]), strings(d.attrs["column_distributions"]), modes):
        # 'set' and 'scale' (a factor of the nominal value) must stay positive; an 'add' offset need not
        if mode not in ("set", "scale") or not law.startswith("normal(") or \
                not name.split(".")[-1].startswith(POSITIVE_TARGETS):
            continue
        fields = dict(part.split("=") for part in law[len("normal("):law.index(")")].split(", "))
        mean, std = float(fields["mean"]), float(fields["std"])
        p = 0.5 * math.erfc(mean / (std * math.sqrt(2)))
        if p > 1e-9:
            out.append(f"{name}: its distribution {law} puts P = {p:.2g} at or below zero, where the model is "
                       f"invalid (those samples fail as invalid models); a truncated_normal or lognormal avoids it.")
    return out


def scatter_inputs(f, name):
    """A response's strongest inputs one by one: the single inputs of the design's own ranking, then the rest
    by the rank measure."""
    s, inputs = f["sensitivity"][name], f["samples/inputs"]
    names = strings(inputs.attrs["columns"])
    primary, ranks = primary_ranking(s, names), rank_ranking(s, names)
    visible, rank_visible = set(visible_units(primary, inputs)), set(visible_units(ranks, inputs))
    order = [primary.members[int(u)][0] for u in primary.order
             if int(u) in visible and len(primary.members[int(u)]) == 1]
    order += [int(i) for i in ranks.order if int(i) in rank_visible and int(i) not in order]
    return order[:SCATTER_DRIVERS]


def scatter_figures(f, page, rows):
    """Each response against its strongest inputs, over every run the file holds (so every run of the
    extremes table is inside the axes): by level where the design's runs go in levels (/samples/level:
    subset simulation), else the counted runs and the others apart, in the design's words."""
    if "sensitivity" not in f or "samples/inputs" not in f:
        return
    values = f["samples/responses"]
    names, units = strings(values.attrs["columns"]), column_units(values)
    inputs = f["samples/inputs"][:]
    input_names, input_units = strings(f["samples/inputs"].attrs["columns"]), column_units(f["samples/inputs"])
    status, held = f["samples/status"][:], held_rows(f)
    level = f["samples/level"][:] if "samples/level" in f else None
    for r, name in enumerate(names):
        order = scatter_inputs(f, name) if name in f["sensitivity"] else []
        if not order:
            continue
        y = values[:, r]
        fig, axes = subplot_grid(len(order), width=3.6, height=2.8, columns=4)
        for ax, i in zip(axes, order):
            if level is not None:
                level_scatter(ax, inputs[:, i], y, status, held, level)
            else:
                run_scatter(ax, inputs[:, i], y, status, (rows & held, held & ~rows), exceeded(values, r, y),
                            other_runs(f)[1])
            if np.isfinite(values.attrs["limit"][r]):
                ax.axhline(values.attrs["limit"][r], color="tab:red", ls="--", lw=0.8, label="limit")
            ax.set_xlabel(f"{input_names[i]} ({input_units[i]})", fontsize=8)
            ax.set_ylabel(f"{name} ({units[r]})", fontsize=8)
        legend_outside(axes)
        failed = bool((held & (status != 0)).any())
        page.figure(fig, scatter_caption(f, name, len(order), (rows & held, held & ~rows), failed), f"scatter_{name}")


def scatter_caption(f, name, count, sets, failed):
    counted, others = sets
    runs = (f"every run of every level ({int((counted | others).sum())}), coloured by level (level 0: the "
            "Monte-Carlo sample; level j: the chains beyond level j - 1's threshold)" if "samples/level" in f else
            f"the {int(counted.sum())} counted runs (dots)" +
            (f" and the {int(others.sum())} {other_runs(f)[0]}" if others.any() else ""))
    return f"{name} against its {count} strongest inputs: {runs}" + ("; failed runs drawn at the bottom of the axes"
                                                                    if failed else "")


def other_runs(f):
    """The runs beside the counted ones, for a caption and for a legend label."""
    return design_of(f).other_runs_legend(f)


def drawn_range(y, ok):
    return (float(np.min(y[ok])), float(np.max(y[ok]))) if ok.any() else (0.0, 1.0)


def run_scatter(ax, x, y, status, sets, beyond, other_label):
    """The counted runs as dots, the others (+) fainter; blue ok, red beyond the limit."""
    ok, infinite, failed = (status == 0) & np.isfinite(y), (status == 0) & np.isinf(y), (status != 0) & (status != 3)
    low, high = drawn_range(y, ok & (sets[0] | sets[1]))
    for rows, marker, alpha, words in ((sets[0], ".", 1.0, ""), (sets[1], "+", 0.45, other_label)):
        if not rows.any():
            continue
        ax.plot(x[rows & ok & ~beyond], y[rows & ok & ~beyond], marker, color="tab:blue", ms=4, alpha=alpha,
                label="ok" + words)
        if (rows & ok & beyond).any():
            ax.plot(x[rows & ok & beyond], y[rows & ok & beyond], marker, color="tab:red", ms=5, alpha=alpha,
                    label="limit exceeded" + words)
    shown = sets[0] | sets[1]
    if (infinite & shown).any():
        ax.plot(x[infinite & shown], np.full(int((infinite & shown).sum()), high), "^", color="tab:green", ms=4,
                label="not finite, e.g. never crossed (drawn at the top)")
    if (failed & shown).any():
        ax.plot(x[failed & shown], np.full(int((failed & shown).sum()), low), "x", color="0.3", ms=5,
                label="failed (drawn at the bottom)")


def level_scatter(ax, x, y, status, held, level):
    """Subset simulation: every run, coloured by its level."""
    ok = held & (status == 0) & np.isfinite(y)
    levels = np.unique(level[held])
    colours = plt.get_cmap("viridis", max(len(levels), 2))
    for k, j in enumerate(levels):
        m = ok & (level == j)
        ax.plot(x[m], y[m], ".", color=colours(k), ms=3, label=f"level {j}")
    failed = held & (status != 0)
    if failed.any():
        ax.plot(x[failed], np.full(int(failed.sum()), drawn_range(y, ok)[0]), "x", color="0.3", ms=5,
                label="failed (drawn at the bottom)")


def rerun_commands(f, file_name, k):
    job = shlex.quote(text(f.attrs.get("job_path", "JOB.toml")))
    source = f" --from {shlex.quote(file_name)}" if "samples/level" in f and f["samples/level"][k] > 0 else ""
    return (f"treedyn-ensemble {job} --sample {k}{source} -o sample_{k}.h5",
            f"treedyn-ensemble {job} --write-job {k}{source} -o sample_{k}.toml")


def extreme_samples(f, page, file_name):
    """The top runs of each response towards its limit (every run counts here) and the failed ones."""
    values = f["samples/responses"]
    names, units = strings(values.attrs["columns"]), column_units(values)
    shown, folded = shown_inputs(f["samples/inputs"]) if "samples/inputs" in f else ([], {})
    inputs = f["samples/inputs"][:][:, shown] if "samples/inputs" in f else np.zeros((values.shape[0], 0))
    input_names = [f"{strings(f['samples/inputs'].attrs['columns'])[i]} ({column_units(f['samples/inputs'])[i]})"
                   for i in shown] if "samples/inputs" in f else []
    status = f["samples/status"][:]
    level = f["samples/level"][:] if "samples/level" in f else None
    page.heading("Extreme and failed samples", 3)
    page.paragraph("Every run counts here (" + design_of(f).every_run_words(f) + ": each is a real sample). The "
                   "commands rerun one sample alone, bit for bit, or write it as a standalone job.")
    table = []
    for r, name in enumerate(names):
        y = np.where(status == 0, values[:, r], np.nan)
        toward = fail_side(values, r) or "above"
        finite = np.flatnonzero(np.isfinite(y))
        picks = finite[np.argsort(-y[finite] if toward == "above" else y[finite], kind="stable")][:EXTREME_ROWS]
        for k in picks:
            why = f"{'largest' if toward == 'above' else 'smallest'} {name}" + \
                  (f" (level {level[k]})" if level is not None else "")
            table.append(extreme_row(f, file_name, k, why, f"{y[k]:.6g} {units[r]}", inputs[k]))
    for k in np.flatnonzero((status == 1) | (status == 2))[:EXTREME_ROWS]:
        table.append(extreme_row(f, file_name, k, "failed", text(f["samples/reason"][k]), inputs[k]))
    page.table(["sample", "why listed", "value (with its unit) or reason"] + input_names + ["rerun alone", "as a job"],
               table, code_columns=(3 + len(input_names), 4 + len(input_names)))
    if folded:
        page.paragraph(folded_note(folded))


def extreme_row(f, file_name, k, why, value, inputs):
    rerun, job = rerun_commands(f, file_name, int(k))
    return [int(k), why, value] + [f"{v:.6g}" for v in inputs] + [rerun, job]
