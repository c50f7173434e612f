"""Reading treedyn's files: strings, units, the rows a file holds and the inputs a page shows (which runs a
statistic counts is the design's: designs/)."""


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
