"""What a design changes nothing of (monte_carlo; the others' defaults): every run held is an independent draw,
and the design has no answer, table or figure of its own."""


def counted_rows(f, held, note):
    return held, f"all {int(held.sum())} samples{note}"


def counted_runs_meaning(f):
    return ""


def other_runs_words(f, others):
    return f"the {others} other runs"


def answer(f, page):
    pass


def after_failure_region(f, page):
    pass


def evidence(f, page):
    pass


def ranking_table(page, name, s, ranking, visible, ranks, correlations):
    """A table by the design's own ranking for one response; False: the rank measures' table is drawn."""
    return False


def stratified_runs_meaning(design):
    """For the designs that spread their points (sobol, latin_hypercube): the verdicts below are a bound."""
    return (f"The verdicts take the runs as independent; the {design} design's stratification usually makes "
            f"the estimates better than that.")
