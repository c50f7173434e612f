"""Which inputs drive each response: one sentence per response from the design's own ranking where it has one
(else |SRRC| or |Spearman|) that orders two inputs only where the bootstrap tells them apart, the measures with
their intervals (the design's own table, else the rank measures'), and one note where the rank measures and the
design's own measure rank differently. What the design's measure is, and its words, come from its module in
designs/."""
import math
import re

import numpy as np

from rankings import clipped, driven_by, primary_ranking, rank_ranking, top_unit, value_text, visible_units
from designs import design_of
from read import folded_note, shown_inputs, strings

CORRELATED_INPUTS = 0.2  # |Spearman| between two inputs above which their rank measures mix
TABLE_ROWS = 20


def drivers_section(f, page, rows):
    if "sensitivity" not in f or "samples/inputs" not in f or "samples/responses" not in f:
        return
    inputs = f["samples/inputs"]
    design = design_of(f)
    page.heading("Which inputs drive each response", 3)
    page.paragraph(" ".join(w for w in (
        "An order (A > B) is stated only where the 95 % bootstrap interval of the difference excludes 0; A ~ B: not "
        "told apart yet.", design.measure_words(f), "|SRRC| and |Spearman| measure how monotonically the response's "
        "ranks follow the input's (SRRC: the others held fixed).") if w))
    asked = asked_correlations(f)
    if asked:
        page.note("Inputs correlated on purpose by the job ([[ensemble.correlation]], a normal copula on each "
                  "input's own distribution): " + "; ".join(asked) + ". Their Spearman coefficients below mix "
                  "each other's effects; the SRRC separate them.")
    _, folded = shown_inputs(inputs) if "column_targets" in inputs.attrs else ([], {})
    if folded:
        page.paragraph(folded_note(folded) + design.folded_words(f))
    correlations = input_correlations(f, rows)
    no_regression = set()
    for name in [r for r in strings(f["samples/responses"].attrs["columns"]) if r in f["sensitivity"]]:
        no_regression.add(response_drivers(page, name, f["sensitivity"][name], inputs, correlations, asked,
                                           design.ranked_runs_words(f), design))
    for line in sorted(no_regression - {""}):  # said once: it is about the design, not a response
        page.paragraph(line)
    if correlations[0]:
        page.note(f"Some inputs are correlated in the {correlations[1]} counted runs (|rho| >= {CORRELATED_INPUTS}, "
                  "see the notes): their Spearman coefficients mix each other's effects; "
                  + design.correlated_inputs_words(f))


def where_words(s, ranking, design, runs_of=""):
    """Which runs a ranking rests on: the design's words for its own ranking; for the rank measures', `runs_of`
    names them where they are not all (a subset simulation's level 0)."""
    own = design.own_ranking_words(s, ranking) if ranking.word != "runs" else ""
    return own or f"over {runs_of}{int(s.attrs.get('rank_samples', 0))} runs"


def response_drivers(page, name, s, inputs, correlations, asked, runs_of, design):
    """The sentence, the table and the notes of one response; returns why there is no rank regression ('' when
    there is one)."""
    names = strings(inputs.attrs["columns"])
    primary = primary_ranking(s, names)
    visible = visible_units(primary, inputs)
    words = driven_by(name, primary, visible, where_words(s, primary, design, runs_of))
    unreliable = design.unreliable_words(s)
    if unreliable:
        page.note(f"Unreliable: {unreliable}. {words}", "alarm")
    else:
        page.note(words, "good")
    ranks = rank_ranking(s, names)
    if not design.ranking_table(page, name, s, primary, visible, ranks, (correlations, asked)):
        rank_table(page, s, ranks, visible, (correlations, asked))
    own = design.has_own_ranking(s)
    if own:
        disagreement = disagreement_note(name, primary, visible, ranks, visible_units(ranks, inputs),
                                         design.own_measure_words())
        if disagreement:
            page.note(disagreement)
    line = rank_regression_line(name, s, own)
    if line:
        page.paragraph(line)
    return no_regression_line(s, len(names))


def interval_text(v, ci):
    if not np.isfinite(v):
        return "n/a"
    return f"{v:.3g}" + (f" [{clipped(ci[0]):.3g}, {clipped(ci[1]):.3g}]" if np.isfinite(ci[0]) else "")


def disagreement_note(name, primary, visible, ranks, rank_visible, own_words):
    """One note where the two rankings (the design's own and the rank measure's) put a different unit first,
    saying what each measures (`own_words`: the design's, designs/base.py: own_measure_words)."""
    top, rank_top = top_unit(primary, visible), top_unit(ranks, rank_visible)
    if own_words is None or top is None or rank_top is None or primary.members[top] == [rank_top]:
        return ""
    by, runs, meaning, its, which = own_words
    group = (f" {primary.units[top]} is a group: its inputs one by one show little in a rank measure, its effect "
             f"together only in {its}." if len(primary.members[top]) > 1 else "")
    return (f"{name}: the rank measures put another input first: {value_text(ranks, rank_top)} by "
            f"{ranks.measure}, {value_text(primary, top)} by {by}. They measure different things: "
            f"{ranks.measure} how monotonically the response's ranks follow one input's, {runs}; {by} {meaning}."
            + group + f" The ranking above is the {which} one.")


def rank_table(page, s, ranks, visible, correlations):
    header = ["input", f"{ranks.measure} [95 %]", "SRRC", "Spearman", "note"]
    table = [[ranks.units[i], interval_text(ranks.value[i], ranks.ci[i]), f"{s['srrc'][i]:.3f}",
              f"{s['spearman'][i]:.3f}", correlation_note(i, ranks.units, correlations)]
             for i in [int(i) for i in ranks.order if int(i) in set(visible)][:TABLE_ROWS]]
    page.table(header, table)


def no_regression_line(s, inputs):
    r2, used = s.attrs.get("rank_r_squared", float("nan")), int(s.attrs.get("rank_samples", 0))
    if np.isfinite(r2):
        return ""
    return (f"No rank regression (SRRC, R²): it needs more runs than inputs ({inputs} inputs, {used} runs), or an "
            "input or the response is constant; the rank measure is then Spearman's.")


def rank_regression_line(name, s, own):
    """How far the rank regression can be trusted ('' where there is none, or the design's own measure
    ranks)."""
    r2, used = s.attrs.get("rank_r_squared", float("nan")), int(s.attrs.get("rank_samples", 0))
    if own or not np.isfinite(r2):
        return ""
    line = (f"{name}: rank R² = {r2:.2f} over {used} runs (how much of the response's rank variance the SRRC "
            "explain; near 1 the ranking by SRRC is trustworthy).")
    if r2 < 0.7:
        line += (f" Only {r2:.0%}: the response is not monotone in the inputs or they interact, so this ranking is "
                 "uncertain; a saltelli design gives Sobol' indices that do not assume monotonicity.")
    return line


def folded_members(members, input_names):
    """'base.z.phases[1], ..., base.z.phases[64]' as 'base.z.phases[1..64]': a list's entries in one name."""
    out, runs = [], {}
    for name in (input_names[i] for i in members):
        m = re.fullmatch(r"(.*)\[(\d+)\]", name)
        if not m:
            out.append(name)
            continue
        if m.group(1) not in runs:
            out.append(m.group(1))
        runs.setdefault(m.group(1), []).append(int(m.group(2)))
    return ", ".join(f"{n}[{min(runs[n])}..{max(runs[n])}]" if n in runs and len(runs[n]) > 1 else
                     (f"{n}[{runs[n][0]}]" if n in runs else n) for n in out)


def ranks_of(x):
    order = np.argsort(x, kind="stable")
    r = np.empty(x.size)
    r[order] = np.arange(x.size)
    return r


def input_correlations(f, rows):
    """Pairs of inputs whose Spearman correlation in the counted successful runs is large, and how many runs."""
    inputs = f["samples/inputs"][:][rows]
    ok = (f["samples/status"][:][rows] == 0) & np.all(np.isfinite(inputs), axis=1)
    shown, _ = shown_inputs(f["samples/inputs"]) if "column_targets" in f["samples/inputs"].attrs else \
        (list(range(inputs.shape[1])), {})
    if ok.sum() < 4 or not shown:
        return {}, int(ok.sum())
    ranked = np.array([ranks_of(inputs[ok, i]) for i in shown])
    rho = np.corrcoef(ranked) if len(shown) > 1 else np.ones((1, 1))
    pairs = {}
    for a, i in enumerate(shown):
        for b in range(a + 1, len(shown)):
            if abs(rho[a, b]) >= CORRELATED_INPUTS:
                pairs.setdefault(i, []).append((shown[b], rho[a, b]))
                pairs.setdefault(shown[b], []).append((i, rho[a, b]))
    return pairs, int(ok.sum())


def correlation_note(i, names, correlations):
    (pairs, n), asked = correlations
    chance = 2 / math.sqrt(n - 1) if n > 1 else 1.0
    return "; ".join(f"correlated with {names[j]} in these runs (rho = {rho:.2f}; "
                     + ("asked by the job)" if asked_pair(asked, names[i], names[j]) else
                        f"chance alone gives |rho| up to about {chance:.2f} at n = {n})")
                     for j, rho in pairs.get(i, []))


def asked_correlations(f):
    """The input pairs the job correlates on purpose ([[ensemble.correlation]]), as written in the file
    ("A ~ B: normal copula rho, Spearman r")."""
    return strings(f["samples/inputs"].attrs.get("correlated_pairs", []))


def asked_pair(asked, a, b):
    return any(set(words.split(": ")[0].split(" ~ ")) == {a, b} for words in asked)
