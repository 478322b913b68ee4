#!/usr/bin/python3
"""Plot the robustness R over a design parameter for several fricrom sweeps in one figure (e.g. a
bladed disk's engine orders), with each one's NOA result and the response bounds below.

Usage:
    /usr/bin/python3 scripts/plot_disk_design.py OUT.png --curve LABEL SWEEP.h5 [NOA.json] \\
        [--curve LABEL SWEEP.h5 [NOA.json] ...] [--title TEXT]
e.g.
    /usr/bin/python3 scripts/plot_disk_design.py docs/figures/disk24_rpm_design.png \\
        --curve "EO 2" OUT/eo2/sweep.h5 OUT/eo2_noa.json \\
        --curve "EO 12" OUT/eo12/sweep.h5 OUT/eo12_noa.json

Each SWEEP.h5 is the file `fricrom sweep` writes (layout in scripts/plot_sweep.py); each NOA.json
the one `fricrom noa --json` writes (p_opt, R_opt). The sweeps must share their parameter.

Exit status: 0 on success, 2 on a missing dependency, a missing/unreadable file or dataset, or
inconsistent data. Only the Debian packages python3-matplotlib, python3-numpy and python3-h5py
are needed.
"""

import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import fricrom_plot_common as common  # noqa: E402  (checks numpy, matplotlib, h5py first)
from fricrom_plot_common import np, plt, InputError  # noqa: E402
from plot_sweep import read_sweep, read_noa  # noqa: E402

import argparse  # noqa: E402
import math  # noqa: E402

SCRIPT = "plot_disk_design.py"
COLOURS = ["#1f4e9c", "#d95f02", "#2a9d8f", "#7570b3"]


def parse_curves(raw):
    curves = []
    for item in raw:
        if len(item) not in (2, 3):
            raise InputError(f"--curve expects LABEL SWEEP.h5 [NOA.json], got {item}")
        sweep = read_sweep(item[1])
        noa = read_noa(item[2], sweep["param"]) if len(item) == 3 else None
        curves.append({"label": item[0], "sweep": sweep, "noa": noa})
    params = {c["sweep"]["param"] for c in curves}
    if len(params) != 1:
        raise InputError(f"the sweeps have different parameters: {sorted(params)}")
    return curves


def make_figure(curves, title):
    param = curves[0]["sweep"]["param"]
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(8.0, 6.6), sharex=True,
                                 gridspec_kw={"height_ratios": [3.0, 1.8]})
    ax.axhline(1.0, color="0.35", linestyle=":", linewidth=1.2, zorder=1,
               label="R = 1 (unique response)")
    for i, c in enumerate(curves):
        s, colour = c["sweep"], COLOURS[i % len(COLOURS)]
        order = np.argsort(s["values"], kind="stable")
        p, r = s["values"][order], s["R"][order]
        ymin, ymax = s["ymin"][order], s["ymax"][order]
        freq = s["ref_freq"]
        at = f"{freq:.2f} Hz" if freq is not None and math.isfinite(freq) else "tracked peak"
        ax.plot(p, r, color=colour, linewidth=1.6, marker="o", markersize=4, zorder=3,
                label=f"{c['label']}: sweep at {at}")
        bad = ~np.isfinite(r)
        if bad.any():
            ax.plot(p[bad], np.zeros(int(bad.sum())), linestyle="none", marker="x", color="red",
                    markersize=7, clip_on=False, zorder=5,
                    label=f"{c['label']}: bounds failed ({int(bad.sum())})")
        noa = c["noa"]
        if noa is not None:
            on_axis = noa["R"] is None or not math.isfinite(noa["R"])
            ax.plot([noa["p"]], [0.0 if on_axis else noa["R"]], linestyle="none", marker="*",
                    markersize=15, color=colour, markeredgecolor="black", markeredgewidth=0.7,
                    zorder=6, clip_on=False,
                    label=f"{c['label']}: {noa['label']} {param} = {noa['p']:.4g}, R = "
                          + ("n/a" if on_axis else f"{noa['R']:.3f}"))
        both = np.isfinite(ymin) & np.isfinite(ymax)
        bx.fill_between(p, np.where(both, ymin, np.nan), np.where(both, ymax, np.nan),
                        where=both, color=colour, alpha=0.25, linewidth=0)
        bx.plot(p, ymax, color=colour, linewidth=1.3, marker="^", markersize=3,
                label=f"{c['label']} y_max")
        bx.plot(p, ymin, color=colour, linewidth=1.3, linestyle="--", marker="v", markersize=3,
                label=f"{c['label']} y_min")
    ax.set_ylim(0.0, 1.05)
    ax.set_ylabel("robustness R [-]")
    ax.set_title(title or f"Robustness over {param}: {curves[0]['sweep']['case_name']}")
    ax.grid(True, color="0.9", linewidth=0.8)
    ax.legend(loc="lower left", fontsize=8, framealpha=0.92)
    dof = curves[0]["sweep"]["response_dof"] or "response"
    bx.set_ylabel(f"{dof} amplitude [m]", fontsize=9)
    bx.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3), useMathText=True)
    bx.set_xlabel(f"{param}")
    bx.grid(True, color="0.9", linewidth=0.8)
    bx.legend(loc="best", fontsize=7.5, ncol=2, framealpha=0.92)
    common.footer(fig, curves[0]["sweep"]["version"])
    fig.tight_layout()
    return fig


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Plot R over a design parameter for several fricrom sweeps (HDF5), each with "
                    "its NOA result, to PNG or SVG.")
    parser.add_argument("out", metavar="OUT.png", help="output image (.png or .svg)")
    parser.add_argument("--curve", nargs="+", action="append", required=True,
                        metavar="ARG", help="LABEL SWEEP.h5 [NOA.json]; repeatable")
    parser.add_argument("--title", help="figure title")
    args = parser.parse_args(argv)

    def work():
        common.check_output(args.out)
        fig = make_figure(parse_curves(args.curve), args.title)
        common.save_figure(fig, args.out)
        return f"wrote {args.out}"

    return common.run(SCRIPT, work)


if __name__ == "__main__":
    sys.exit(main())
