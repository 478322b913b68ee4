#!/usr/bin/python3
"""R over the wedge angle from two geometry NOA runs (scripts/geometry_noa.py), side by side.

    /usr/bin/python3 scripts/plot_geometry_compare.py A/geometry_noa.csv "label A" \
        B/geometry_noa.csv "label B" OUT.png [--title T]

Each CSV: cham_deg, status, R, y_min_m, y_max_m, ... (one row per design; rows whose status is
not "ok" are left out). Only Debian's python3-matplotlib and python3-numpy.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r.get("status") == "ok":
                rows.append((float(r["cham_deg"]), float(r["R"])))
    if not rows:
        sys.exit(f"plot_geometry_compare.py: {path}: no design with status ok")
    return sorted(rows)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("a")
    p.add_argument("label_a")
    p.add_argument("b")
    p.add_argument("label_b")
    p.add_argument("out")
    p.add_argument("--title", default="")
    a = p.parse_args()
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for path, label, style in ((a.a, a.label_a, "o-"), (a.b, a.label_b, "s--")):
        rows = read(path)
        ax.plot([r[0] for r in rows], [r[1] for r in rows], style, label=label)
    ax.set_xlabel("wedge angle cham_deg [deg]")
    ax.set_ylabel("robustness R = 1 - (y_max - y_min) / y_max")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend()
    if a.title:
        ax.set_title(a.title)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)


if __name__ == "__main__":
    main()
