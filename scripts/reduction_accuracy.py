#!/usr/bin/python3
"""Accuracy against cost of the Craig-Bampton reduction: runs `fricrom reduce` on one FE model for
a list of fixed-interface mode counts and charts the relative error of the reduced
eigenfrequencies (modes 1, 5, 10 of the full model) and of the static response to a body load
(at the boundary/contact nodes, exact by construction, and at the recovered interior DOFs),
against the number of modes and against the reduction time.

Usage:
    /usr/bin/python3 scripts/reduction_accuracy.py [--model JOB.inp] [--boundary SETS]
        [--modes 5,10,20,...] [--fricrom build/fricrom] [--out docs/figures/reduction_accuracy.png]
Writes the figure and a CSV beside it (same name, .csv). Needs python3-matplotlib, python3-numpy
(and python3-h5py, checked by fricrom_plot_common).
"""

import argparse
import csv
import io
import json
import os
import subprocess
import sys
import tempfile

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fricrom_plot_common as common  # noqa: E402  (checks numpy, matplotlib, h5py first)
from fricrom_plot_common import InputError, np, plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TRACKED = (1, 5, 10)


def run_reduce(fricrom, model, boundary, modes, compare, workdir):
    out = os.path.join(workdir, f"r{modes}.h5")
    cmd = [fricrom, "reduce", model, "--boundary", boundary, "--modes", str(modes), "--to", out,
           "--json", "--quiet", "--compare-modes", str(compare)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 1):
        raise InputError(f"{' '.join(cmd)} failed (exit {p.returncode}): {p.stderr.strip()}")
    return json.loads(p.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--model", default=os.path.join(ROOT, "meshes/blade_sector/coarse/blade_sector.inp"))
    ap.add_argument("--boundary", default="CONTACT_LEFT,CONTACT_RIGHT,EXCITATION,RESPONSE")
    ap.add_argument("--modes", default="2,5,10,20,40,80,160,320")
    ap.add_argument("--fricrom", default=os.path.join(ROOT, "build/fricrom"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs/figures/reduction_accuracy.png"))
    args = ap.parse_args()

    def work():
        common.check_output(args.out)
        if not os.path.exists(args.fricrom):
            raise InputError(f"no fricrom executable at {args.fricrom} (build first: cmake --build build)")
        counts = [int(x) for x in args.modes.split(",") if x.strip()]
        compare = max(TRACKED)
        rows = []
        with tempfile.TemporaryDirectory() as tmp:
            for n in counts:
                j = run_reduce(args.fricrom, args.model, args.boundary, n, compare, tmp)
                table = j.get("eigen_comparison") or []
                if len(table) < compare:
                    raise InputError(f"{args.model}: only {len(table)} compared modes with --modes {n}")
                st = j.get("static_body_load") or {}
                rows.append({
                    "modes": j["modes"], "boundary_dofs": j["boundary_dofs"], "full_dofs": j["full_dofs"],
                    "reduction_s": j["timings"]["reduction_s"], "wall_s": j["wall_s"],
                    "highest_fixed_interface_hz": (j["fixed_interface_hz"] or [0])[-1],
                    **{f"err_mode{m}": table[m - 1]["rel_error"] for m in TRACKED},
                    **{f"full_hz_mode{m}": table[m - 1]["full_hz"] for m in TRACKED},
                    "err_static_boundary": st.get("rel_error_at_boundary"),
                    "err_static_interior": st.get("rel_error_interior_recovered"),
                })
                print(f"modes {n:4d}: reduction {rows[-1]['reduction_s']:.3f} s, "
                      + ", ".join(f"mode {m} {rows[-1][f'err_mode{m}']:.2e}" for m in TRACKED)
                      + f", static: boundary {rows[-1]['err_static_boundary']:.1e}"
                      + f" interior {rows[-1]['err_static_interior']:.2e}", file=sys.stderr)
        buf = io.StringIO()
        w = csv.DictWriter(buf, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
        csv_out = os.path.splitext(args.out)[0] + ".csv"
        common.write_text_atomically(csv_out, buf.getvalue())

        fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
        q = np.array([r["modes"] for r in rows])
        t = np.array([r["reduction_s"] for r in rows])
        floor = 1e-16
        for m, marker in zip(TRACKED, "os^"):
            e = np.maximum([r[f"err_mode{m}"] for r in rows], floor)
            label = f"mode {m} ({rows[0][f'full_hz_mode{m}']:.0f} Hz)"
            axes[0].loglog(q, e, marker + "-", label=label)
            axes[1].loglog(t, e, marker + "-", label=label)
        for key, style, label in (("err_static_interior", "d--", "static body load, interior (recovered)"),
                                  ("err_static_boundary", "x:", "static body load, contact/boundary nodes")):
            es = np.array([r[key] if r[key] is not None else np.nan for r in rows])
            axes[0].loglog(q, np.maximum(es, floor), style, color="0.3", label=label)
            axes[1].loglog(t, np.maximum(es, floor), style, color="0.3", label=label)
        for ax in axes:
            ax.axhline(1e-6, color="r", lw=0.8, ls=":")
            ax.grid(True, which="both", alpha=0.3)
            ax.set_ylabel("relative error (reduced vs full)")
        axes[0].set_xlabel("fixed-interface modes kept")
        axes[1].set_xlabel("reduction wall time [s] (whole Craig-Bampton step)")
        axes[0].legend(fontsize=8)
        r0 = rows[0]
        fig.suptitle(f"Craig-Bampton accuracy vs cost: {os.path.basename(args.model)}, "
                     f"{r0['full_dofs']} DOFs, {r0['boundary_dofs']} boundary DOFs", fontsize=10)
        fig.tight_layout()
        common.save_figure(fig, args.out)
        return f"wrote {args.out} and {csv_out}"

    return common.run("reduction_accuracy.py", work)


if __name__ == "__main__":
    sys.exit(main())
