#!/usr/bin/python3
"""The report page of an ensemble file against its design's Morris answers (by hand, or from a test):

  morris_page_checks.py FILE.h5 DIR   DIR: what `treedyn report FILE.h5 -o DIR` wrote

For design = "morris" with responses, per response with /sensitivity/<r>/morris_mu_star: the green box states
the text summary's Morris ranking (summary.txt's drivers line, its > and ~, its values) by mu* with its units
and trajectories, before any figure; the table of mu*, mu and sigma (with units) lists the factors in the
file's morris_ranking order; the figure morris_<r>.png is referenced, exists and is not blank, with its
sigma = mu* caption; the counted runs are each trajectory's first run and the page says it is a screen.
For any other design: no Morris section (the word Morris nowhere on the page, no morris_*.png).
Prints 'ok ...' and exits 0, or prints what is wrong and exits 1.
"""
import html
import os
import re
import sys

import h5py
import numpy as np


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def summary_ranking(summary, response):
    """The Morris drivers line of `response` in summary.txt ("A 6.41e+03 [6.32e+03, 6.51e+03] > B ..."), without
    its "(and N more)" / "(not shown: ...)" tails; None where there is none."""
    at = summary.find(f"  {response} (")
    line = summary.find("    drivers (", at)
    if at < 0 or line < 0 or "Morris mu*" not in summary[line:summary.find("\n", line)]:
        return None
    start = summary.find("): ", line) + 3
    ranking = summary[start:summary.find("\n", start)]
    return re.sub(r" \((and \d+ more|not shown: [^)]*)\)", "", ranking).strip()


def response_checks(f, page, summary, out_dir, name):
    bad = []
    s = f["sensitivity"][name]
    unit = text(s["morris_mu_star"].attrs.get("units", ""))
    factors = [text(u) for u in s["morris_mu_star"].attrs["columns"]]
    trajectories = int(s.attrs["morris_trajectories"])
    ranking = summary_ranking(summary, name)
    if ranking is None:
        bad.append(f"{name}: no Morris drivers line in summary.txt")
    else:
        box = page.find('<div class="good">' + html.escape(f"{name} is driven by {ranking}"))
        if box < 0:
            bad.append(f"{name}: the page does not state the summary's ranking: {ranking}")
        elif box > page.find("<img"):
            bad.append(f"{name}: the ranking comes after a figure")
        elif html.escape(f"(Morris mu* [95 %], {unit} per unit of u, from {trajectories} trajectories") not in \
                page[box:page.find("</div>", box)]:
            bad.append(f"{name}: the ranking does not say Morris mu*, {unit} per unit of u and {trajectories} "
                       "trajectories")
    header = html.escape(f"<th>mu* [95 %] ({unit} per unit of u)</th><th>mu [95 %] ({unit} per unit of u)</th>"
                         f"<th>sigma [95 %] ({unit} per unit of u)</th>").replace("&lt;", "<").replace("&gt;", ">")
    table = page.find(header)
    if table < 0:
        bad.append(f"{name}: no table of mu*, mu and sigma in {unit} per unit of u")
    else:
        body = page[table:page.find("</table>", table)]
        shown = re.findall(r"<tr><td>([^<]*)</td>", body)
        order = [factors[int(u)] for u in s["morris_ranking/order"][:]]
        if [html.unescape(n) for n in shown] != order[:len(shown)] or not shown:
            bad.append(f"{name}: the table's factors {shown} are not in mu*'s order {order}")
    figure = f"morris_{name}.png"
    at = page.find(f'<img src="{figure}"')
    if at < 0:
        bad.append(f"{name}: no figure {figure}")
    else:
        caption = page[at:page.find("</figcaption>", at)]
        if "dashed: sigma = mu*" not in caption:
            bad.append(f"{name}: the figure's caption does not explain the line sigma = mu*")
        bad += png_problems(os.path.join(out_dir, figure))
    return bad


def png_problems(path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as image
    if not os.path.exists(path):
        return [f"{path}: missing"]
    pixels = image.imread(path)
    return [f"{path}: blank"] if pixels.size == 0 or float(np.var(pixels[..., :3])) < 1e-4 else []


def morris_checks(f, page, summary, out_dir):
    bad = []
    block, status = int(f.attrs["morris_block"]), f["samples/status"][:]
    first = int(np.count_nonzero((np.arange(status.size) % block == 0) & (status != 3)))
    if f"the {first} independent runs of the {status.size} (each Morris trajectory's first run" not in \
            html.unescape(page):
        bad.append(f"the counted runs are not said to be the {first} trajectories' first runs")
    if "samples/responses" not in f:
        return bad
    if "a screen, not an estimate of a small probability" not in html.unescape(page):
        bad.append("the page does not say that a Morris design's P is a screen")
    names = [text(n) for n in f["samples/responses"].attrs["columns"]]
    checked = [n for n in names if "sensitivity" in f and n in f["sensitivity"] and
               "morris_mu_star" in f["sensitivity"][n]]
    if not checked:
        bad.append("no response has Morris datasets")
    for name in checked:
        bad += response_checks(f, page, summary, out_dir, name)
    return bad


def main(path, out_dir):
    with open(os.path.join(out_dir, "index.html"), encoding="utf-8") as p:
        page = p.read()
    summary_path = os.path.join(out_dir, "summary.txt")
    summary = open(summary_path, encoding="utf-8").read() if os.path.exists(summary_path) else ""
    with h5py.File(path, "r") as f:
        design = text(f.attrs.get("design", ""))
        if design == "morris":
            bad = morris_checks(f, page, summary, out_dir)
            ok = "ok morris page"
        else:
            bad = [f"{design} page: {what}" for what, found in
                   (("mentions Morris", "morris" in page.lower()), ("has a morris figure", 'src="morris_' in page))
                   if found]
            ok = f"ok {design} page: no Morris section"
    for b in bad:
        print(b)
    if not bad:
        print(ok)
    return 1 if bad else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1], sys.argv[2]))
