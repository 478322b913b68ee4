#!/usr/bin/python3
"""Nodal-diameter map of a cyclic sector: its natural frequencies against the nodal diameter.

Usage:
    /usr/bin/python3 scripts/plot_nd_map.py MODES.json OUT.png [--fmax HZ] [--families N]

MODES.json is `fricrom modes CASE --json` of a cyclic case (schema fricrom-assembly-2). Draws
the full-stick families (the k-th frequency of every nodal diameter joined), the free system's
frequencies (the blades without dampers: the same at every nodal diameter, the disk being rigid)
as dashed lines, and the nodal diameter harmonic 1 of the engine order excites (h·EO folded into
0..N/2). Units: Hz. Needs python3-matplotlib.
"""
import argparse
import json
import os
import sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fricrom_plot_common as common  # noqa: E402
from fricrom_plot_common import InputError, plt  # noqa: E402


def read_modes(path):
    try:
        with open(path, encoding="utf-8") as f:
            j = json.load(f)
    except (OSError, ValueError) as e:
        raise InputError(f"{path}: cannot read the modes JSON ({e})")
    for key in ("stick_by_nodal_diameter", "free_hz", "sectors", "engine_order",
                "harmonic_nodal_diameters"):
        if key not in j:
            raise InputError(f"{path}: no '{key}' (is it `fricrom modes CASE --json` of a cyclic "
                             "case?)")
    return j


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("modes")
    ap.add_argument("out")
    ap.add_argument("--fmax", type=float, default=None, help="upper frequency shown [Hz]")
    ap.add_argument("--families", type=int, default=6, help="full-stick families drawn")
    args = ap.parse_args()

    def work():
        common.check_output(args.out)
        j = read_modes(args.modes)
        per_nd = sorted(j["stick_by_nodal_diameter"], key=lambda e: e["nodal_diameter"])
        nds = [e["nodal_diameter"] for e in per_nd]
        fams = min(args.families, min(len(e["stick_hz"]) for e in per_nd))
        fig, ax = plt.subplots(figsize=(7.5, 5.2))
        top = 0.0
        for k in range(fams):
            f = [e["stick_hz"][k] for e in per_nd]
            top = max(top, max(f))
            ax.plot(nds, f, "o-", ms=4, lw=1.2, label="full stick" if k == 0 else None,
                    color="tab:blue")
        fmax = args.fmax or 1.1 * top
        free = [v for v in j["free_hz"] if v <= fmax]
        for i, v in enumerate(free):
            ax.axhline(v, ls="--", lw=0.9, color="tab:orange",
                       label="free (no contact), every ND" if i == 0 else None)
        nd1 = j["harmonic_nodal_diameters"][0]
        ax.axvline(nd1, color="tab:red", lw=1.0, ls=":",
                   label=f"EO {j['engine_order']}: harmonic 1 at ND {nd1}")
        ax.set_xlim(-0.3, max(nds) + 0.3)
        ax.set_ylim(0, fmax)
        ax.set_xlabel("nodal diameter")
        ax.set_ylabel("natural frequency [Hz]")
        ax.set_title(f"Nodal-diameter map, one sector of {j['sectors']} ({j.get('case', '')})")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3)
        fig.tight_layout()
        common.save_figure(fig, args.out)
        plt.close(fig)
        return f"wrote {args.out}"

    return common.run("plot_nd_map.py", work)


if __name__ == "__main__":
    sys.exit(main())
