#!/usr/bin/python3
"""Plot the robustness R over a design parameter from a fricrom sweep file (paper Fig. 11, 14),
with the NOA result(s) and the response bounds below.

Usage:
    /usr/bin/python3 scripts/plot_sweep.py SWEEP.h5 OUT.png [--noa NOA.json ...] [--paper-noa P,R]
e.g.
    /usr/bin/python3 scripts/plot_sweep.py results/lumped3/sweep_gamma/sweep.h5 sweep_gamma.png \\
        --noa results/lumped3/noa_gamma.json --paper-noa 0.354,0.974

Reads the HDF5 layout written by `fricrom sweep`:
  root attributes   fricrom_version, case_name, units, response_dof, command
  /sweep/values     float64 [S]   parameter values
  /sweep/robustness float64 [S]   R = 1 - (y_max - y_min) / y_max (NaN where the bounds failed)
  /sweep/y_min_m, /sweep/y_max_m  float64 [S]
  /sweep attributes param (e.g. "gamma"), reference_freq_hz (NaN when the peak was tracked)
--noa NOA.json (repeatable; from `fricrom noa ... --json`): keys "param", "p_opt", "R_opt" and
optionally "objective"; drawn as a star labelled "NOA (objective)".
--paper-noa P,R adds the paper's NOA point as a hollow marker (gamma: 0.354,0.974;
beta: 0.0794,1).

Exit status: 0 on success, 2 on a missing dependency, a missing/unreadable file or dataset, or
inconsistent data. Only the Debian packages python3-matplotlib, python3-numpy and python3-h5py
are needed.
"""

import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import fricrom_plot_common as common  # noqa: E402  (checks numpy, matplotlib, h5py first)
from fricrom_plot_common import np, plt, h5py  # noqa: E402,F401

import argparse
import json
import math
import os

from fricrom_plot_common import InputError

SCRIPT = "plot_sweep.py"
COLOUR_R = "#1f4e9c"
COLOUR_MAX = "#1f4e9c"
COLOUR_MIN = "#2a9d8f"
COLOUR_BAND = "#9ecae1"
NOA_COLOURS = ["#e6a100", "#d95f02", "#7570b3", "#e7298a"]


def read_sweep(path):
    h5 = common.open_h5(path)
    with h5:
        g = common.require_group(h5, "sweep")
        p = common.dataset(h5, "sweep/values")
        r = common.dataset(h5, "sweep/robustness")
        ymin = common.dataset(h5, "sweep/y_min_m")
        ymax = common.dataset(h5, "sweep/y_max_m")
        common.same_length(h5, "sweep", ["values", "robustness", "y_min_m", "y_max_m"],
                           [p, r, ymin, ymax])
        if len(p) == 0:
            raise InputError(f"{path}: '/sweep/values' is empty")
        param = common.attr_str(g, "param")
        if not param:
            raise InputError(f"{path}: attribute 'param' of '/sweep' is missing")
        return {
            "case_name": common.attr_str(h5, "case_name", os.path.splitext(os.path.basename(path))[0]),
            "version": common.attr_str(h5, "fricrom_version", "?"),
            "response_dof": common.attr_str(h5, "response_dof"),
            "param": param, "ref_freq": common.attr_float(g, "reference_freq_hz"),
            "values": p, "R": r, "ymin": ymin, "ymax": ymax,
        }


def _number(data, key, path, required=True):
    v = data.get(key)
    if v is None:
        if required:
            raise InputError(f"{path}: key '{key}' is missing or null")
        return None
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise InputError(f"{path}: key '{key}' must be a number, got {v!r}")
    return float(v)


def read_noa(path, sweep_param):
    if not os.path.isfile(path):
        raise InputError(f"NOA file '{path}' does not exist")
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        raise InputError(f"cannot read '{path}' as JSON: {e}") from e
    if not isinstance(data, dict):
        raise InputError(f"{path}: expected a JSON object")
    p = _number(data, "p_opt", path)
    r = _number(data, "R_opt", path, required=False)
    param = data.get("param")
    if param is not None and str(param) != sweep_param:
        common.warn(SCRIPT, f"{path}: NOA parameter '{param}' differs from the sweep's "
                            f"'{sweep_param}'; drawn anyway")
    if r is None or not math.isfinite(r):
        common.warn(SCRIPT, f"{path}: R_opt is null/NaN; the NOA point is drawn on the p axis")
    objective = data.get("objective")
    label = f"NOA ({objective})" if objective else "NOA"
    return {"p": p, "R": r, "label": label, "path": path}


def parse_point(text):
    try:
        p, r = (float(x) for x in text.split(","))
    except ValueError as e:
        raise InputError(f"--paper-noa expects P,R (two numbers), got '{text}'") from e
    if not (math.isfinite(p) and math.isfinite(r)):
        raise InputError(f"--paper-noa values must be finite, got '{text}'")
    return p, r


def make_figure(res, noas, paper):
    sym = common.param_symbol(res["param"])
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(8.0, 6.4), sharex=True,
                                 gridspec_kw={"height_ratios": [3.0, 1.4]})
    order = np.argsort(res["values"], kind="stable")
    p = res["values"][order]
    r = res["R"][order]
    ymin = res["ymin"][order]
    ymax = res["ymax"][order]
    ok = np.isfinite(r)

    ax.axhline(1.0, color="0.35", linestyle=":", linewidth=1.2, zorder=1, label="R = 1 (unique response)")
    marker_size = 5 if len(p) <= 60 else 3
    ax.plot(p, r, color=COLOUR_R, linewidth=1.6, marker="o", markersize=marker_size, zorder=3,
            label="manual sweep")
    n_failed = int(np.count_nonzero(~ok))
    if n_failed:
        ax.plot(p[~ok], np.zeros(n_failed), linestyle="none", marker="x", color="red",
                markersize=7, markeredgewidth=1.6, clip_on=False, zorder=5,
                label=f"bounds failed ({n_failed}; R undefined)")

    for i, noa in enumerate(noas):
        colour = NOA_COLOURS[i % len(NOA_COLOURS)]
        on_axis = noa["R"] is None or not math.isfinite(noa["R"])
        y = 0.0 if on_axis else noa["R"]
        text = f"{sym} = {noa['p']:.4g}, R = " + ("n/a" if on_axis else f"{noa['R']:.3f}")
        ax.plot([noa["p"]], [y], linestyle="none", marker="*", markersize=16, color=colour,
                markeredgecolor="black", markeredgewidth=0.7, zorder=6, clip_on=False,
                label=f"{noa['label']}: {text}")
    if paper is not None:
        ax.plot([paper[0]], [paper[1]], linestyle="none", marker="o", markersize=11,
                markerfacecolor="none", markeredgecolor="black", markeredgewidth=1.5, zorder=6,
                clip_on=False,
                label=f"paper NOA: {sym} = {paper[0]:.4g}, R = {paper[1]:.3f}")

    ax.set_ylim(0.0, 1.05)
    ax.set_ylabel("robustness R [-]")
    title = f"Robustness over {sym}"
    if res["ref_freq"] is not None and math.isfinite(res["ref_freq"]):
        title += f" at {res['ref_freq']:.2f} Hz"
    else:
        title += " (at the tracked resonance)"
    ax.set_title(f"{title}: {res['case_name']}")
    ax.grid(True, color="0.9", linewidth=0.8)
    ax.legend(loc="best", fontsize=8.5, framealpha=0.92)

    both = np.isfinite(ymin) & np.isfinite(ymax)
    bx.fill_between(p, np.where(both, ymin, np.nan), np.where(both, ymax, np.nan), where=both,
                    color=COLOUR_BAND, alpha=0.45, linewidth=0, zorder=1)
    bx.plot(p, ymax, color=COLOUR_MAX, linewidth=1.4, marker="^", markersize=3.5, zorder=3,
            label="y_max")
    bx.plot(p, ymin, color=COLOUR_MIN, linewidth=1.4, marker="v", markersize=3.5, zorder=3,
            label="y_min")
    fin = np.concatenate([ymin[np.isfinite(ymin)], ymax[np.isfinite(ymax)]])
    if fin.size:
        lo, hi = float(fin.min()), float(fin.max())
        pad = 0.1 * (hi - lo) if hi > lo else 0.05 * max(abs(hi), 1e-12)
        bx.set_ylim(max(0.0, lo - pad) if lo >= 0 else lo - pad, hi + pad)
    dof = res["response_dof"] or "response"
    bx.set_ylabel(f"{dof} amplitude [m]", fontsize=9)
    bx.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3), useMathText=True)
    bx.set_xlabel(f"{sym} ({res['param']}) [-]" if sym != res["param"] else f"{sym} [-]")
    bx.grid(True, color="0.9", linewidth=0.8)
    bx.legend(loc="best", fontsize=8, ncol=2, framealpha=0.92)

    xs = [p.min(), p.max()] + [n["p"] for n in noas] + ([paper[0]] if paper else [])
    lo, hi = min(xs), max(xs)
    pad = 0.04 * (hi - lo) if hi > lo else 0.05 * max(abs(hi), 1.0)
    ax.set_xlim(lo - pad, hi + pad)
    common.footer(fig, res["version"])
    fig.tight_layout()
    return fig


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Plot robustness R over a design parameter from a fricrom sweep file (HDF5) "
                    "to PNG or SVG (paper Fig. 11, 14).")
    parser.add_argument("sweep", metavar="SWEEP.h5", help="fricrom sweep file")
    parser.add_argument("out", metavar="OUT.png", help="output image (.png or .svg)")
    parser.add_argument("--noa", metavar="NOA.json", action="append", default=[],
                        help="NOA result (fricrom noa --json); repeatable")
    parser.add_argument("--paper-noa", metavar="P,R",
                        help="the paper's NOA point, drawn hollow (e.g. 0.354,0.974 for gamma)")
    args = parser.parse_args(argv)

    def work():
        common.check_output(args.out)
        paper = parse_point(args.paper_noa) if args.paper_noa else None
        res = read_sweep(args.sweep)
        noas = [read_noa(path, res["param"]) for path in args.noa]
        fig = make_figure(res, noas, paper)
        common.save_figure(fig, args.out)
        return f"wrote {args.out}"

    return common.run(SCRIPT, work)


if __name__ == "__main__":
    sys.exit(main())
