"""Saltelli's design: blocks of U + 2 runs (A, B and one AB run per unit), of which A and B are independent
draws, and its Sobol' indices drawn per response: bars of the first-order and total indices with their 95 %
intervals (a group as one bar), and the indices of the first m base points against m
(/sensitivity/<r>/sobol_convergence) with their interval bands. Estimates and intervals are drawn within [0, 1]:
an index is a share of variance."""
import numpy as np

import matplotlib.pyplot as plt

from designs import base
from drivers import TABLE_ROWS, correlation_note, folded_members, interval_text
from rankings import has_sobol, sobol_ranking, visible_units
from read import folded_note, shown_inputs, strings, text

MAX_BARS = 12
MAX_LINES = 5
COLOURS = plt.rcParams["axes.prop_cycle"].by_key()["color"]
RELIABLE_SHARE = 0.8  # the file's sobol_reliable: at least this share of the base points complete
INDEX_INTERVAL = 0.1  # N is enough for the indices where the widest total-index interval of a unit that matters
                      # is within this


def counted_rows(f, held, note):
    if "saltelli_block" not in f.attrs:
        return base.counted_rows(f, held, note)
    rows = (np.arange(held.size) % int(f.attrs["saltelli_block"]) < 2) & held
    return rows, (f"the {int(rows.sum())} independent runs of the {held.size} (the A and B runs of the Saltelli "
                  f"design; its AB runs repeat A's inputs but one){note}")


def counted_runs_meaning(f):
    if "saltelli_block" not in f.attrs:
        return ""
    block = int(f.attrs["saltelli_block"])
    return (f"For this Saltelli design K counted runs are samples = K / 2 base points, that is K / 2 x {block} "
            f"model runs.")


def other_runs_words(f, others):
    return f"the {others} AB runs (A's inputs with one from B: real samples, not independent draws)"


def evidence(f, page):
    index_figures(f, page)


def other_runs_legend(f):
    return "AB runs (+: A's inputs with one from B, in the extremes table too)", ", AB run"


def every_run_words(f):
    return "the AB runs too"


def measure_words(f):
    return ("The total Sobol' index is the share of the response's variance that goes with an input, its "
            "interactions included;")


def folded_words(f):
    return " Their effect together is a group's Sobol' index where the job groups them ([[ensemble.group]])."


def correlated_inputs_words(f):
    return "read the SRRC or the Sobol' indices instead."


def has_own_ranking(s):
    return has_sobol(s)


def own_ranking_words(s, ranking):
    return f"from {int(s.attrs.get('sobol_base_samples', 0))} of {int(s.attrs.get('sobol_blocks', 0))} base points"


def own_measure_words():
    return base.MeasureWords("the total Sobol' index", "over the A and B runs", "the share of the response's "
                             "variance that goes with the input, its interactions and non-monotone effects included",
                             "its Sobol' index", "Sobol'")


def reliable(s):
    return int(s.attrs.get("sobol_reliable", 1)) != 0


def unreliable_words(s):
    return unreliable_text(s) if has_sobol(s) and not reliable(s) else ""


def unreliable_text(s):
    return (f"failed runs left {int(s.attrs['sobol_base_samples'])} of {int(s.attrs['sobol_blocks'])} base points "
            f"complete (fewer than {100 * RELIABLE_SHARE:.0f} %); failures that depend on the inputs bias what remains")


def failure_effects(f, names):
    """The base points the Sobol' indices rest on, said once when every response's are the same."""
    said = {}
    for name in names:
        s = f["sensitivity"][name] if "sensitivity" in f and name in f["sensitivity"] else None
        if s is None or "sobol_blocks" not in s.attrs:
            continue
        base_points, blocks = int(s.attrs["sobol_base_samples"]), int(s.attrs["sobol_blocks"])
        if base_points < blocks:
            said.setdefault((base_points, blocks, reliable(s)), []).append(name)
    block = int(f.attrs.get("saltelli_block", 0))
    return ["The Sobol' indices" + (f" of {', '.join(who)}" if len(said) > 1 else "") +
            f" rest on {base_points} of {blocks} base points (a base point counts when all its {block} runs "
            "succeeded)" + (f"; unreliable: fewer than {100 * RELIABLE_SHARE:.0f} %." if not ok else ".")
            for (base_points, blocks, ok), who in said.items()]


def verdict_column(f, sensitivity):
    if not any(s is not None and has_sobol(s) for s in sensitivity):
        return None
    return base.VerdictColumn(f"is N enough for the Sobol' indices (intervals within {INDEX_INTERVAL})?",
                              index_verdict)


def index_verdict(s):
    """Whether N is enough for the Sobol' indices, as the file's attributes say (the text summary's verdict)."""
    if s is None or "sobol_blocks" not in s.attrs:
        return ""
    widest, unit = float(s.attrs["index_widest_interval"]), text(s.attrs.get("index_widest_unit", ""))
    blocks = f" (from {int(s.attrs['sobol_base_samples'])} of {int(s.attrs['sobol_blocks'])} base points)"
    unreliable = "" if reliable(s) else unreliable_text(s)
    if not np.isfinite(widest):
        words = "no interval of a total index that matters (no bootstrap, or no complete block)" + blocks
        return f"no: unreliable, {unreliable}; {words}" if unreliable else f"no verdict: {words}"
    words = f"the widest total-index interval of an input that matters is {widest:.2g} ({unit})"
    more = f"; about {float(s.attrs['index_base_points_needed']):.0f} base points would do"
    if unreliable:
        return f"no: unreliable, {unreliable}; {words}" + ("" if int(s.attrs["indices_enough"]) else more)
    if int(s.attrs["indices_enough"]):
        return f"yes: {words}" + blocks
    return f"not for {INDEX_INTERVAL}: {words}{more}" + blocks


def ranking_table(page, name, s, sobol, visible, ranks, correlations):
    """The total and first-order indices per input or group, beside the rank measures (a response whose indices
    this file does not hold gets the rank measures' table)."""
    if not has_sobol(s):
        return False
    sobol_table(page, s, sobol, visible, ranks, correlations)
    return True


def sobol_table(page, s, sobol, visible, ranks, correlations):
    grouped = "group_total_order" in s
    first, first_ci = sobol_first(s)
    header = ["input or group" if grouped else "input"] + (["its inputs"] if grouped else []) + \
             ["total Sobol' [95 %]", "first order [95 %]", f"{ranks.measure} [95 %]", "Spearman", "note"]
    table = []
    for u in [int(u) for u in sobol.order if int(u) in set(visible)][:TABLE_ROWS]:
        members = sobol.members[u]
        row = [sobol.units[u]] + ([folded_members(members, ranks.units)] if grouped else [])
        row += [interval_text(sobol.value[u], sobol.ci[u]),
                first_order_cell(first[u], first_ci[u], sobol.value[u], sobol.ci[u])]
        if len(members) == 1:
            i = members[0]
            row += [interval_text(ranks.value[i], ranks.ci[i]), f"{s['spearman'][i]:.3f}",
                    correlation_note(i, ranks.units, correlations)]
        else:
            row += ["(a group: its inputs one by one are not ranked)", "", ""]
        table.append(row)
    page.table(header, table)
    for words in index_notes(sobol, visible, first, first_ci):
        page.paragraph(words)


def index_notes(sobol, visible, first, first_ci):
    """Why a first-order index above its total one, or an estimate outside [0, 1], is read as noise."""
    out = []
    above = [u for u in visible if np.isfinite(first[u]) and first[u] > sobol.value[u]]
    noise = [sobol.units[u] for u in above if first_ci[u][0] <= sobol.ci[u][1]]
    beyond = [sobol.units[u] for u in above if first_ci[u][0] > sobol.ci[u][1]]
    if noise:
        out.append(f"First order above total ({', '.join(noise)}): within noise. Where an input does not interact, "
                   "both estimate the same share of variance, and here their difference lies within their "
                   "intervals: read both as about the total index.")
    if beyond:
        out.append(f"First order above total beyond their intervals ({', '.join(beyond)}): the estimates disagree "
                   "more than the bootstrap allows; more base points are needed before reading these first-order "
                   "indices.")
    outside = [f"{sobol.units[u]} {sobol.value[u]:.2g}" for u in visible
               if np.isfinite(sobol.value[u]) and not 0 <= sobol.value[u] <= 1]
    if outside:
        out.append(f"An estimate outside [0, 1] ({', '.join(outside)}) is estimation noise: an index is a share of "
                   "variance; its interval, clipped to [0, 1], is what the data say.")
    return out


def first_order_cell(first, first_ci, total, total_ci):
    """A first-order index above its total one (they estimate the same share where nothing interacts) is
    within noise where the intervals overlap."""
    cell = interval_text(first, first_ci)
    if np.isfinite(first) and np.isfinite(total) and first > total:
        overlap = first_ci[0] <= total_ci[1]
        cell += ": within noise of the total" if overlap else ": above the total beyond the intervals"
    return cell


def sobol_first(s):
    key = "group_first_order" if "group_total_order" in s else "first_order"
    return s[key][:], s[key + "_ci"][:]


def index_figures(f, page):
    if "sensitivity" not in f or "samples/inputs" not in f or "samples/responses" not in f:
        return
    inputs = f["samples/inputs"]
    names = strings(inputs.attrs["columns"])
    _, folded = shown_inputs(inputs) if "column_targets" in inputs.attrs else ([], {})
    for name in [r for r in strings(f["samples/responses"].attrs["columns"]) if r in f["sensitivity"]]:
        s = f["sensitivity"][name]
        if not has_sobol(s):
            continue
        sobol = sobol_ranking(s, names)
        visible = set(visible_units(sobol, inputs))
        units = [int(u) for u in sobol.order if int(u) in visible][:MAX_BARS]
        convergence = s.get("sobol_convergence")
        fig, axes = plt.subplots(1, 2 if convergence is not None else 1, figsize=(12, 1.8 + 0.42 * len(units)),
                                 squeeze=False, layout="constrained")
        index_bars(axes[0][0], sobol, sobol_first(s), units)
        if convergence is not None:
            index_convergence(axes[0][1], convergence, sobol, units[:MAX_LINES])
        grouped = " (a group as one bar)" if "group_total_order" in s else ""
        page.figure(fig, f"{name}: left, the total (dark) and first-order (light) Sobol' indices{grouped} with their "
                         f"95 % bootstrap intervals, from {int(s.attrs.get('sobol_base_samples', 0))} of "
                         f"{int(s.attrs.get('sobol_blocks', 0))} base points; "
                    + ("right, the indices of the first m base points (their complete blocks) against m: total "
                       "solid with its interval as a band, first order dashed; " if convergence is not None else "")
                    + "estimates and intervals drawn within [0, 1], the estimate written beside its bar"
                    + (". " + folded_note(folded) if folded and not grouped else ""), f"sobol_indices_{name}")


def clipped_errors(v, ci):
    """Estimate and asymmetric error bars, all within [0, 1] (no bar where the interval is unknown)."""
    point = np.clip(v, 0.0, 1.0)
    low, high = np.clip(ci[:, 0], 0.0, 1.0), np.clip(ci[:, 1], 0.0, 1.0)
    errors = np.vstack([np.maximum(point - low, 0.0), np.maximum(high - point, 0.0)])
    return point, np.nan_to_num(errors, nan=0.0)


def index_bars(ax, sobol, first, units):
    y = np.arange(len(units))[::-1]
    for offset, (v, ci), label, alpha in ((-0.2, (sobol.value, sobol.ci), "total", 0.9),
                                         (0.2, first, "first order", 0.45)):
        point, errors = clipped_errors(v[units], ci[units])
        ax.barh(y - offset, np.nan_to_num(point), height=0.38, color="tab:blue", alpha=alpha, label=label,
                xerr=errors, error_kw={"ecolor": "0.2", "capsize": 2, "lw": 0.8})
        for yk, value, top in zip(y - offset, v[units], point + errors[1]):
            if np.isfinite(value):
                ax.text(min(np.nan_to_num(top), 1.0) + 0.02, yk, f"{value:.2g}", va="center", fontsize=7)
    ax.set_yticks(y, [sobol.units[u] for u in units], fontsize=8)
    ax.set_xlim(0, 1.15)
    ax.set_xlabel("Sobol' index (share of the response's variance)", fontsize=8)
    ax.legend(fontsize=7, loc="lower right")


def index_convergence(ax, g, sobol, units):
    m = g["base_points"][:]
    columns = strings(g["total_order"].attrs["columns"])
    total, total_ci, first = g["total_order"][:], g["total_order_ci"][:], g["first_order"][:]
    for k, u in enumerate(units):
        c = columns.index(sobol.units[u])
        colour = COLOURS[k % len(COLOURS)]
        ax.fill_between(m, np.clip(total_ci[:, c, 0], 0, 1), np.clip(total_ci[:, c, 1], 0, 1), color=colour,
                        alpha=0.15, lw=0)
        ax.plot(m, np.clip(total[:, c], 0, 1), "o-", color=colour, ms=3, label=sobol.units[u])
        ax.plot(m, np.clip(first[:, c], 0, 1), "--", color=colour, lw=0.9)
    ax.set_xscale("log", base=2)
    ax.set_ylim(0, 1.02)
    ax.set_xlabel("base points m (the first m)", fontsize=8)
    ax.set_ylabel("Sobol' index", fontsize=8)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
