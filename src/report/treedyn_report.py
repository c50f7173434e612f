#!/usr/bin/python3
"""Figures and one HTML page from a treedyn HDF5 file (ensemble or trajectory).

Started by `treedyn report`, which has already checked the file and written
the text summary (DIR/summary.txt) with the same code as the end-of-run
summary of treedyn-ensemble. The page answers first (answers.py, with
drivers.py and failure_region.py), then shows the evidence
(ensemble_details.py) and, folded, every recorded quantity over time
(history.py); a trajectory file's page is trajectory.py's. What a sampling
design adds (its counted runs, its answer, its figures) is its module in
designs/, found by the file's design name.
Reads only what one figure needs at a time.

Exit codes: 0 ok, 2 the file or the options were refused (one line on
stderr), 4 the output directory could not be written.
"""
import argparse
import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ beside the sources


def fail(message, code=2):
    print(f"error: {message}", file=sys.stderr)
    sys.exit(code)


def say(line):
    """One line on stdout, which may be a pipe closed early (`treedyn report
    F | head -1`): the report is written all the same, without a traceback."""
    try:
        print(line, flush=True)
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())


try:
    import numpy as np
    import h5py
except ImportError as e:
    fail(f"treedyn report needs numpy and h5py ({e.name} is missing): apt-get install python3-h5py")
try:
    import matplotlib
    matplotlib.use("Agg")
except ImportError:
    fail("treedyn report needs matplotlib: apt-get install python3-matplotlib")

from answers import answers_section  # noqa: E402
from designs import counted_rows, design_of  # noqa: E402
from ensemble_details import failed_table, response_figures, sensitivity_figures  # noqa: E402
from history import ensemble_quantity_figures, final_value_histograms  # noqa: E402
from page import Page  # noqa: E402
from read import strings, text  # noqa: E402
from trajectory import trajectory_report  # noqa: E402
from view3d import view_section  # noqa: E402
from xdmf import write_xdmf  # noqa: E402


PROVENANCE = ["start_utc", "end_utc", "host", "command_line", "job_path", "treedyn_version", "git_commit",
              "build_type", "compiler", "sundials_version", "hdf5_version", "libdeflate_version", "eigen_version",
              "tomlplusplus_version", "mpi_library", "ranks", "rank_hosts"]


def provenance(f, page):
    page.fold("Provenance: who ran what, where, with which libraries")
    rows = []
    for key in PROVENANCE:
        if key in f.attrs:
            v = f.attrs[key]
            rows.append([key, ", ".join(strings(v)) if isinstance(v, np.ndarray) else text(v)])
    page.table(["attribute", "value"], rows)
    page.end_fold()


def summary_text(page, out_dir):
    summary_path = os.path.join(out_dir, "summary.txt")
    if os.path.exists(summary_path):
        with open(summary_path, encoding="utf-8") as s:
            page.fold("The run's text summary (as treedyn-ensemble printed it)")
            page.pre(s.read())
            page.end_fold()


def ensemble_report(f, page, file_name, quantities, out_dir):
    recorded = [text(q) for q in f["stats"].attrs["quantities"]] if "quantities" in f["stats"].attrs \
        else [q for q in f["stats"].keys() if q != "time"]
    for q in quantities:
        if q not in recorded:
            fail(f"--quantity {q}: not recorded in {file_name}; recorded: {' '.join(recorded)}")
    rows, counted = counted_rows(f)
    answers_section(f, page, file_name)
    view_section(f, page)
    summary_text(page, out_dir)
    page.heading("The evidence behind the answers")
    response_figures(f, page, rows, counted)
    design_of(f).evidence(f, page)
    sensitivity_figures(f, page)
    failed_table(f, page)
    page.heading("Recorded quantities over time")
    page.paragraph("Statistics over the successful samples at every output time. Click a quantity to open it; "
                   "`treedyn report FILE --quantity Q` draws all of Q's columns and the histograms of its values at "
                   f"the last output time over {counted}.")
    for q in quantities or recorded:
        page.fold(q)
        groups = ensemble_quantity_figures(f, page, q, bool(quantities))
        if quantities:  # on request: the page stays quick to draw (the values are in /samples/final)
            final_value_histograms(f, page, q, groups, rows, counted)
        page.end_fold()


def trajectory_page(f, page, file_name, quantities, out_dir):
    recorded = [k for k in f.keys() if isinstance(f[k], h5py.Dataset) and k not in ("time", "final_state")]
    recorded += [k for k in ("joint_reaction_magnitude",) if "joint_reaction" in f and k not in recorded]
    for q in quantities:
        if q not in recorded:
            fail(f"--quantity {q}: not recorded in {file_name}; recorded: {' '.join(recorded)}")
    trajectory_report(f, page, set(quantities))
    xmf, why = write_xdmf(f, file_name)
    if xmf:
        companion = os.path.splitext(xmf)[0] + ".motion.h5"
        page.paragraph(f"For ParaView, VisIt or meshio: {os.path.basename(xmf)} beside the file (File > Open, any of "
                       f"ParaView's XDMF readers) holds the stick figure as poly-lines at every output time; its "
                       f"points are in {os.path.basename(companion)}, one dataset per output time, copied from "
                       "/motion/points (the readers cannot all take a slice of one dataset).")
        say(f"wrote {xmf} and {companion}")
    else:
        page.paragraph(f"No XDMF file for ParaView: {why}.")
        print(f"warning: no XDMF file: {why}", file=sys.stderr)
    summary_text(page, out_dir)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("file")
    parser.add_argument("--out", required=True)
    parser.add_argument("--quantity", action="append", default=[])
    a = parser.parse_args()
    try:
        f = h5py.File(a.file, "r")
    except OSError as e:
        fail(f"{a.file}: not an HDF5 file h5py can open ({e})")
    with f:
        title = text(f.attrs.get("title", "")) or os.path.basename(a.file)
        page = Page(a.out, f"treedyn report: {title}")
        if "stats" in f:
            ensemble_report(f, page, a.file, a.quantity, a.out)
        else:
            trajectory_page(f, page, a.file, a.quantity, a.out)
        provenance(f, page)
        try:
            page.write()
        except OSError as e:
            fail(f"{a.out}: cannot write the report ({e})", 4)
    say(f"wrote {os.path.join(a.out, 'index.html')} ({page.figures} figures)")


if __name__ == "__main__":
    main()
