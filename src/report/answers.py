"""The answers an analyst came for, first on the page: each response's mean and
probability of exceeding its limit with a verdict on N, the ranked drivers,
the warnings that matter, input-vs-response scatter plots and the extreme and
failed samples with the commands that rerun them."""
import math
import re
import shlex

import numpy as np

from page import legend_outside, subplot_grid
from read import counted_rows, fail_side, folded_note, shown_inputs, strings, text

MEAN_PRECISION = 0.05         # "N is enough" for a mean: 95 % half-width within 5 % of |mean|
PROBABILITY_PRECISION = 0.20  # ... for P(exceeded): 95 % half-width within 20 % of P
CORRELATED_INPUTS = 0.2       # |Spearman| between two inputs above which their rank measures mix
LAST_TIME_SHARE = 0.1         # an extremum at the last output time in more runs than this: too short
TOP_DRIVERS = 10
SCATTER_DRIVERS = 4
EXTREME_ROWS = 5
POSITIVE_TARGETS = ("mass", "length", "inertia", "stiffness", "damping", "frequency")
NOT_RUN = 3  # /samples/status of a row a merge of some parts does not hold


def answers_section(f, page, file_name):
    """The opening section of an ensemble page."""
    page.heading("Answers")
    rows, counted = counted_rows(f)
    failure_banner(f, page)
    if "samples/responses" not in f:
        page.paragraph("No [[ensemble.response]] in this job: name one (quantity, column, reduce, and a limit "
                       "for a probability) to get means, probabilities and drivers here.")
        return
    page.paragraph(f"Counted runs: {counted}.")
    if "stop_reason" in f.attrs and text(f.attrs["stop_reason"]):
        page.paragraph(f"Stopping rule: {text(f.attrs['stop_reason'])}.")
    response_table(f, page, rows)
    for warning in last_time_warnings(f, rows) + outside_range_warnings(f):
        page.note(warning)
    drivers(f, page, rows)
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
    page.note(words, "alarm" if share > 0.01 else "warning")


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


def counted_runs_meaning(f):
    """What a number of counted runs means for the job's `samples`, said once under the table."""
    design = text(f.attrs.get("design", ""))
    if design == "saltelli" and "saltelli_block" in f.attrs:
        block = int(f.attrs["saltelli_block"])
        return (f"For this Saltelli design K counted runs are samples = K / 2 base points, that is K / 2 x {block} "
                f"model runs.")
    if design in ("sobol", "latin_hypercube"):
        return (f"The verdicts take the runs as independent; the {design} design's stratification usually makes "
                f"the estimates better than that.")
    return ""


def response_table(f, page, rows):
    values = f["samples/responses"]
    names, units = strings(values.attrs["columns"]), strings(values.attrs["column_units"])
    if "responses" not in f:
        page.paragraph("No /responses: the file holds only some of the samples (root attribute held_samples).")
        return
    table = []
    for r, name in enumerate(names):
        g = f["responses"][name]
        mean, sem, used = g["mean"][()], g["sem"][()], int(g["used"][()])
        infinite = int(g["not_finite"][()]) if "not_finite" in g else 0
        runs = f"{used} ({int(g['failed'][()])} failed" + (f", {infinite} not finite: never crossed, not in the mean)"
                                                           if infinite else ")")
        row = [name, f"{mean:.6g} ± {sem:.3g} {units[r]}" + (" (over the finite ones)" if infinite else ""), runs,
               mean_verdict(mean, sem, used, (used + infinite) / used if used else 1.0), "", ""]
        e = g.get("exceedance")
        if e is not None:
            side = ">" if fail_side(values, r) == "above" else "<"
            p, count, n = e["probability"][()], int(e["count"][()]), int(e["successful"][()])
            low, high = e["interval"][0], e["interval"][1]
            row[4] = (f"P({name} {side} {values.attrs['limit'][r]:.6g} {units[r]}) = {p:.4g} ({count} of {n}), "
                      f"95 % [{low:.3g}, {high:.3g}]")
            row[5] = probability_verdict(count, n, p, low, high)
        table.append(row)
    page.table(["response", "mean ± standard error", "runs used", f"is N enough for the mean "
                f"(±{MEAN_PRECISION:.0%})?", "probability of exceeding the limit (Wilson interval)",
                f"is N enough for P (±{PROBABILITY_PRECISION:.0%})?"], table)
    if counted_runs_meaning(f):
        page.paragraph(counted_runs_meaning(f))


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


def ranks(x):
    order = np.argsort(x, kind="stable")
    r = np.empty(x.size)
    r[order] = np.arange(x.size)
    return r


def input_correlations(f, rows):
    """Pairs of inputs whose Spearman correlation in the counted successful runs is large."""
    inputs = f["samples/inputs"][:][rows]
    ok = (f["samples/status"][:][rows] == 0) & np.all(np.isfinite(inputs), axis=1)
    names = strings(f["samples/inputs"].attrs["columns"])
    shown, _ = shown_inputs(f["samples/inputs"])  # a list's entries (random phases) are not read one by one
    if ok.sum() < 4 or not shown:
        return {}, names, int(ok.sum())
    ranked = np.array([ranks(inputs[ok, i]) for i in shown])
    rho = np.corrcoef(ranked) if len(shown) > 1 else np.ones((1, 1))
    pairs = {}
    for a, i in enumerate(shown):
        for b in range(a + 1, len(shown)):
            j = shown[b]
            if abs(rho[a, b]) >= CORRELATED_INPUTS:
                pairs.setdefault(i, []).append((j, rho[a, b]))
                pairs.setdefault(j, []).append((i, rho[a, b]))
    return pairs, names, int(ok.sum())


def per_input_sobol(s):
    """Whether the per-input Sobol' indices are there: a grouped design has them per group."""
    return "total_order" in s and "group_total_order" not in s


def ranking(s):
    """The per-input key of the ranking and its name: the total Sobol' index where there is one per input,
    else |SRRC|, else (more inputs than runs leave the rank regression undetermined) |Spearman|."""
    if per_input_sobol(s):
        return s["total_order"][:], "total Sobol' index"
    if np.isfinite(s["srrc"][:]).any():
        return np.abs(s["srrc"][:]), "|SRRC|"
    return np.abs(s["spearman"][:]), "|Spearman|"


def driver_order(s, shown=None):
    """Inputs ranked by ranking(s), only those in `shown` when given."""
    key, _ = ranking(s)
    order = np.argsort(-np.nan_to_num(key, nan=-1.0), kind="stable")
    return order if shown is None else np.array([i for i in order if i in set(shown)], dtype=int)


def asked_correlations(f):
    """The input pairs the job correlates on purpose ([[ensemble.correlation]]), as written in the file
    ("A ~ B: normal copula rho, Spearman r")."""
    return strings(f["samples/inputs"].attrs.get("correlated_pairs", []))


def asked_pair(asked, a, b):
    return any(set(text.split(": ")[0].split(" ~ ")) == {a, b} for text in asked)


def group_drivers(page, name, s):
    """A grouped Saltelli design: one total and first-order index per group of inputs taken together."""
    groups = strings(s["group_total_order"].attrs["columns"])
    members = strings(s.attrs.get("group_inputs", [""] * len(groups)))
    total, first = s["group_total_order"][:], s["group_first_order"][:]
    order = np.argsort(-np.nan_to_num(total, nan=-1.0), kind="stable")
    strong = [i for i in order if np.isfinite(total[i]) and total[i] >= 0.05]
    words = f"{name} is driven by " + (", ".join(f"{groups[i]} (total Sobol' index {total[i]:.2g})" for i in strong)
                                       if strong else "no single group")
    weak = [groups[i] for i in order if i not in strong]
    if weak:
        words += f"; {', '.join(weak)} matter little (total Sobol' index below 0.05)"
    page.note(words + " (groups: the inputs of each taken together).", "good")
    page.table(["group", "its inputs", "total Sobol' [95 %]", "first order [95 %]"],
               [[groups[i], folded_members(members[i]), interval(total[i], s["group_total_order_ci"][i]),
                 interval(first[i], s["group_first_order_ci"][i])] for i in order])


def folded_members(members):
    """'base.z.phases[1], ..., base.z.phases[64]' as 'base.z.phases[1..64]': a list's entries in one name."""
    out, runs = [], {}
    for name in members.split(", "):
        m = re.fullmatch(r"(.*)\[(\d+)\]", name)
        if m:
            if m.group(1) not in runs:
                out.append(m.group(1))
            runs.setdefault(m.group(1), []).append(int(m.group(2)))
        else:
            out.append(name)
    return ", ".join(f"{n}[{min(runs[n])}..{max(runs[n])}]" if n in runs and len(runs[n]) > 1 else
                     (f"{n}[{runs[n][0]}]" if n in runs else n) for n in out)


def interval(v, ci):
    return f"{v:.3g} [{ci[0]:.3g}, {ci[1]:.3g}]" if np.isfinite(v) else "n/a"


def conclusion(name, s, order, names):
    """One sentence: what drives the response, and what does not matter."""
    key, measure = ranking(s)
    strong = [i for i in order if np.isfinite(key[i]) and key[i] >= 0.05]
    weak = [names[i] for i in order if i not in strong]
    words = f"{name} is driven by " + (", ".join(f"{names[i]} ({measure} {key[i]:.2g})" for i in strong)
                                       if strong else "no single input")
    if weak:
        words += f"; {', '.join(weak)} matter little ({measure} below 0.05)"
    return words + "."


def drivers(f, page, rows):
    if "sensitivity" not in f:
        return
    pairs, names, n = input_correlations(f, rows)
    page.heading("Which inputs drive each response", 3)
    page.paragraph("Ranked by the total Sobol' index where the design gives one (the share of the response's "
                   "variance that goes away if the input were known), else by the standardised rank regression "
                   "coefficient (SRRC: the input's own effect with the others held fixed). Spearman's rank "
                   "correlation is each input alone; with inputs correlated in the sample it mixes their effects.")
    asked = asked_correlations(f)
    if asked:
        page.note("Inputs correlated on purpose by the job ([[ensemble.correlation]], a normal copula on each "
                  "input's own distribution): " + "; ".join(asked) + ". Their Spearman coefficients below mix "
                  "each other's effects; the SRRC separate them.")
    shown, folded = shown_inputs(f["samples/inputs"])
    if folded:
        page.note("Per input below: the inputs one by one. " + folded_note(folded) + " Their effect together is "
                  "the group's Sobol' index where the job groups them ([[ensemble.group]]).")
    responses = strings(f["samples/responses"].attrs["columns"])
    for name in [r for r in responses if r in f["sensitivity"]]:
        s = f["sensitivity"][name]
        order = driver_order(s, shown)[:TOP_DRIVERS]
        sobol = per_input_sobol(s)
        r2 = s.attrs.get("rank_r_squared", float("nan"))
        if "group_total_order" in s:
            group_drivers(page, name, s)
        page.note(conclusion(name, s, order, names), "good")
        header = ["input"] + (["total Sobol' [95 %]", "first order [95 %]"] if sobol else []) + \
                 ["SRRC", "Spearman", "note"]
        table = []
        for i in order:
            row = [names[i]]
            if sobol:
                row += [interval(s["total_order"][i], s["total_order_ci"][i]),
                        interval(s["first_order"][i], s["first_order_ci"][i])]
            chance = 2 / math.sqrt(n - 1) if n > 1 else 1.0
            note = "; ".join(f"correlated with {names[j]} in these runs (rho = {rho:.2f}; "
                             + ("asked by the job)" if asked_pair(asked, names[i], names[j]) else
                                f"chance alone gives |rho| up to about {chance:.2f} at n = {n})")
                             for j, rho in pairs.get(i, []))
            row += [f"{s['srrc'][i]:.3f}", f"{s['spearman'][i]:.3f}", note]
            table.append(row)
        used = int(s.attrs.get("rank_samples", n))
        if np.isfinite(r2):
            page.paragraph(f"{name}: rank R² = {r2:.2f} over {used} runs (how much of the response's rank variance "
                           f"the SRRC explain; near 1 the ranking by SRRC is trustworthy).")
        else:
            page.paragraph(f"{name}: no rank regression (SRRC, R²): it needs more runs than inputs ({len(names)} "
                           f"inputs, {used} runs), or an input or the response is constant; the inputs are ranked "
                           f"by Spearman alone.")
        if r2 < 0.7 and "total_order" not in s:
            page.note(f"{name}: the SRRC explain only {r2:.0%} of its rank variance: the response is not monotone "
                      f"in the inputs or they interact, so this ranking is uncertain; a saltelli design gives "
                      f"Sobol' indices that do not assume monotonicity.")
        page.table(header, table)
    if pairs:
        page.note(f"Some inputs are correlated in the sample (|rho| >= {CORRELATED_INPUTS}, see the notes): their "
                  "Spearman coefficients mix each other's effects; read the SRRC or the Sobol' indices instead.")


def scatter_figures(f, page, rows):
    """Each response against its strongest inputs: ok, exceeded and failed runs in three colours."""
    if "sensitivity" not in f or "samples/inputs" not in f:
        return
    values = f["samples/responses"]
    names, units = strings(values.attrs["columns"]), strings(values.attrs["column_units"])
    inputs = f["samples/inputs"][:][rows]
    input_names = strings(f["samples/inputs"].attrs["columns"])
    input_units = strings(f["samples/inputs"].attrs["column_units"])
    status = f["samples/status"][:][rows]
    for r, name in enumerate(names):
        if name not in f["sensitivity"]:
            continue
        y = values[:, r][rows]
        order = driver_order(f["sensitivity"][name], shown_inputs(f["samples/inputs"])[0])[:SCATTER_DRIVERS]
        exceeded = exceeded_mask(values, r, y)
        ok = (status == 0) & np.isfinite(y)
        infinite = (status == 0) & ~np.isfinite(y)
        failed = status != 0
        low, high = (np.min(y[ok]), np.max(y[ok])) if ok.any() else (0.0, 1.0)
        fig, axes = subplot_grid(len(order), width=3.6, height=2.8, columns=4)
        for ax, i in zip(axes, order):
            x = inputs[:, i]
            ax.plot(x[ok & ~exceeded], y[ok & ~exceeded], ".", color="tab:blue", ms=4, label="ok")
            if exceeded.any():
                ax.plot(x[ok & exceeded], y[ok & exceeded], ".", color="tab:red", ms=5, label="limit exceeded")
            if infinite.any():
                ax.plot(x[infinite], np.full(infinite.sum(), high), "^", color="tab:green", ms=4,
                        label="not finite, e.g. never crossed (drawn at the top)")
            if failed.any():
                ax.plot(x[failed], np.full(failed.sum(), low), "x", color="0.3", ms=5,
                        label="failed (drawn at the bottom)")
            limit = values.attrs["limit"][r]
            if np.isfinite(limit):
                ax.axhline(limit, color="tab:red", ls="--", lw=0.8, label="limit")
            ax.set_xlabel(f"{input_names[i]} ({input_units[i]})", fontsize=8)
            ax.set_ylabel(f"{name} ({units[r]})", fontsize=8)
        legend_outside(axes)
        page.figure(fig, f"{name} against its {len(order)} strongest inputs, over the counted runs",
                    f"scatter_{name}")


def exceeded_mask(values, r, y):
    limit = values.attrs["limit"][r]
    if not np.isfinite(limit):
        return np.zeros(y.size, dtype=bool)
    with np.errstate(invalid="ignore"):
        return y > limit if fail_side(values, r) == "above" else y < limit


def rerun_commands(f, file_name, k):
    job = shlex.quote(text(f.attrs.get("job_path", "JOB.toml")))
    source = f" --from {shlex.quote(file_name)}" if "samples/level" in f and f["samples/level"][k] > 0 else ""
    return (f"treedyn-ensemble {job} --sample {k}{source} -o sample_{k}.h5",
            f"treedyn-ensemble {job} --write-job {k}{source} -o sample_{k}.toml")


def extreme_samples(f, page, file_name):
    """The top runs of each response towards its limit (every run counts here) and the failed ones."""
    values = f["samples/responses"]
    names = strings(values.attrs["columns"])
    shown, folded = shown_inputs(f["samples/inputs"]) if "samples/inputs" in f else ([], {})
    inputs = f["samples/inputs"][:][:, shown] if "samples/inputs" in f else np.zeros((values.shape[0], 0))
    input_names = [strings(f["samples/inputs"].attrs["columns"])[i] for i in shown] if "samples/inputs" in f else []
    status = f["samples/status"][:]
    page.heading("Extreme and failed samples", 3)
    page.paragraph("Every run counts here (for Saltelli designs the AB runs too: each is a real sample). "
                   "The commands rerun one sample alone, bit for bit, or write it as a standalone job.")
    table = []
    for r, name in enumerate(names):
        y = np.where(status == 0, values[:, r], np.nan)
        toward = fail_side(values, r) or "above"
        finite = np.flatnonzero(np.isfinite(y))
        picks = finite[np.argsort(-y[finite] if toward == "above" else y[finite], kind="stable")][:EXTREME_ROWS]
        for k in picks:
            table.append(extreme_row(f, file_name, k, f"{'largest' if toward == 'above' else 'smallest'} {name}",
                                     f"{y[k]:.6g}", inputs[k]))
    for k in np.flatnonzero((status == 1) | (status == 2))[:EXTREME_ROWS]:
        table.append(extreme_row(f, file_name, k, "failed", text(f["samples/reason"][k]), inputs[k]))
    page.table(["sample", "why listed", "value or reason"] + input_names + ["rerun alone", "as a job"], table,
               code_columns=(3 + len(input_names), 4 + len(input_names)))
    if folded:
        page.paragraph(folded_note(folded))


def extreme_row(f, file_name, k, why, value, inputs):
    rerun, job = rerun_commands(f, file_name, int(k))
    return [int(k), why, value] + [f"{v:.6g}" for v in inputs] + [rerun, job]
