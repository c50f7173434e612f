"""Morris' screen: trajectories of U + 1 runs, each stepping one factor from the run before, of which the first
is an independent draw; drawn per response, each factor's mu* (the mean size of its elementary effects) against
sigma (their spread), with their 95 % bootstrap intervals where finite, and the line sigma = mu*: above it a factor
acts nonlinearly or through interactions, near the x-axis linearly. Sizes in the response's units per unit of u,
drawn as they are (no share of variance: nothing to clip)."""
import numpy as np

import matplotlib.pyplot as plt

from designs import base
from drivers import TABLE_ROWS, folded_members
from rankings import has_morris, morris_ranking, visible_units
from read import strings, text

MAX_LABELS = 12  # factors named beside their point, largest mu* first
MARGIN = 1.15    # the axes reach this far beyond the largest interval
SAME_SIGN = 0.99  # |mu| this close to mu*: the elementary effects all have one sign


def counted_rows(f, held, note):
    if "morris_block" not in f.attrs:
        return base.counted_rows(f, held, note)
    rows = (np.arange(held.size) % int(f.attrs["morris_block"]) == 0) & held
    return rows, (f"the {int(rows.sum())} independent runs of the {held.size} (each Morris trajectory's first run; "
                  f"the trajectory's other runs step one factor at a time from it){note}")


def counted_runs_meaning(f):
    if "morris_block" not in f.attrs:
        return ""
    where = (f"on the inputs' {int(f.attrs['morris_levels'])}-level grid" if "morris_levels" in f.attrs
             else "a scrambled Sobol' point")
    return (f"For this Morris design the mean and the probability use each trajectory's first run (an "
            f"independent draw, {where}: a screen, not an estimate of a small probability); K counted runs "
            f"are K trajectories, that is K x {int(f.attrs['morris_block'])} model runs.")


def other_runs_words(f, others):
    return (f"the {others} other runs of the Morris trajectories (each steps one factor from the run before: "
            "not independent draws)")


def evidence(f, page):
    morris_figures(f, page)


def other_runs_legend(f):
    if "morris_block" not in f.attrs:
        return base.other_runs_legend(f)
    return ("other runs of the Morris trajectories (+: each steps one factor from the run before, in the extremes "
            "table too)", ", trajectory step")


def every_run_words(f):
    if "morris_block" not in f.attrs:
        return base.every_run_words(f)
    return "every step of the Morris trajectories too"


def measure_words(f):
    return ("Morris mu* is the mean size of a factor's elementary effects: the change of the response when the "
            "factor (an input, or a group of inputs moved together) alone steps, divided by the step in its "
            "inputs' probability u, so in the response's units per unit of u; mu is their mean with its sign (the "
            "direction), sigma their spread (large: the effect changes with where the step is taken, a nonlinear "
            "or interacting factor). A screen: it orders the factors with few runs; it is no share of variance.")


def folded_words(f):
    return " Their effect together is their factor's Morris mu*: a list's entries step together."


def correlated_inputs_words(f):
    return "Morris mu* does not (each elementary effect steps one factor alone)."


def has_own_ranking(s):
    return has_morris(s)


def own_ranking_words(s, ranking):
    return f"{morris_units(s)} per unit of u, {trajectories_words(s)}"


def own_measure_words():
    return base.MeasureWords("Morris mu*", "over each trajectory's first run", "the mean size of the response's "
                             "change when the input alone steps, its interactions and non-monotone effects included",
                             "its Morris mu*", "Morris")


def morris_units(s):
    return text(s["morris_mu_star"].attrs.get("units", ""))


def trajectories_words(s):
    """'from 10 trajectories', and how many elementary effects a factor rests on where failed runs cost some."""
    trajectories = int(s.attrs.get("morris_trajectories", 0))
    effects = s["morris_effects"][:] if "morris_effects" in s else np.full(1, float(trajectories))
    if np.nanmin(effects) >= trajectories:
        return f"from {trajectories} trajectories"
    return (f"from {trajectories} trajectories; failed runs left {np.nanmin(effects):.0f} to {np.nanmax(effects):.0f} "
            "elementary effects per factor")


def ranking_table(page, name, s, morris, visible, ranks, correlations):
    """mu*, mu and sigma per factor (a response without them gets the rank measures' table)."""
    if not has_morris(s):
        return False
    morris_table(page, name, s, morris, visible, ranks.units)
    return True


def morris_table(page, name, s, morris, visible, input_names):
    """mu* with its interval, mu and sigma per factor (largest mu* first), in the response's units per unit of
    u, and what mu and sigma say of each; then the factors that act nonlinearly or through interactions."""
    grouped = any(len(morris.members[u]) > 1 for u in visible)
    unit = morris_units(s)
    shown = [int(u) for u in morris.order if int(u) in set(visible)]
    header = ["factor"] + (["its inputs"] if grouped else []) + \
             [f"mu* [95 %] ({unit} per unit of u)", f"mu [95 %] ({unit} per unit of u)",
              f"sigma [95 %] ({unit} per unit of u)", "elementary effects", "reading"]
    page.table(header, [morris_row(name, s, morris, u, input_names if grouped else None) for u in shown[:TABLE_ROWS]])
    line = nonlinear_line(name, morris, s["morris_sigma"][:], shown)
    if line:
        page.paragraph(line)


def morris_row(name, s, morris, u, input_names):
    """One factor's row; its inputs folded where `input_names` is given (a table with groups)."""
    mu, sigma = s["morris_mu"][u], s["morris_sigma"][u]
    effects = float(s["morris_effects"][u]) if "morris_effects" in s else float("nan")
    return [morris.units[u]] + ([folded_members(morris.members[u], input_names)] if input_names else []) + \
        [size_text(morris.value[u], morris.ci[u]), size_text(mu, s["morris_mu_ci"][u]),
         size_text(sigma, s["morris_sigma_ci"][u]), f"{effects:.0f}" if np.isfinite(effects) else "n/a",
         morris_reading(name, morris.value[u], mu, sigma)]


def nonlinear_line(name, morris, sigma, shown):
    """The factors with sigma >= mu*, as the text summary names them ('' where there are none)."""
    nonlinear = [f"{morris.units[u]} (sigma {sigma[u]:.3g}, mu* {morris.value[u]:.3g})" for u in shown
                 if nonlinear_factor(morris.value[u], sigma[u])]
    if not nonlinear:
        return ""
    return (f"{name}: sigma >= mu*, nonlinear or interacting: {', '.join(nonlinear)}. Their effect depends on where "
            "they step (or on the other factors): mu* orders them, but a Saltelli design's Sobol' "
            "indices say how much of the variance goes with them.")


def size_text(v, ci):
    """A size in the response's units with its interval, not clipped (mu, mu*, sigma)."""
    if not np.isfinite(v):
        return "n/a"
    return f"{v:.3g}" + (f" [{ci[0]:.3g}, {ci[1]:.3g}]" if np.isfinite(ci[0]) and np.isfinite(ci[1]) else "")


def nonlinear_factor(mu_star, sigma):
    """The summary's rule: sigma at least mu* (and an effect at all)."""
    return bool(np.isfinite(sigma) and np.isfinite(mu_star) and mu_star > 0 and sigma >= mu_star)


def morris_reading(name, mu_star, mu, sigma):
    """What mu and sigma say of one factor: its direction where its effects (nearly) all have one sign
    (|mu| = mu*), else that they change sign; nonlinear or interacting where sigma >= mu*."""
    if not (np.isfinite(mu_star) and np.isfinite(mu)) or mu_star == 0:
        return "no effect seen" if mu_star == 0 else ""
    words = [(f"raises {name}" if mu > 0 else f"lowers {name}") if abs(mu) >= SAME_SIGN * mu_star else
             "its effects change sign (|mu| < mu*): non-monotone"]
    if nonlinear_factor(mu_star, sigma):
        words.append("nonlinear or interacting (sigma >= mu*)")
    return "; ".join(words)


def morris_figures(f, page):
    if "sensitivity" not in f or "samples/inputs" not in f or "samples/responses" not in f:
        return
    inputs = f["samples/inputs"]
    names = strings(inputs.attrs["columns"])
    for name in [r for r in strings(f["samples/responses"].attrs["columns"]) if r in f["sensitivity"]]:
        s = f["sensitivity"][name]
        if not has_morris(s):
            continue
        morris = morris_ranking(s, names)
        units = [int(u) for u in morris.order if int(u) in set(visible_units(morris, inputs))]
        fig, ax = plt.subplots(figsize=(10, 4.8), layout="constrained")
        morris_plane(ax, morris, s["morris_sigma"][:], s["morris_sigma_ci"][:], units, morris_units(s))
        ax.set_title(name, fontsize=9)
        page.figure(fig, morris_caption(name, s, len(units) > MAX_LABELS), f"morris_{name}")


def morris_caption(name, s, unlabelled):
    unit = morris_units(s)
    return (f"{name}: Morris mu* (the mean size of a factor's elementary effects) against sigma (their spread), per "
            f"factor, in {unit} per unit of u, with their 95 % bootstrap intervals where finite, "
            f"{trajectories_words(s)}; dashed: sigma = mu*. Above the line a factor acts nonlinearly or through "
            "interactions (its effect changes with where it steps, or with the other factors); near "
            "the x-axis it acts linearly (about the same effect wherever it steps); near the origin it matters "
            "little" + (f"; the {MAX_LABELS} largest mu* named" if unlabelled else ""))


def interval_errors(v, ci):
    """Asymmetric error bars from an interval (none where it or the estimate is not finite)."""
    errors = np.vstack([v - ci[:, 0], ci[:, 1] - v])
    errors[:, ~(np.isfinite(v) & np.all(np.isfinite(ci), axis=1))] = 0.0
    return np.maximum(errors, 0.0)


def morris_plane(ax, morris, sigma, sigma_ci, units, unit):
    x, y = morris.value[units], sigma[units]
    x_ci, y_ci = morris.ci[units], sigma_ci[units]
    ax.errorbar(x, y, xerr=interval_errors(x, x_ci), yerr=interval_errors(y, y_ci), fmt="o", color="tab:blue",
                ecolor="0.55", elinewidth=0.9, capsize=2, ms=5, label="factor (95 % intervals)")
    right = MARGIN * max(np.nanmax(np.r_[x, x_ci[:, 1][np.isfinite(x_ci[:, 1])]], initial=0.0), 1e-300)
    top = MARGIN * max(np.nanmax(np.r_[y, y_ci[:, 1][np.isfinite(y_ci[:, 1])]], initial=0.0), 1e-300)
    reach = max(right, top)
    ax.plot([0, reach], [0, reach], "--", color="0.3", lw=1, label="sigma = mu*")
    ax.set_xlim(0, right)
    ax.set_ylim(0, top)
    for k, u in enumerate(units[:MAX_LABELS]):
        if np.isfinite(x[k]) and np.isfinite(y[k]):
            near_right = x[k] > 0.6 * right
            ax.annotate(morris.units[u], (x[k], y[k]), xytext=(-5 if near_right else 5, 5), textcoords="offset points",
                        ha="right" if near_right else "left", fontsize=8)
    ax.set_xlabel(f"mu*, the mean |elementary effect| ({unit} per unit of u)", fontsize=8)
    ax.set_ylabel(f"sigma, their standard deviation ({unit} per unit of u)", fontsize=8)
    ax.tick_params(labelsize=8)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: the upper left is where
    # the nonlinear factors sit
