#!/usr/bin/python3
"""The stages of a bound run and of a bound curve, as a diagram (docs/concepts.md).

Usage: /usr/bin/python3 scripts/plot_concepts.py [OUT.png]   (default docs/figures/concepts_bound_run.png)
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch  # noqa: E402

LEVEL = "#d6e9f5"
CHECK = "#fde2c8"
CURVE = "#e3f1dc"


def box(ax, x, y, w, h, text, colour, size=9):
    ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0.02,rounding_size=0.08",
                                facecolor=colour, edgecolor="0.3", linewidth=1.0))
    ax.text(x + w / 2, y + h / 2, text, ha="center", va="center", fontsize=size, wrap=True)


def arrow(ax, a, b, label=None):
    ax.add_patch(FancyArrowPatch(a, b, arrowstyle="-|>", mutation_scale=12, color="0.25",
                                 linewidth=1.1))
    if label:
        ax.text((a[0] + b[0]) / 2 + 0.08, (a[1] + b[1]) / 2, label, fontsize=7.5, color="0.25",
                va="center")


def main(argv):
    out = argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "docs",
                                                     "figures", "concepts_bound_run.png")
    fig, ax = plt.subplots(figsize=(11.0, 6.2))
    ax.set_xlim(0, 11)
    ax.set_ylim(0, 6.2)
    ax.axis("off")

    ax.text(0.2, 5.95, "One frequency: `fricrom bounds CASE --freq F`", fontsize=11,
            weight="bold")
    levels = [("interface level\none α per interface\nand direction (4–8)",
               "corners of the box solved,\nruns from the extremes"),
              ("face level\nuniform + two linear\nshapes per face",
               "runs from the\ninterface optima"),
              ("pair level\none α per node pair\n(216 on the cascade)",
               "runs from the\nface optima")]
    x = 0.2
    for k, (name, how) in enumerate(levels):
        box(ax, x, 3.9, 2.2, 1.5, name, LEVEL)
        ax.text(x + 1.1, 3.6, how, ha="center", va="top", fontsize=7.5, color="0.3")
        if k < 2:
            arrow(ax, (x + 2.2, 4.65), (x + 2.75, 4.65))
        x += 2.75
    box(ax, 8.5, 3.9, 2.3, 1.5, "sample check\n(α samples beyond a\nbound restart its run)",
        CHECK)
    arrow(ax, (7.9, 4.65), (8.5, 4.65))
    ax.text(0.2, 3.0, "Each level searches at H = 1 and refines its optima at the case's H (the "
            "harmonic ladder); each keeps the coarser level's optima as candidates,\nso the "
            "bounds of a finer level contain every coarser level's.", fontsize=8.5, va="top")
    ax.text(0.2, 2.45, "Result: y_min, y_max, R = 1 − (y_max − y_min)/y_max, the α and contact "
            "states at both, and the Hill stability of both solutions.", fontsize=8.5)

    ax.text(0.2, 1.95, "A curve: `fricrom bounds CASE` (the case's range, --points)",
            fontsize=11, weight="bold")
    stages = ["pass 1: every frequency\nas above (threads / MPI)",
              "pass 2: sweeps up and\ndown the curve, each point\nfrom its neighbour's bounds",
              "refinement at the\ncase's H", "verify: α sampling and\ntime integration\n(separate command)"]
    x = 0.2
    for k, s in enumerate(stages):
        box(ax, x, 0.35, 2.45, 1.3, s, CURVE if k < 3 else CHECK, size=8.5)
        if k < 3:
            arrow(ax, (x + 2.45, 1.0), (x + 2.75, 1.0))
        x += 2.75
    fig.subplots_adjust(left=0.01, right=0.99, bottom=0.01, top=0.99)
    fig.savefig(out, dpi=110)
    print(f"plot_concepts.py: wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
