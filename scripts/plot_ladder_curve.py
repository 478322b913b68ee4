#!/usr/bin/python3
"""Two bound curves of one case side by side, e.g. H = 1 and H = 3 on the harmonic ladder.

Usage:
    /usr/bin/python3 scripts/plot_ladder_curve.py A/bounds.h5 LABEL_A B/bounds.h5 LABEL_B OUT.png
        [--json OUT.json] [--ratio]

Reads /bounds/{freq_hz, y_min_m, y_max_m} of two `fricrom bounds CASE --points N` runs over the
same frequencies and draws y_min and y_max [m] of both over frequency (log scale, the peak of each
marked), R = 1 − (y_max − y_min)/y_max below and, where both files hold /bounds/wall_s, the wall
time of each point [s] (log scale; the curve's wall time in the legend); with --ratio a panel of
y_max of B against A [%] (differences a log scale hides); with --json writes the points (SI
units).
Failed bounds are NaN in the files and gaps in the figure. Exit status 2 on files that do not
hold curves over the same frequencies.
"""

import json
import sys

sys.dont_write_bytecode = True
import fricrom_plot_common as common  # noqa: E402
from fricrom_plot_common import np, plt  # noqa: E402

COLORS = ("#999999", "#1f4e9c")


def number_or_null(v):
    """A failed value is null in the JSON, never a number."""
    return float(v) if np.isfinite(v) else None


def read_curve(path):
    """freq_hz, y_min, y_max, the points' wall times (None if absent) and the curve's."""
    with common.open_h5(path) as h5:
        f, lo, hi = common.bound_curve(h5)
        g = h5["bounds"]
        wall = np.asarray(g["wall_s"][...], float) if "wall_s" in g else None
        total = float(g.attrs["wall_s"]) if "wall_s" in g.attrs else float("nan")
    if wall is not None and wall.shape != np.shape(f):
        raise common.InputError(f"{path}: /bounds/wall_s does not match /bounds/freq_hz")
    return np.asarray(f, float), np.asarray(lo, float), np.asarray(hi, float), wall, total


def work():
    args = [a for a in sys.argv[1:]]
    out_json = None
    if "--json" in args:
        k = args.index("--json")
        if k + 1 >= len(args):
            raise common.InputError("--json needs a file name")
        out_json = args[k + 1]
        del args[k:k + 2]
    ratio = "--ratio" in args
    if ratio:
        args.remove("--ratio")
    if len(args) != 5:
        raise common.InputError("usage: plot_ladder_curve.py A.h5 LABEL_A B.h5 LABEL_B OUT.png "
                                "[--json OUT.json] [--ratio]")
    (path_a, label_a, path_b, label_b, out) = args
    common.check_output(out)
    curves = [(label_a, *read_curve(path_a)), (label_b, *read_curve(path_b))]
    f = curves[0][1]
    if curves[1][1].shape != f.shape or not np.allclose(curves[1][1], f, rtol=1e-12):
        raise common.InputError(f"{path_a} and {path_b} are not curves over the same frequencies")
    timed = all(c[4] is not None for c in curves)
    heights = [2.2, 1] + ([1] if ratio else []) + ([1] if timed else [])
    fig, axes = plt.subplots(len(heights), 1, figsize=(8, 4.3 + 2.0 * (len(heights) - 1)),
                             sharex=True, gridspec_kw={"height_ratios": heights})
    ax, axr = axes[0], axes[1]
    axq = axes[2] if ratio else None
    axt = axes[-1] if timed else None
    series = {}
    for (name, _, lo, hi, wall, total), color in zip(curves, COLORS):
        r = 1 - (hi - lo) / hi
        series[name] = {"y_min_m": [number_or_null(v) for v in lo],
                        "y_max_m": [number_or_null(v) for v in hi],
                        "R": [number_or_null(v) for v in r]}
        ax.semilogy(f, hi, "-", color=color, lw=1.6, label=f"y_max, {name}")
        ax.semilogy(f, lo, "--", color=color, lw=1.2, label=f"y_min, {name}")
        ax.fill_between(f, lo, hi, color=color, alpha=0.12)
        if np.any(np.isfinite(hi)):
            p = int(np.nanargmax(hi))
            ax.plot(f[p], hi[p], "o", color=color, ms=5)
            ax.annotate(f"{f[p]:.2f} Hz, {hi[p]:.4e} m", (f[p], hi[p]), fontsize=7, color=color,
                        textcoords="offset points", xytext=(8, 8 if color == COLORS[1] else -12))
        axr.plot(f, r, "o-", color=color, ms=3, lw=1, label=name)
        if timed:
            series[name]["point_wall_s"] = [number_or_null(v) for v in wall]
            series[name]["curve_wall_s"] = number_or_null(total)
            axt.semilogy(f, wall, "o-", color=color, ms=3, lw=1,
                         label=f"{name}: curve {total:.0f} s")
    if ratio:
        change = 100.0 * (curves[1][3] / curves[0][3] - 1.0)
        axq.axhline(0.0, color="#999999", lw=0.8)
        axq.plot(f, change, "o-", color=COLORS[1], ms=3, lw=1)
        axq.set_ylabel(f"y_max: {label_b}\nagainst {label_a} [%]", fontsize=7)
        axq.grid(True, lw=0.3)
    ax.set_ylabel("response amplitude, blade 2 [m]")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7, ncol=2, loc="lower left")
    axr.set_ylabel("R = 1 − δ/y_max")
    axr.set_ylim(-0.05, 1.05)
    axr.grid(True, lw=0.3)
    axr.legend(fontsize=7)
    if timed:
        axt.set_ylabel("wall time per point [s]")
        axt.grid(True, which="both", lw=0.3)
        axt.legend(fontsize=7)
    axes[-1].set_xlabel("frequency [Hz]")
    fig.suptitle(f"Bound curves: {label_a} and {label_b}", fontsize=10)
    fig.tight_layout()
    common.save_figure(fig, out)
    if out_json:
        common.write_text_atomically(out_json, json.dumps(
            {"units": "SI (Hz, m)", "freq_hz": f.tolist(), "curves": series}, indent=1))
    return f"wrote {out}"


if __name__ == "__main__":
    sys.exit(common.run("plot_ladder_curve.py", work))
