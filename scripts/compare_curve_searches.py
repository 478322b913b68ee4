#!/usr/bin/python3
"""Bound curves of one case found by different searches, against the best bound any of them found.

Usage: compare_curve_searches.py OUT_STEM LABEL=BOUNDS.json [LABEL=BOUNDS.json ...]

Each BOUNDS.json is the output of `fricrom bounds CASE --json` over the same frequencies. Every
curve's y_max is a lower bound of the true maximum response and its y_min an upper bound of the
true minimum (each is a response some alpha reaches), so the best known bound at a frequency is
the largest y_max and the smallest y_min of all curves. Prints, per curve, how far its y_max falls
short of the best known (mean, worst, points beyond 1 %) and how far its R = y_min / y_max lies
above the best known R; writes OUT_STEM.json (the curves, reduced) and OUT_STEM.png (y_max and R
over frequency, and the y_max shortfall). Units SI (Hz, m).
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from atomic_write import replace_atomically, write_text_atomically  # noqa: E402


def load(spec):
    label, _, path = spec.partition("=")
    if not path:
        sys.exit(f"compare_curve_searches: expected LABEL=BOUNDS.json, got {spec!r}")
    with open(path) as f:
        pts = json.load(f)["points"]
    return label, [(p["freq_hz"], p["y_min"], p["y_max"]) for p in pts]


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    stem, curves = sys.argv[1], [load(s) for s in sys.argv[2:]]
    freqs = [f for f, _, _ in curves[0][1]]
    for label, c in curves:
        if [f for f, _, _ in c] != freqs:
            sys.exit(f"compare_curve_searches: {label} has other frequencies than {curves[0][0]}")
        if any(y is None or lo is None for _, lo, y in c):
            sys.exit(f"compare_curve_searches: {label} has a failed bound (null)")
    n = len(freqs)
    best_max = [max(c[i][2] for _, c in curves) for i in range(n)]
    best_min = [min(c[i][1] for _, c in curves) for i in range(n)]
    summary = {"units": {"freq": "Hz", "amplitude": "m"}, "freq_hz": freqs,
               "best_y_max_m": best_max, "best_y_min_m": best_min, "curves": {}}
    fig, ax = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    for label, c in curves:
        short = [1.0 - c[i][2] / best_max[i] for i in range(n)]
        r_excess = [c[i][1] / c[i][2] - best_min[i] / best_max[i] for i in range(n)]
        peak = max(range(n), key=lambda i: c[i][2])
        row = {"y_min_m": [p[1] for p in c], "y_max_m": [p[2] for p in c],
               "y_max_shortfall_mean": sum(short) / n, "y_max_shortfall_worst": max(short),
               "points_short_by_more_than_1pct": sum(s > 0.01 for s in short),
               "R_excess_mean": sum(r_excess) / n, "R_excess_worst": max(r_excess),
               "peak_freq_hz": c[peak][0], "peak_y_max_m": c[peak][2],
               "peak_R": c[peak][1] / c[peak][2]}
        summary["curves"][label] = row
        print(f"{label:>12}: y_max short of the best by {100 * row['y_max_shortfall_mean']:.2f} % "
              f"mean, {100 * row['y_max_shortfall_worst']:.2f} % worst, > 1 % at "
              f"{row['points_short_by_more_than_1pct']} of {n}; R above the best by "
              f"{row['R_excess_mean']:.4f} mean, {row['R_excess_worst']:.4f} worst; peak "
              f"{row['peak_freq_hz']:.2f} Hz, y_max {row['peak_y_max_m']:.4e} m, R "
              f"{row['peak_R']:.4f}")
        ax[0].plot(freqs, [p[2] for p in c], label=label)
        ax[1].plot(freqs, [p[1] / p[2] for p in c], label=label)
        ax[2].plot(freqs, [100 * s for s in short], marker=".", label=label)
    ax[0].plot(freqs, best_max, "k:", label="best known")
    ax[0].set_yscale("log")
    ax[0].set_ylabel("y_max [m]")
    ax[1].set_ylabel("R = y_min / y_max")
    ax[2].set_ylabel("y_max below the best known [%]")
    ax[2].set_xlabel("frequency [Hz]")
    for a in ax:
        a.grid(True, alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    write_text_atomically(stem + ".json", json.dumps(summary, indent=1) + "\n")
    replace_atomically(stem + ".png", ".png", lambda tmp: fig.savefig(tmp, format="png", dpi=110))


if __name__ == "__main__":
    main()
