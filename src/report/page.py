"""One HTML page and its figures: headings, tables, folded sections, PNGs with
descriptive names, written atomically at the end."""
import html
import math
import os
import re

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = ("body{font-family:sans-serif;max-width:1150px;margin:auto;padding:0 8px}img{max-width:100%}"
         "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;padding:2px 6px;"
         "font-size:90%;vertical-align:top}th{background:#f0f0f0}"
         "figure{margin:1em 0}pre{background:#f4f4f4;padding:6px;overflow-x:auto;font-size:85%}"
         ".alarm{background:#fde2e1;border-left:6px solid #c62828;padding:6px 10px;margin:0.6em 0}"
         ".warning{background:#fff4d6;border-left:6px solid #e0a000;padding:6px 10px;margin:0.6em 0}"
         ".good{background:#e5f4e6;border-left:6px solid #2e7d32;padding:6px 10px;margin:0.6em 0}"
         "details{margin:0.4em 0}summary{cursor:pointer;font-weight:bold}code{background:#f4f4f4}"
         "td code{word-break:break-all;font-size:85%}")


def slug(words):
    return re.sub(r"[^A-Za-z0-9]+", "_", words).strip("_").lower()[:80] or "figure"


class Page:
    def __init__(self, out_dir, title):
        self.out_dir, self.title, self.parts, self.figures, self.names = out_dir, title, [], 0, set()

    def heading(self, words, level=2):
        self.parts.append(f"<h{level}>{html.escape(words)}</h{level}>")

    def paragraph(self, words):
        self.parts.append(f"<p>{html.escape(words)}</p>")

    def note(self, words, kind="warning"):
        """A boxed sentence: kind is alarm (red), warning (amber) or good (green)."""
        self.parts.append(f'<div class="{kind}">{html.escape(words)}</div>')

    def pre(self, words):
        self.parts.append(f"<pre>{html.escape(words)}</pre>")

    def table(self, header, rows, code_columns=()):
        cells = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)

        def cell(i, c):
            inner = html.escape(str(c))
            return f"<td><code>{inner}</code></td>" if i in code_columns and c != "" else f"<td>{inner}</td>"
        body = "".join("<tr>" + "".join(cell(i, c) for i, c in enumerate(r)) + "</tr>" for r in rows)
        self.parts.append(f"<table><tr>{cells}</tr>{body}</table>")

    def fold(self, summary):
        """Everything until end_fold() goes into a closed <details> block."""
        self.parts.append(f"<details><summary>{html.escape(summary)}</summary>")

    def end_fold(self):
        self.parts.append("</details>")

    def raw(self, markup):
        self.parts.append(markup)

    def figure(self, fig, caption, name):
        """Saved as NAME.png (made unique), with the caption under it."""
        base = slug(name)
        file_name, n = f"{base}.png", 1
        while file_name in self.names:
            n += 1
            file_name = f"{base}_{n}.png"
        self.names.add(file_name)
        self.figures += 1
        fig.savefig(os.path.join(self.out_dir, file_name), dpi=90)
        plt.close(fig)
        self.parts.append(f'<figure><img src="{file_name}" alt="{html.escape(caption)}">'
                          f"<figcaption>{html.escape(caption)}</figcaption></figure>")

    def write(self):
        page = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(self.title)}</title>"
                f"<style>{STYLE}</style></head><body><h1>{html.escape(self.title)}</h1>"
                + "\n".join(self.parts) + "</body></html>\n")
        temporary = os.path.join(self.out_dir, f"index.html.tmp-{os.getpid()}")
        with open(temporary, "w", encoding="utf-8") as f:
            f.write(page)
        os.replace(temporary, os.path.join(self.out_dir, "index.html"))


def subplot_grid(count, width=4.2, height=2.9, columns=3):
    """A constrained-layout grid of `count` axes (titles and labels never overlap)."""
    if count == 1:
        width *= 1.8  # one axes alone: room for its legend beside it
    columns = max(1, min(count, columns))
    rows = math.ceil(count / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(width * columns, height * rows), squeeze=False,
                             layout="constrained")
    for a in axes.flat[count:]:
        a.set_visible(False)
    return fig, list(axes.flat[:count])


def legend_outside(axes, entries=None):
    """The legend outside every data area: in a spare cell of the grid if there is one, else right of the
    top-right axes (constrained layout makes room). `entries`: (handles, labels), else the first axes'."""
    handles, labels = entries or axes[0].get_legend_handles_labels()
    if not handles:
        return
    spare = [a for a in axes[0].figure.axes if not a.get_visible()]
    if spare:
        spare[0].set_visible(True)
        spare[0].axis("off")
        spare[0].legend(handles, labels, loc="center", fontsize=8)
        return
    top_right = max(axes, key=lambda a: (round(a.get_position().y0, 3), a.get_position().x0))
    top_right.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8)
