"""Reading treedyn's files: strings, units, and which runs a statistic counts."""
import numpy as np


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def strings(v):
    return [text(x) for x in v]


def units_of(dataset, column=None):
    if column is not None and "column_units" in dataset.attrs:
        return text(dataset.attrs["column_units"][column])
    return text(dataset.attrs.get("units", ""))


def fail_side(responses, r):
    """'above', 'below' or '' for response column r of /samples/responses."""
    return text(responses.attrs["fail_if"][r]) if "fail_if" in responses.attrs else ""


def counted_rows(f):
    """The rows of /samples that are independent draws, and the words saying which: for Saltelli the A and B
    runs (the AB runs repeat A's inputs but one), for subset simulation level 0 (its Monte-Carlo sample)."""
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
    return held, f"all {int(held.sum())} samples{note}"
