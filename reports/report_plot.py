"""What every figure of the report shares: the Figure record, the table of plotted numbers
written as CSV beside each figure, saving (PNG, SVG and CSV with one stem), colours and labels.
"""

import csv
import math
import os
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from report_words import plain  # noqa: E402

DPI = 110
# SVG element ids from a fixed salt and no date: the same report twice gives the same files.
matplotlib.rcParams["svg.hashsalt"] = "jam-report"


@dataclass
class Figure:
    """One figure of the page: `file` the PNG, with `svg` and `csv` (its plotted numbers)
    beside it under the same stem."""

    file: str
    title: str
    caption: str

    @property
    def stem(self):
        return os.path.splitext(self.file)[0]

    @property
    def svg(self):
        return self.stem + ".svg"

    @property
    def csv(self):
        return self.stem + ".csv"


class Plotted:
    """The numbers a figure draws, one row per point: panel, series, x and y (with their
    names), y_error (empty where there is none). Written as the figure's CSV."""

    COLUMNS = ("panel", "series", "x_name", "x", "y_name", "y", "y_error")

    def __init__(self):
        self.rows = []
        self.names = {}

    def panel(self, panel, x_name, y_name):
        """Names the axes of `panel` for the rows added to it."""
        self.names[panel] = (x_name, y_name)

    def add(self, panel, series, x, y, y_error=None):
        x_name, y_name = self.names.get(panel, ("x", "y"))
        x, y = np.atleast_1d(np.asarray(x, dtype=float)), np.atleast_1d(np.asarray(y, dtype=float))
        err = (np.full(len(y), np.nan) if y_error is None
               else np.broadcast_to(np.asarray(y_error, dtype=float), y.shape))
        for xi, yi, ei in zip(x, y, err):
            self.rows.append((panel, series, x_name, xi, y_name, yi, ei))

    def write(self, path):
        with open(path, "w", newline="", encoding="utf-8") as f:
            w = csv.writer(f)
            w.writerow(self.COLUMNS)
            for row in self.rows:
                w.writerow([_cell(v) for v in row])


def _cell(v):
    """One CSV cell: a number as itself; text with its control characters made visible (a case
    name comes from a file) and, where it starts like a formula, quoted so that a spreadsheet
    shows it as text."""
    if isinstance(v, float):
        return "" if math.isnan(v) else repr(v)
    if isinstance(v, str):
        v = plain(v)
        return "'" + v if v[:1] in ("=", "+", "-", "@") else v
    return v


def label(x):
    """Text from a file (a case name) as matplotlib draws it: control characters made visible,
    shortened, and `$` shown as itself (matplotlib reads text between two `$` as TeX, and
    refuses TeX it cannot parse: a case name could stop the report)."""
    return plain(x, 200).replace("$", r"\$")


def _named(path, write):
    """write(path); an error that names no file (a full disk fails on close) names it."""
    try:
        write(path)
    except OSError as e:
        if e.filename is None:
            e.filename = path
        raise


def save(fig, out_dir, file, plotted):
    """Writes the figure as `file` (PNG) and as SVG, and its plotted numbers as CSV, beside
    each other in out_dir; returns `file`."""
    stem = os.path.join(out_dir, os.path.splitext(file)[0])
    try:
        _named(stem + ".png", lambda p: fig.savefig(p, dpi=DPI))
        # The layout that the PNG's draw placed holds for the SVG (it is in figure fractions);
        # with the layout engine kept, savefig would lay the figure out and draw it once more.
        fig.set_layout_engine(None)
        _named(stem + ".svg", lambda p: fig.savefig(p, format="svg", metadata={"Date": None}))
    finally:
        plt.close(fig)
    _named(stem + ".csv", plotted.write)
    return file


def rate_colors(log10_rates):
    rates = sorted(set(log10_rates), reverse=True)
    cmap = plt.get_cmap("viridis")
    return {r: cmap(0.85 * k / max(1, len(rates) - 1)) for k, r in enumerate(rates)}


def panels_with_key(rows, columns, panel_size, key_width=1.9, sharex=False, sharey=None):
    """A figure of rows x columns panels (each panel_size inches) and a column on the right
    for the figure's one legend (matplotlib 3.6, Debian 12's, has no legend placed outside by
    the layout). sharey: None, "row" or "all". Returns (fig, axes as a 2-D array, key axes)."""
    width, height = panel_size
    fig = plt.figure(layout="constrained", figsize=(width * columns + key_width, height * rows))
    grid = fig.add_gridspec(rows, columns + 1,
                            width_ratios=[width] * columns + [key_width])
    axes = np.empty((rows, columns), dtype=object)
    for r in range(rows):
        for k in range(columns):
            share_y = {"row": axes[r, 0] if k else None,
                       "all": axes[0, 0] if (r or k) else None}.get(sharey)
            axes[r, k] = fig.add_subplot(grid[r, k], sharex=axes[0, 0] if sharex and (r or k)
                                         else None, sharey=share_y)
    key = fig.add_subplot(grid[:, -1])
    key.axis("off")
    return fig, axes, key


def rate_label(log10_rate):
    return f"rate $10^{{{log10_rate:g}}}$"


def rate_text(log10_rate):
    """rate_label without TeX, for the CSV files."""
    return f"rate 10^{log10_rate:g}"


def decorate(ax, xlabel, ylabel, log_y=False):
    """Axis labels, legend and grid, the same on every single-panel figure."""
    if log_y:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if ax.get_legend_handles_labels()[1]:
        ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both" if log_y else "major")


def representative_phi_init(c):
    """The phi_init the fit used (stats.h5 fit/phi_init), else the lowest one."""
    if c.fit and "phi_init" in c.fit["attrs"]:
        return float(c.fit["attrs"]["phi_init"])
    return min(e.phi_init for e in c.ensembles)
