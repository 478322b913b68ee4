#!/usr/bin/python3
"""Plot the response bounds (minimum and maximum forced response) of a fricrom bounds file
(paper Fig. 9, "normalised response boundaries of blade 2").

Usage:
    /usr/bin/python3 scripts/plot_bounds.py BOUNDS.h5 OUT.png [--normalise]
    /usr/bin/python3 scripts/plot_bounds.py BOUNDS.h5 OUT.svg [--normalise]

Reads the HDF5 layout written by `fricrom bounds`:
  root attributes   fricrom_version, case_name, units, response_dof, command
  /bounds/freq_hz, /bounds/y_min_m, /bounds/y_max_m            float64 [P]
  /bounds/status_min, /bounds/status_max                       strings [P] ("converged" or not)
  /bounds attributes peak_freq_hz, robustness_at_peak          (both optional)
  /linear/freq_hz, /linear/free_amplitude_m, /linear/stick_amplitude_m   float64 [F]
The band between y_min and y_max is filled; non-converged bound points are marked with red
crosses; the free (dashed grey) and full-stick (dotted black) linear responses are references.
--normalise divides everything by the maximum of the full-stick response. With a single frequency
(P = 1) the two bounds are drawn as markers joined by the scatter delta.

Exit status: 0 on success, 2 on a missing dependency, a missing/unreadable file or dataset, or
inconsistent data. Only the Debian packages python3-matplotlib, python3-numpy and python3-h5py
are needed.
"""

import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import fricrom_plot_common as common  # noqa: E402  (checks numpy, matplotlib, h5py first)
from fricrom_plot_common import np, plt, h5py  # noqa: E402,F401

import argparse
import os

from fricrom_plot_common import InputError

SCRIPT = "plot_bounds.py"
COLOUR_MAX = "#1f4e9c"   # dark blue
COLOUR_MIN = "#2a9d8f"   # teal
COLOUR_BAND = "#9ecae1"  # light blue
COLOUR_PEAK = "#7b3294"  # purple


def read_bounds(path):
    h5 = common.open_h5(path)
    with h5:
        g = common.require_group(h5, "bounds")
        f = common.dataset(h5, "bounds/freq_hz")
        ymin = common.dataset(h5, "bounds/y_min_m")
        ymax = common.dataset(h5, "bounds/y_max_m")
        smin = common.strings(h5, "bounds/status_min")
        smax = common.strings(h5, "bounds/status_max")
        common.same_length(h5, "bounds", ["freq_hz", "y_min_m", "y_max_m", "status_min", "status_max"],
                           [f, ymin, ymax, smin, smax])
        if len(f) == 0:
            raise InputError(f"{path}: '/bounds/freq_hz' is empty")
        # bounds --stable-only: the bounds over stable candidates (NaN: none stable).
        stable = None
        if "stable_y_min_m" in g and "stable_y_max_m" in g:
            stable = (common.dataset(h5, "bounds/stable_y_min_m"),
                      common.dataset(h5, "bounds/stable_y_max_m"))
            common.same_length(h5, "bounds", ["freq_hz", "stable_y_min_m", "stable_y_max_m"],
                               [f, stable[0], stable[1]])
        lf = common.dataset(h5, "linear/freq_hz")
        free = common.dataset(h5, "linear/free_amplitude_m")
        stick = common.dataset(h5, "linear/stick_amplitude_m")
        common.same_length(h5, "linear", ["freq_hz", "free_amplitude_m", "stick_amplitude_m"],
                           [lf, free, stick])
        return {
            "case_name": common.attr_str(h5, "case_name", os.path.splitext(os.path.basename(path))[0]),
            "version": common.attr_str(h5, "fricrom_version", "?"),
            "response_dof": common.attr_str(h5, "response_dof"),
            "freq": f, "ymin": ymin, "ymax": ymax,
            "ok_min": np.array([s == "converged" for s in smin], dtype=bool),
            "ok_max": np.array([s == "converged" for s in smax], dtype=bool),
            "peak_freq": common.attr_float(g, "peak_freq_hz"),
            "robustness": common.attr_float(g, "robustness_at_peak"),
            "linear": {"freq": lf, "free": free, "stick": stick},
            "stable": stable,
        }


def _finite(x):
    return x is not None and np.isfinite(x)


def make_figure(res, normalise):
    lin = res["linear"]
    scale = common.full_stick_scale(lin, normalise)

    fig, ax = plt.subplots(figsize=(8.0, 5.6))
    reliable = []

    order = np.argsort(lin["freq"], kind="stable")
    lf = lin["freq"][order]
    free = lin["free"][order] / scale
    stick = lin["stick"][order] / scale
    ax.plot(lf, free, linestyle="--", color="0.55", linewidth=1.4, label="free (blades only)")
    ax.plot(lf, stick, linestyle=":", color="black", linewidth=1.8, label="full stick")
    reliable += [free, stick]

    order = np.argsort(res["freq"], kind="stable")
    f = res["freq"][order]
    ymin = res["ymin"][order] / scale
    ymax = res["ymax"][order] / scale
    ok_min = res["ok_min"][order] & np.isfinite(ymin)
    ok_max = res["ok_max"][order] & np.isfinite(ymax)
    show_min = np.where(ok_min, ymin, np.nan)
    show_max = np.where(ok_max, ymax, np.nan)
    reliable += [show_min, show_max]
    n_bad = int(np.count_nonzero(~res["ok_min"])) + int(np.count_nonzero(~res["ok_max"]))

    if len(f) == 1:
        if ok_min[0] and ok_max[0]:
            ax.plot([f[0], f[0]], [ymin[0], ymax[0]], color=COLOUR_BAND, linewidth=6,
                    solid_capstyle="butt", zorder=2, label="scatter \u03b4")
        ax.plot(f, show_max, linestyle="none", marker="_", markersize=18, markeredgewidth=2.5,
                color=COLOUR_MAX, zorder=4, label="maximum response")
        ax.plot(f, show_min, linestyle="none", marker="_", markersize=18, markeredgewidth=2.5,
                color=COLOUR_MIN, zorder=4, label="minimum response")
    else:
        both = ok_min & ok_max
        ax.fill_between(f, show_min, show_max, where=both, color=COLOUR_BAND, alpha=0.45,
                        linewidth=0, zorder=1, label="scatter \u03b4 (min\u2013max band)")
        marker = "." if len(f) < 60 else None
        ax.plot(f, show_max, color=COLOUR_MAX, linewidth=1.8, marker=marker, markersize=4,
                zorder=3, label="maximum response")
        ax.plot(f, show_min, color=COLOUR_MIN, linewidth=1.8, marker=marker, markersize=4,
                zorder=3, label="minimum response")

    if res.get("stable") is not None:
        # Drawn where they differ from the bounds; a curve of identical bounds says so in its label.
        smin = res["stable"][0][order] / scale
        smax = res["stable"][1][order] / scale
        differs = ~np.isclose(smin, ymin, rtol=1e-9, equal_nan=True) | \
            ~np.isclose(smax, ymax, rtol=1e-9, equal_nan=True)
        note = "" if np.any(differs) else " (= the bounds)"
        style = dict(linestyle="none", marker="o", markersize=6, fillstyle="none") if len(f) == 1 \
            else dict(linestyle="--", linewidth=1.4, marker="o" if len(f) < 60 else None,
                      markersize=5, fillstyle="none")
        ax.plot(f, smax, color=COLOUR_MAX, zorder=4, label="max over stable solutions" + note,
                **style)
        ax.plot(f, smin, color=COLOUR_MIN, zorder=4, label="min over stable solutions" + note,
                **style)
        reliable += [smin, smax]
        none = ~np.isfinite(smin) & ~np.isfinite(smax) & (ok_min | ok_max)
        if np.any(none):
            ax.plot(f[none], np.zeros(np.count_nonzero(none)), linestyle="none", marker="^",
                    color="0.35", markersize=7, clip_on=False, zorder=5,
                    label=f"no stable candidate ({np.count_nonzero(none)} frequencies)")

    finite = np.concatenate([r[np.isfinite(r)] for r in reliable] + [np.zeros(1)])
    top = float(np.max(finite)) * 1.12 if np.max(finite) > 0.0 else 1.0

    bad_f, bad_a = [], []
    for ok, y in ((res["ok_min"][order], ymin), (res["ok_max"][order], ymax)):
        keep = ~ok & np.isfinite(y) & np.isfinite(f)
        bad_f += list(f[keep])
        bad_a += list(y[keep])
    lost = n_bad - len(bad_f)  # non-converged points without a finite amplitude
    if bad_f:
        bad_a = np.asarray(bad_a)
        clipped = bool(np.any(bad_a > top))
        ax.plot(bad_f, np.minimum(bad_a, top), linestyle="none", marker="x", color="red",
                markersize=7, markeredgewidth=1.6, clip_on=False, zorder=5,
                label=f"not converged: {n_bad}" + (f" ({lost} without amplitude)" if lost else "")
                + (", top clipped" if clipped else ""))
    elif lost:
        ax.plot([], [], linestyle="none", marker="x", color="red",
                label=f"not converged ({lost}, no amplitude)")
    ax.set_ylim(0.0, top)

    # Peak of the maximum response: vertical line, R annotated there.
    peak = res["peak_freq"]
    if _finite(peak):
        ax.axvline(peak, color=COLOUR_PEAK, linestyle="-.", linewidth=1.1, zorder=2)
        lines = [f"peak {peak:.2f} Hz" if len(f) > 1 else f"f = {peak:.2f} Hz"]
        if len(f) == 1:
            for name, y, ok in (("y_max", ymax[0], ok_max[0]), ("y_min", ymin[0], ok_min[0])):
                if ok:
                    lines.append(f"{name} = {y:.4f}" if normalise else f"{name} = {y:.4e} m")
                else:
                    lines.append(f"{name}: not converged")
        if _finite(res["robustness"]):
            lines.append(f"R = {res['robustness']:.3f}")
        elif res["robustness"] is not None:
            lines.append("R = n/a (bounds failed)")
        lo, hi = ax.get_xlim()
        right_side = (peak - lo) < 0.7 * (hi - lo)
        y_text, va, dx = 0.97 * top, "top", 8
        if len(f) == 1 and (ok_min[0] or ok_max[0]):
            # Single frequency: the values go beside the markers.
            y_text, va, dx = float(np.nanmean([show_min[0], show_max[0]])), "center", 22
        ax.annotate("\n".join(lines), xy=(peak, y_text), xycoords="data",
                    xytext=(dx if right_side else -dx, 0), textcoords="offset points",
                    ha="left" if right_side else "right", va=va, fontsize=9, color=COLOUR_PEAK,
                    bbox={"boxstyle": "round,pad=0.3", "fc": "white", "ec": COLOUR_PEAK,
                          "lw": 0.8, "alpha": 1.0})

    ax.set_xlabel("Frequency [Hz]")
    dof = res["response_dof"] or "response DOF"
    if normalise:
        ax.set_ylabel(f"Normalised amplitude of {dof} (/ max full-stick) [-]")
    else:
        ax.set_ylabel(f"Amplitude of {dof} [m]")
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3), useMathText=True)
    title = f"Response bounds: {res['case_name']}"
    if len(f) == 1:
        title += f" at {f[0]:.2f} Hz"
    ax.set_title(title)
    ax.grid(True, color="0.9", linewidth=0.8)
    # Below the axes: inside, it would hide the curves or the peak annotation.
    handles, labels = ax.get_legend_handles_labels()
    rows = -(-len(handles) // 3)
    fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 0.02), ncol=3,
               fontsize=9, frameon=False)
    common.footer(fig, res["version"])
    fig.tight_layout(rect=(0.0, 0.035 + 0.045 * rows, 1.0, 1.0))
    return fig


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Plot the response bounds of a fricrom bounds file (HDF5) to PNG or SVG "
                    "(paper Fig. 9).")
    parser.add_argument("bounds", metavar="BOUNDS.h5", help="fricrom bounds file")
    parser.add_argument("out", metavar="OUT.png", help="output image (.png or .svg)")
    parser.add_argument("--normalise", "--normalize", action="store_true",
                        help="divide every curve by the maximum of the full-stick curve")
    args = parser.parse_args(argv)

    def work():
        common.check_output(args.out)
        res = read_bounds(args.bounds)
        fig = make_figure(res, args.normalise)
        common.save_figure(fig, args.out)
        return f"wrote {args.out}"

    return common.run(SCRIPT, work)


if __name__ == "__main__":
    sys.exit(main())
