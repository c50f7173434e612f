"""The rankings the file stores (/sensitivity/<r>/sobol_ranking, morris_ranking and rank_ranking) read as one
shape, and what they allow a reader to say: "A > B" only where the bootstrap tells the two apart, else that they
cannot yet be told apart and about how many more base points, trajectories or runs would."""
from collections import namedtuple

import numpy as np

from read import shown_inputs, strings, text

NEGLIGIBLE = 0.05  # an input matters little only where its interval's upper end is below this
TOP_UNITS = 10     # units named in a "driven by" sentence

# units: names; members: each unit's input indices (one for an input, several for a group); value, ci: the
# measure and its 95 % interval per unit (ci NaN without a bootstrap); order: units, largest first;
# told_apart, needed: per neighbour pair in that order; word: what `needed` counts; share: the measure is a
# share in [0, 1] (a Sobol' index, a rank coefficient: shown clipped to it, negligible below NEGLIGIBLE), not a
# size in the response's units (Morris mu*).
Ranking = namedtuple("Ranking", "measure units members value ci order told_apart needed resamples word share",
                     defaults=(True,))
# One unit of a ranking as a reader is told it: whether the bootstrap tells it from the unit before it in
# the sentence, and about how many base points or runs would where it does not.
Link = namedtuple("Link", "unit apart needed")


def has_sobol(s):
    return "total_order" in s or "group_total_order" in s


def has_morris(s):
    return "morris_mu_star" in s


def group_members(s, input_names, key="group_inputs"):
    """Each group's input indices, from the attribute `key` ("a, b, c" per group)."""
    index = {n: i for i, n in enumerate(input_names)}
    return [[index[n] for n in members.split(", ") if n in index] for members in strings(s.attrs[key])]


def sobol_ranking(s, input_names):
    """The total Sobol' indices' ranking: per group in a grouped design, else per input."""
    grouped = "group_total_order" in s
    key = "group_total_order" if grouped else "total_order"
    units = strings(s[key].attrs["columns"]) if "columns" in s[key].attrs else list(input_names)
    members = group_members(s, input_names) if grouped else [[i] for i in range(len(units))]
    return stored_ranking(s.get("sobol_ranking"), "total Sobol' index", units, members, s[key][:],
                          s[key + "_ci"][:], "base points")


def morris_ranking(s, input_names):
    """Morris' ranking by mu* over its factors (an input, or a group of inputs moved together), in the
    response's units per unit of u."""
    units = strings(s["morris_mu_star"].attrs["columns"])
    members = group_members(s, input_names, "morris_unit_inputs") if "morris_unit_inputs" in s.attrs else \
        [[list(input_names).index(u)] if u in input_names else [] for u in units]
    ranking = stored_ranking(s.get("morris_ranking"), "Morris mu*", units, members, s["morris_mu_star"][:],
                             s["morris_mu_star_ci"][:], "trajectories")
    return ranking._replace(share=False)


def rank_ranking(s, input_names):
    """|SRRC| where the rank regression could be computed (more runs than inputs), else |Spearman|."""
    g = s.get("rank_ranking")
    srrc = np.abs(s["srrc"][:])
    measure = text(g.attrs["measure"]) if g is not None else ("|SRRC|" if np.isfinite(srrc).any() else "|Spearman|")
    value = srrc if measure == "|SRRC|" else np.abs(s["spearman"][:])
    ci = s["rank_measure_ci"][:] if "rank_measure_ci" in s else np.full((value.size, 2), np.nan)
    return stored_ranking(g, measure, list(input_names), [[i] for i in range(value.size)], value, ci, "runs")


def stored_ranking(g, measure, units, members, value, ci, word):
    """A ranking group as stored; without one (a file from before the rankings), the point estimates' order
    with nothing told apart."""
    if g is None:
        order = np.argsort(-np.nan_to_num(value, nan=-1.0), kind="stable")
        pairs = max(len(units) - 1, 0)
        return Ranking(measure, units, members, value, ci, order, np.zeros(pairs, dtype=bool),
                       np.full(pairs, np.nan), 0, word)
    return Ranking(measure, units, members, value, ci, g["order"][:], g["told_apart"][:].astype(bool),
                   g["needed"][:], int(g.attrs.get("resamples", 0)), word)


def primary_ranking(s, input_names):
    """The design's own ranking: Sobol' where there is one (saltelli), Morris' mu* (morris), else the rank
    measure's."""
    if has_sobol(s):
        return sobol_ranking(s, input_names)
    return morris_ranking(s, input_names) if has_morris(s) else rank_ranking(s, input_names)


def visible_units(ranking, inputs):
    """Units a reader sees one by one: groups, and inputs that are not a list's entries (a sea state's 64
    phases are one input to a reader; one by one they are noise)."""
    shown = set(shown_inputs(inputs)[0]) if "column_targets" in inputs.attrs else set(range(inputs.shape[1]))
    return [u for u in range(len(ranking.units)) if len(ranking.members[u]) != 1 or ranking.members[u][0] in shown]


def negligible(ranking, u):
    """A share whose interval ends below NEGLIGIBLE; a size in the response's units (mu*) never is: what is
    small there is the reader's call."""
    return bool(ranking.share and np.isfinite(ranking.ci[u][1]) and ranking.ci[u][1] < NEGLIGIBLE)


def chain(ranking, visible):
    """The visible units that matter, largest first. Two of them are told apart where any neighbour pair
    between them in the full order is (the units left out between them, list entries or negligible ones,
    sit in between); about as many samples as the least of those pairs needs would tell them apart."""
    position = {int(u): k for k, u in enumerate(ranking.order)}
    kept = [int(u) for u in ranking.order if int(u) in set(visible) and not negligible(ranking, int(u))]
    links = []
    for previous, u in zip([None] + kept, kept):
        if previous is None:
            links.append(Link(u, True, np.nan))
            continue
        between = slice(position[previous], position[u])
        needed = ranking.needed[between]
        needed = needed[~np.isnan(needed)]
        links.append(Link(u, bool(ranking.told_apart[between].any()), float(needed.min()) if needed.size else np.nan))
    return links


def clipped(v):
    return min(max(v, 0.0), 1.0)


def value_text(ranking, u):
    """'name 0.84 [0.53, 1]': the estimate, and its interval shown within [0, 1] for a share (as the text
    summary; mu* as it is, to 3 digits: 'name 6.41e+03 [6.32e+03, 6.51e+03]')."""
    v, (low, high) = ranking.value[u], ranking.ci[u]
    if not ranking.share:
        return f"{ranking.units[u]} {v:.3g}" + (f" [{low:.3g}, {high:.3g}]" if np.isfinite(low) else "")
    words = f"{ranking.units[u]} {v:.2g}"
    return words + (f" [{clipped(low):.2g}, {clipped(high):.2g}]" if np.isfinite(low) else "")


def needed_words(link, word):
    if np.isinf(link.needed):
        return f" (their estimates are equal: more {word} would not tell them apart)"
    return f" (about {link.needed:.0f} {word} would tell them apart)" if np.isfinite(link.needed) else ""


def driven_by(name, ranking, visible, where):
    """The one sentence a reader takes away: the order only where the bootstrap states it."""
    links = chain(ranking, visible)
    if not links:
        return (f"{name} is driven by no single input: every {ranking.measure}'s 95 % interval ends below "
                f"{NEGLIGIBLE} ({where}).")
    shown = links[:TOP_UNITS]
    bootstrap = ranking.resamples > 0
    words = f"{name} is driven by " + value_text(ranking, shown[0].unit)
    for link in shown[1:]:
        words += (" > " if link.apart else " ~ ") if bootstrap else ", "
        words += value_text(ranking, link.unit)
    more = f", and {len(links) - len(shown)} more" if len(links) > len(shown) else ""
    words += f" ({ranking.measure}" + (" [95 %]" if bootstrap else "") + f", {where}{more})."
    if not bootstrap:
        return words + " No bootstrap intervals (bootstrap_resamples = 0): the order is the estimates' alone."
    for before, link in zip(shown, shown[1:]):
        if not link.apart:
            words += (f" {ranking.units[before.unit]} and {ranking.units[link.unit]} cannot yet be told apart"
                      + needed_words(link, ranking.word) + ".")
    little = [ranking.units[u] for u in ranking.order if int(u) in set(visible) and negligible(ranking, int(u))]
    if little:
        words += (f" {', '.join(little)} matter{'s' if len(little) == 1 else ''} little (the 95 % interval of the "
                  f"{ranking.measure} ends below {NEGLIGIBLE}).")
    return words


def top_unit(ranking, visible):
    """The first visible unit in the order, or None."""
    return next((int(u) for u in ranking.order if int(u) in set(visible)), None)
