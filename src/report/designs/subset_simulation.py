"""Subset simulation: level 0 is a Monte-Carlo sample (its runs are the counted ones), the levels after it are
chains beyond each level's threshold. Its answer: the probability, its cov and interval, the runs beside crude
Monte Carlo's (first, in the answers), and the levels with the exceedance curve they trace (P(g > b_j) =
p0^(j+1) at each level's threshold), after what makes the response exceed its limit."""
import numpy as np

import matplotlib.pyplot as plt

from designs import base
from read import text


def counted_rows(f, held, note):
    if "samples/level" not in f:
        return base.counted_rows(f, held, note)
    rows = f["samples/level"][:] == 0
    return rows, f"level 0 of the subset simulation, its Monte-Carlo sample ({int(rows.sum())} runs)"


def other_runs_words(f, others):
    return f"the {others} runs of levels 1 and up (chains beyond each level's threshold, not draws of the inputs)"


def answer(f, page):
    rare_event_answer(f, page)


def every_run_words(f):
    return "every level's runs too"


def ranked_runs_words(f):
    return "level 0's " if "samples/level" in f else ""


def own_probability_group(f, name):
    """Its response's P is the levels' answer: level 0 alone (the counted runs) rarely reaches the limit."""
    return f["rare_event"][name] if "rare_event" in f and name in f["rare_event"] else None


def own_probability_words(f):
    return "the subset simulation's, above (level 0 alone is not the answer)"


def own_failure_region(f, name):
    """Every level's runs beyond the limit: each is a draw of the inputs given the failure."""
    g = own_probability_group(f, name)
    if g is None or "failure_region" not in g or "samples/level" not in f:
        return None
    level0 = f["samples/level"][:] == 0
    failed = int(round(float(np.nansum(g["failed_per_level"][:])))) if "failed_per_level" in g else 0
    return base.OwnRegion(g["failure_region"], "runs beyond the limit, any level of the subset simulation", failed,
                          level0, f"level 0, the Monte-Carlo sample, {int(level0.sum())} runs")


def after_failure_region(f, page):
    rare_event_levels(f, page)


def rare_event_answer(f, page):
    if "rare_event" not in f:
        return
    page.heading("Rare event (subset simulation)", 3)
    for name, g in f["rare_event"].items():
        answer_table(page, name, g)
        if int(g.attrs.get("no_threshold", 0)):
            page.note("The last level has no threshold (N (1 - p0) or more of its runs failed, or its responses "
                      "pile up at one value): the estimate counts that level's exceedances and may be far off; see "
                      "'Failed samples'.", "alarm")


def rare_event_levels(f, page):
    if "rare_event" not in f:
        return
    for name, g in f["rare_event"].items():
        page.heading(f"The subset simulation's levels ({name})", 3)
        units, side = text(g.attrs["units"]), ">" if text(g.attrs["fail_if"]) == "above" else "<"
        thresholds, conditional = g["thresholds"][:], g["conditional_probability"][:]
        failed = g["failed_per_level"][:] if "failed_per_level" in g else np.zeros(len(thresholds))
        page.table(["level", f"threshold ({units})", "conditional probability", "gamma", "acceptance rate", "runs",
                    "failed runs"],
                   [[j, f"{thresholds[j]:.6g}", f"{conditional[j]:.4g}", f"{g['gamma'][j]:.3g}",
                     f"{g['acceptance_rate'][j]:.3g}", int(g["runs_per_level"][j]), int(failed[j])]
                    for j in range(len(thresholds))])
        fig, ax = plt.subplots(figsize=(6, 3.5), layout="constrained")
        ax.semilogy(thresholds, np.cumprod(conditional), "o-", color="tab:red")
        ax.set_xlabel(f"{name} ({units})")
        ax.set_ylabel(f"P({name} {side} threshold)")
        page.figure(fig, "the exceedance curve the levels trace: at each level's threshold, the product of the "
                         "conditional probabilities so far; the last point is the limit", f"rare_event_{name}")


def answer_table(page, name, g):
    units, side = text(g.attrs["units"]), ">" if text(g.attrs["fail_if"]) == "above" else "<"
    p, cov, runs = g["probability"][()], g["cov"][()], int(g["runs"][()])
    page.table(["question", "answer"], [
        [f"P({name} {side} {g.attrs['limit']:.6g} {units})", f"{p:.4g}"],
        ["coefficient of variation (levels taken as uncorrelated)", f"{cov:.3g}"],
        ["95 % interval (lognormal with that cov)", f"[{g['interval'][0]:.4g}, {g['interval'][1]:.4g}]"],
        ["model runs (every proposal is a run)", f"{runs} in {len(g['thresholds'])} levels"],
        ["crude Monte Carlo for the same cov, (1 - P) / (P cov²)", f"{g['crude_monte_carlo_runs'][()]:.3g}"],
        ["the threshold reached the limit", "yes" if int(g.attrs["reached_limit"]) else
         "no: max_levels ran out (raise it)"]])
