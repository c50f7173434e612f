"""What a design changes nothing of (monte_carlo; the others' defaults): every run held is an independent draw,
and the design has no answer, table or figure of its own."""
from collections import namedtuple

# own_measure_words(): the design's measure as the drivers' disagreement note words it: its name, the runs the rank
# measures stand on, what it measures, "its <measure>", the ranking's name.
MeasureWords = namedtuple("MeasureWords", "name rank_runs meaning its ranking")
# verdict_column(): the answers table's column on the design's own answer: its header, and the verdict of one
# response's /sensitivity group (or None).
VerdictColumn = namedtuple("VerdictColumn", "header verdict")
# own_failure_region(): the stored failure region group, which runs it rests on (words), the failed runs, the rows
# drawn as its reference sample, and their words.
OwnRegion = namedtuple("OwnRegion", "group which_runs failed reference reference_words")


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


def other_runs_legend(f):
    """The runs beside the counted ones in a scatter's caption, and their legend label's suffix."""
    return "other runs of the design (+: not independent draws, in the extremes table too)", ", other run"


def every_run_words(f):
    """What 'every run counts here' takes in beside the counted runs (the extremes table)."""
    return "every run of the design"


def measure_words(f):
    """The sentence on what the design's own measure of the drivers means ('' where the rank measures alone
    rank)."""
    return ""


def folded_words(f):
    """After the note on a list's entries shown as one name: where their effect together shows."""
    return ""


def correlated_inputs_words(f):
    """What to read where the counted runs' inputs are correlated: their Spearman coefficients mix."""
    return "read the SRRC instead."


def ranked_runs_words(f):
    """Which runs the rank measures stand on, before 'N runs' ('' where the counted ones are all there are)."""
    return ""


def has_own_ranking(s):
    """Whether /sensitivity/<r> `s` holds the design's own ranking (it then ranks, the rank measures beside it:
    rankings.py reads it)."""
    return False


def own_ranking_words(s, ranking):
    """Where the design's own ranking comes from, in its sentence ('' for the rank measures')."""
    return ""


def own_measure_words():
    """A MeasureWords for the note where its own ranking and the rank measures' put different inputs first;
    None: no note."""
    return None


def unreliable_words(s):
    """Why the design's own measure of `s` is unreliable ('' where it is not)."""
    return ""


def failure_effects(f, names):
    """What the failed runs change of the design's own answers, as sentences."""
    return []


def verdict_column(f, sensitivity):
    """A VerdictColumn of the answers table on the design's own answer, or None."""
    return None


def own_probability_group(f, name):
    """The group of the design's own P of response `name` (probability, cov, interval), where that is the
    answer and not the counted runs' exceedance; else None."""
    return None


def own_probability_words(f):
    """Whose that P is, in the answers table."""
    return ""


def own_failure_region(f, name):
    """The OwnRegion of the design's own P of `name`, or None."""
    return None


def ranking_table(page, name, s, ranking, visible, ranks, correlations):
    """A table by the design's own ranking for one response; False: the rank measures' table is drawn."""
    return False


def stratified_runs_meaning(design):
    """For the designs that spread their points (sobol, latin_hypercube): the verdicts below are a bound."""
    return (f"The verdicts take the runs as independent; the {design} design's stratification usually makes "
            f"the estimates better than that.")
