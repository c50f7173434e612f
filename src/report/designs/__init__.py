"""Each sampling design's part of the page, in designs/<name>.py, found by the file's root attribute `design`;
a design without a module of its own gets base.py's. A design module defines the hooks it changes:

    which runs count, and in what words:
    counted_rows(f, held, note) -> (rows, words)  which runs are independent draws, and the words for them
    counted_runs_meaning(f) -> str                what K counted runs mean for the job's samples ('': nothing)
    other_runs_words(f, others) -> str            the runs outside the counted ones, for a caption
    other_runs_legend(f) -> (caption, label)      ... in a scatter's caption and legend
    every_run_words(f) -> str                     what the extremes table takes in beside the counted runs
    ranked_runs_words(f) -> str                   which runs the rank measures stand on ('': the counted ones)

    its own answers:
    answer(f, page)                               the design's own answer, first among the answers
    own_probability_group(f, name) -> group/None  its own P of a response (probability, cov, interval)
    own_probability_words(f) -> str               whose that P is, in the answers table
    own_failure_region(f, name) -> OwnRegion/None the failure region of that P, and the runs it rests on
    verdict_column(f, sensitivity) -> VerdictColumn/None   its column of the answers table
    failure_effects(f, names) -> [str]            what the failed runs change of its own answers
    after_failure_region(f, page)                 its tables after what makes a response exceed its limit
    evidence(f, page)                             its figures among the evidence behind the answers

    its own measure of the drivers:
    has_own_ranking(s) -> bool                    /sensitivity/<r> holds its ranking (rankings.py reads it)
    own_ranking_words(s, ranking) -> str          where that ranking comes from, in its sentence
    own_measure_words() -> MeasureWords/None      its words where it and the rank measures disagree
    measure_words(f), folded_words(f), correlated_inputs_words(f) -> str   its sentences in the drivers' notes
    unreliable_words(s) -> str                    why its measure is unreliable ('': it is not)
    ranking_table(page, name, s, ranking, visible, ranks, correlations) -> bool   its table of the drivers

A new design adds its module here and nothing else in the report."""
import importlib
import re

from designs import base
from read import text


class Design:
    """A design module's hooks, base.py's where it defines none."""

    def __init__(self, module):
        self.module = module

    def __getattr__(self, hook):
        own = getattr(self.module, hook, None)
        return own if own is not None else getattr(base, hook)


def design_name(f):
    """The file's design; a file without the attribute (none treedyn writes) is read as subset simulation where
    it has levels, as the page read such files before its designs had modules."""
    if "design" in f.attrs:
        return text(f.attrs["design"])
    return "subset_simulation" if "samples/level" in f else ""


def design_of(f):
    name = design_name(f)
    if not re.fullmatch(r"[a-z][a-z0-9_]*", name) or name == "base":
        return Design(base)
    try:
        return Design(importlib.import_module(f"designs.{name}"))
    except ModuleNotFoundError as e:
        if e.name != f"designs.{name}":  # the module exists but something it imports does not
            raise
        return Design(base)


def counted_rows(f):
    """The rows of /samples that are independent draws, and the words saying which (the design's), among the
    rows this file holds (a merge of some parts leaves the others at status 3)."""
    status = f["samples/status"][:]
    held = status != 3
    note = "" if held.all() else f", of the {int(held.sum())} this merged file holds"
    return design_of(f).counted_rows(f, held, note)
