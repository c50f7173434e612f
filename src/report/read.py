"""Reading treedyn's files: strings, units, and which runs a statistic counts."""
import numpy as np


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def strings(v):
    return [text(x) for x in v]


def column_units(dataset):
    """Each column's unit ('column_units'), '' where the file gives none."""
    if "column_units" in dataset.attrs:
        return strings(dataset.attrs["column_units"])
    return [""] * dataset.shape[-1]


def units_of(dataset, column=None):
    if column is not None and "column_units" in dataset.attrs:
        return text(dataset.attrs["column_units"][column])
    return text(dataset.attrs.get("units", ""))


def fail_side(responses, r):
    """'above', 'below' or '' for response column r of /samples/responses."""
    return text(responses.attrs["fail_if"][r]) if "fail_if" in responses.attrs else ""


def held_rows(f):
    """The rows this file holds (a merge of some parts leaves the others at status 3)."""
    return f["samples/status"][:] != 3


def subset_response(f):
    """The response a subset simulation estimates P for ('' for other designs): its level 0 alone is not
    the answer."""
    return next(iter(f["rare_event"].keys()), "") if "rare_event" in f else ""


def morris_design(f):
    return text(f.attrs.get("design", "")) == "morris" and "morris_block" in f.attrs


def counted_rows(f):
    """The rows of /samples that are independent draws, and the words saying which: for Saltelli the A and B
    runs (the AB runs repeat A's inputs but one), for Morris each trajectory's first run (the others step one
    factor at a time from it), for subset simulation level 0 (its Monte-Carlo sample)."""
    status = f["samples/status"][:]
    n, held = status.size, status != 3  # 3: not in this file (a merge of some parts)
    note = "" if held.all() else f", of the {int(held.sum())} this merged file holds"
    if "samples/level" in f:
        rows = f["samples/level"][:] == 0
        return rows, f"level 0 of the subset simulation, its Monte-Carlo sample ({int(rows.sum())} runs)"
    if text(f.attrs.get("design", "")) == "saltelli" and "saltelli_block" in f.attrs:
        rows = (np.arange(n) % int(f.attrs["saltelli_block"]) < 2) & held
        return rows, (f"the {int(rows.sum())} independent runs of the {n} (the A and B runs of the Saltelli "
                      f"design; its AB runs repeat A's inputs but one){note}")
    if morris_design(f):
        rows = (np.arange(n) % int(f.attrs["morris_block"]) == 0) & held
        return rows, (f"the {int(rows.sum())} independent runs of the {n} (each Morris trajectory's first run; "
                      f"the trajectory's other runs step one factor at a time from it){note}")
    return held, f"all {int(held.sum())} samples{note}"


LIST_COLUMNS = 4  # a target with this many input columns or more is a list (a sea state's phases)


def shown_inputs(inputs):
    """Indices of the input columns a table or map shows one by one, and the list targets it folds
    ({target: number of columns}): a sea state's 64 phases are one input to a reader, and one by one
    they are noise (their effect is in the group's Sobol' index)."""
    names = strings(inputs.attrs["columns"])
    targets = strings(inputs.attrs["column_targets"]) if "column_targets" in inputs.attrs else names
    counts = {t: targets.count(t) for t in targets}
    folded = {t: c for t, c in counts.items() if c >= LIST_COLUMNS}
    return [i for i, t in enumerate(targets) if t not in folded], folded


def folded_note(folded):
    return ("Not shown one by one: " + ", ".join(f"{t} ({c} inputs)" for t, c in folded.items()) +
            "; each sample's values are in /samples/inputs (columns " + ", ".join(f"{t}[1..{c}]" for t, c in
                                                                                    folded.items()) + ").")
