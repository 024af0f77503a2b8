#!/usr/bin/env python3
"""Draws a `leafdig plant import … -o tree.csv` as two views (side x–z, top x–y), each axis a line
coloured by its order: the figure in docs/plants.md, "Archives".

    scripts/plot-import-csv.py tree.csv tree.png
"""
import collections
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(source, target):
    axes = collections.OrderedDict()
    with open(source, newline="") as f:
        rows = csv.DictReader(line for line in f if not line.startswith("#"))
        for r in rows:
            axes.setdefault(r["axis"], []).append(
                (float(r["x_mm"]), float(r["y_mm"]), float(r["z_mm"]), int(r["order"])))
    fig, (side, top) = plt.subplots(1, 2, figsize=(11, 6))
    for points in axes.values():
        order = points[-1][3]
        width = max(0.3, 3 - 0.4 * order)
        side.plot([p[0] for p in points], [p[2] for p in points], lw=width, color="C%d" % order)
        top.plot([p[0] for p in points], [p[1] for p in points], lw=width, color="C%d" % order)
    side.set_title("side (x–z, mm), colour = axis order")
    top.set_title("from above (x–y, mm)")
    for ax in (side, top):
        ax.set_aspect("equal")
    fig.tight_layout()
    fig.savefig(target, dpi=60)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot-import-csv.py TREE.csv FIGURE.png")
    main(sys.argv[1], sys.argv[2])
