#!/usr/bin/python3
"""Plot a certification (`fricrom verify --json`) against its bounds: one panel per verify file.

Usage:
    /usr/bin/python3 scripts/plot_verify.py OUT.png VERIFY.json [VERIFY.json ...]
e.g.
    /usr/bin/python3 scripts/plot_verify.py docs/figures/cascade_verify.png fe_verify_1040.json \\
        fe_verify_peak.json

Each panel shows the HBM bounds [y_min, y_max] (band, with the 2 % harmonic-truncation margin the
time integrations are judged by), the range of the α-sampled solutions (bar) and each time
integration's steady amplitude (marker: filled if steady and inside, hollow red otherwise) with
the free vibration that rode on it over its last window (whisker: ± half the spread of the
one-period amplitudes), and the harmonic-balance solution Newton refines from its final state
(purple dot, key hbm_from_state). Where verify restarted the optimisation from solutions beyond
the optimised bounds (key bounds_improved), those are drawn dashed. Reads the keys y_min, y_max, freq_hz, sampling.{sampled_min, sampled_max,
converged, samples}, time_integration[].{amplitude, status, inside, free_vibration, periods,
wall_s}, certified.

Exit status: 0 on success, 2 on a missing dependency, a missing/unreadable file or key.
"""

import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import fricrom_plot_common as common  # noqa: E402  (checks numpy, matplotlib, h5py first)
from fricrom_plot_common import np, plt  # noqa: E402

import argparse
import json
import math

from fricrom_plot_common import InputError

SCRIPT = "plot_verify.py"


def number(v):
    return float("nan") if v is None else float(v)


def read_verify(path):
    try:
        with open(path, encoding="utf-8") as f:
            v = json.load(f)
    except json.JSONDecodeError as e:
        raise InputError(f"{path}: not JSON ({e})")
    try:
        s = v["sampling"]
        runs = [{"y": number(r["amplitude"]), "status": str(r["status"]), "inside": bool(r["inside"]),
                 "free": number(r.get("free_vibration", 0.0)), "periods": int(r["periods"]),
                 "wall": number(r.get("wall_s")),
                 "hbm": number((r.get("hbm_from_state") or {}).get("amplitude"))}
                for r in v["time_integration"]]
        imp = v.get("bounds_improved") or {}
        return {"freq": float(v["freq_hz"]), "lo": number(v["y_min"]), "hi": number(v["y_max"]),
                "restarts": int(imp.get("restarts", 0)),
                "lo_opt": number(imp.get("y_min_optimised")), "hi_opt": number(imp.get("y_max_optimised")),
                "smin": number(s["sampled_min"]), "smax": number(s["sampled_max"]),
                "solved": int(s["converged"]), "samples": int(s["samples"]), "runs": runs,
                "certified": bool(v["certified"]), "path": path}
    except (KeyError, TypeError, ValueError) as e:
        raise InputError(f"{path}: missing or malformed key {e}")


def draw(ax, d):
    lo, hi = d["lo"], d["hi"]
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise InputError(f"{d['path']}: the bounds are not finite (the bounds did not converge)")
    n = max(len(d["runs"]), 1)
    ax.axhspan(lo * 0.98, hi * 1.02, color="0.92", label="bounds ± 2 % (H truncation)")
    ax.axhspan(lo, hi, color="tab:blue", alpha=0.18, label="HBM bounds [y_min, y_max]")
    if d["restarts"] > 0:
        for k, v in enumerate((d["lo_opt"], d["hi_opt"])):
            if math.isfinite(v) and v not in (lo, hi):
                ax.axhline(v, color="tab:blue", ls="--", lw=1,
                           label="optimised bound before verify's restarts (local)" if k == 1 or d["lo_opt"] == lo else None)
    if math.isfinite(d["smin"]):
        # The sampled range: a bar with end markers (visible when all samples coincide).
        ax.plot([-0.6, -0.6], [d["smin"], d["smax"]], color="tab:green", lw=5, marker="_", ms=16,
                mew=2, solid_capstyle="butt",
                label=f"α samples: range of {d['solved']}/{d['samples']} solved")
    for i, r in enumerate(d["runs"]):
        ok = r["status"] == "steady-state" and r["inside"]
        y = r["y"] if math.isfinite(r["y"]) else lo
        half = 0.5 * r["free"] * y if math.isfinite(r["free"]) else 0.0
        ax.errorbar([i], [y], yerr=[[half], [half]], fmt="D", ms=7, capsize=4,
                    color="black" if ok else "tab:red", mfc="black" if ok else "none",
                    label="time integration: filled = steady, inside; hollow red = not\n(whisker: free vibration)" if i == 0 else None)
        ax.annotate(f"{r['periods']} periods\n{r['wall']:.0f} s", (i, y), xytext=(8, -4),
                    textcoords="offset points", fontsize=7)
        if math.isfinite(r["hbm"]):
            ax.plot([i - 0.18], [r["hbm"]], "o", ms=6, color="tab:purple",
                    label="HBM solution refined from the run's state" if i == 0 else None)
    ax.set_xlim(-1.2, n - 0.3)
    ax.set_xticks([-0.6] + list(range(len(d["runs"]))))
    ax.set_xticklabels(["α samples"] + [f"run {i + 1}" for i in range(len(d["runs"]))], fontsize=8)
    ax.set_ylabel("response amplitude [m]")
    verdict = "certified" if d["certified"] else "NOT certified"
    ax.set_title(f"{d['freq']:g} Hz: {verdict}", fontsize=10)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=2, frameon=False)


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Plot fricrom verify results (bounds, alpha samples, time integrations).")
    parser.add_argument("out", metavar="OUT.png", help="output image (.png or .svg)")
    parser.add_argument("verify", metavar="VERIFY.json", nargs="+", help="fricrom verify --json")
    args = parser.parse_args(argv)

    def work():
        common.check_output(args.out)
        data = [read_verify(p) for p in args.verify]
        fig, axes = plt.subplots(1, len(data), figsize=(6.6 * len(data), 5.6), squeeze=False)
        for ax, d in zip(axes[0], data):
            draw(ax, d)
        fig.suptitle("Certification of the bounds: α sampling and time integration", fontsize=11)
        fig.tight_layout()
        common.save_figure(fig, args.out)
        return f"wrote {args.out}"

    return common.run(SCRIPT, work)


if __name__ == "__main__":
    sys.exit(main())
