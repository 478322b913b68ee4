#!/usr/bin/python3
"""Failure map of fricrom's fixed-alpha solves: where they converge, fail, crawl or land on an
unstable solution, over frequency x design parameter x alpha family.

Usage:
    /usr/bin/python3 scripts/failure_map.py CASE.toml OUT_DIR --freqs F1,F2,... \
        [--param gamma --values 0,0.15,0.3] [--fricrom build/fricrom] [--jobs 2] [--harmonics H]

Each cell is one `fricrom frf CASE --freq F --alpha A --set PARAM=V --stability --json` run, timed
(wall seconds, the process included). Alpha families: "zero" (alpha = 0), "corner+" and "corner-"
(the interface corners: every tangential direction t1 of an interface at +-1 with the left and
right faces of the first damper against those of the second, t2 = 0; on a case whose contacts
carry no interface names, alternating +-1), and "random" (uniform in [-1, 1], seed 7).
Writes OUT_DIR/failure_map.json (every cell: status, amplitude [m], Hill verdict, largest
Floquet exponent real part [1/s], wall [s]) and OUT_DIR/failure_map.png (one panel per family:
green converged and Hill-stable, orange converged but Hill-unstable, grey converged with the
stability not computed, red failed; the wall time in each cell).
--redraw draws the figure again from OUT_DIR/failure_map.json without running anything.
Exit status: 0 on success (failed cells are results, not errors), 2 on bad arguments or a run
that did not produce its JSON.
"""

import argparse
import concurrent.futures
import json
import os
import random
import subprocess
import sys
import time

sys.dont_write_bytecode = True
import fricrom_plot_common as common  # noqa: E402  (checks numpy, matplotlib first)
from fricrom_plot_common import np, plt  # noqa: E402


def families(names):
    n = len(names)
    interfaces = [name.split(".")[0] for name in names]
    named = all("." in name for name in names)
    plus = []
    for k, name in enumerate(names):
        if named:
            side = interfaces[k]
            sign = -1.0 if side.startswith("d1") else 1.0
            plus.append(sign if name.endswith("t1") else 0.0)
        else:
            plus.append(1.0 if k % 2 == 0 else -1.0)
    rng = random.Random(7)
    return {
        "zero": [0.0] * n,
        "corner+": plus,
        "corner-": [-v for v in plus],
        "random": [rng.uniform(-1.0, 1.0) for _ in range(n)],
    }


def run_cell(args, fam, alpha, value, freq):
    cmd = [args.fricrom, "frf", args.case, "--freq", repr(freq), "--alpha",
           ",".join(repr(a) for a in alpha), "--stability", "--json", "--out",
           os.path.join(args.out, "runs", f"{fam}_{value}_{freq}")]
    if args.param:
        cmd += ["--set", f"{args.param}={value}"]
    if args.harmonics:
        cmd += ["--harmonics", str(args.harmonics)]
    t0 = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    try:
        point = json.loads(r.stdout)["points"][0]
    except (ValueError, KeyError, IndexError):
        raise RuntimeError(f"no JSON from {' '.join(cmd[:4])}...: {r.stderr.strip()[-300:]}")
    st = point.get("stability") or {}
    return {"family": fam, "value": value, "freq_hz": freq, "status": point["status"],
            "amplitude_m": point["amplitude"], "stable": st.get("stable"),
            "max_floquet_real_per_s": st.get("max_floquet_real_per_s"),
            "approximate": st.get("approximate"), "hill_note": st.get("note"), "wall_s": wall}


def draw(cells, fams, values, freqs, param, title, out):
    # Cells wide enough for their number; sub-second solves in milliseconds (shorter labels).
    width = max(3.4, 0.42 * len(freqs) + 0.8)
    fig, axes = plt.subplots(1, len(fams), figsize=(width * len(fams), 1.2 + 0.55 * len(values)),
                             squeeze=False, sharey=True)
    in_ms = max(c["wall_s"] for c in cells) < 1.0
    scale, unit = (1e3, "milliseconds") if in_ms else (1.0, "seconds")
    colour = {"stable": "#4caf50", "unstable": "#ff9800", "unknown": "#b0b0b0", "failed": "#e53935"}
    for ax, fam in zip(axes[0], fams):
        for i, v in enumerate(values):
            for j, f in enumerate(freqs):
                c = next(c for c in cells if c["family"] == fam and c["value"] == v
                         and c["freq_hz"] == f)
                kind = ("failed" if c["status"] != "converged" else
                        "unknown" if c["stable"] is None else
                        "stable" if c["stable"] else "unstable")
                ax.add_patch(plt.Rectangle((j, i), 1, 1, color=colour[kind], ec="white"))
                ax.text(j + 0.5, i + 0.5, f"{scale * c['wall_s']:.2g}", ha="center",
                        va="center", fontsize=7)
        ax.set_xlim(0, len(freqs))
        ax.set_ylim(0, len(values))
        ax.set_xticks(np.arange(len(freqs)) + 0.5)
        ax.set_xticklabels([f"{f:g}" for f in freqs], rotation=90, fontsize=7)
        ax.set_yticks(np.arange(len(values)) + 0.5)
        ax.set_yticklabels([f"{v:g}" for v in values], fontsize=8)
        ax.set_title(f"alpha: {fam}", fontsize=9)
        ax.set_xlabel("frequency [Hz]", fontsize=8)
    axes[0][0].set_ylabel(param or "-", fontsize=8)
    handles = [plt.Rectangle((0, 0), 1, 1, color=colour[k]) for k in colour]
    fig.legend(handles, ["converged, Hill-stable",
                         "converged, Hill-unstable (approximate at stick-slip)",
                         "converged, stability n/a", "failed"],
               loc="lower center", ncol=4, fontsize=8)
    fig.suptitle(title + f" (number: wall {unit} per solve)", fontsize=10)
    fig.tight_layout(rect=(0, 0.1, 1, 0.93))
    common.save_figure(fig, out)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("case")
    p.add_argument("out")
    p.add_argument("--freqs", required=True, help="comma list [Hz]")
    p.add_argument("--param", default="", help="case parameter varied (e.g. gamma)")
    p.add_argument("--values", default="0", help="its values, comma list")
    p.add_argument("--fricrom", default="build/fricrom")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--harmonics", type=int, default=0)
    p.add_argument("--redraw", action="store_true",
                   help="draw OUT/failure_map.png again from OUT/failure_map.json, no runs")
    args = p.parse_args(argv)
    if args.redraw:
        with open(os.path.join(args.out, "failure_map.json")) as fh:
            d = json.load(fh)
        draw(d["cells"], list(d["families"]), d["values"], d["freqs_hz"], d["param"],
             f"{os.path.basename(os.path.dirname(args.case))}/{os.path.basename(args.case)}",
             os.path.join(args.out, "failure_map.png"))
        return 0
    try:
        freqs = [float(v) for v in args.freqs.split(",")]
        values = [float(v) for v in args.values.split(",")]
    except ValueError:
        sys.stderr.write("failure_map.py: error: --freqs and --values are comma lists of numbers\n")
        return 2
    os.makedirs(os.path.join(args.out, "runs"), exist_ok=True)
    probe = subprocess.run([args.fricrom, "frf", args.case, "--freq", repr(freqs[0]), "--json",
                            "--out", os.path.join(args.out, "runs", "probe")],
                           capture_output=True, text=True)
    try:
        names = json.loads(probe.stdout)["contacts"]
    except (ValueError, KeyError):
        sys.stderr.write(f"failure_map.py: error: cannot run {args.fricrom} on {args.case}: "
                         f"{probe.stderr.strip()[-300:]}\n")
        return 2
    fams = families(names)
    jobs = [(f, a, v, fr) for f, a in fams.items() for v in values for fr in freqs]
    t0 = time.monotonic()
    cells = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = [pool.submit(run_cell, args, *j) for j in jobs]
        for k, fut in enumerate(concurrent.futures.as_completed(futures)):
            try:
                cells.append(fut.result())
            except RuntimeError as e:
                sys.stderr.write(f"failure_map.py: error: {e}\n")
                return 2
            if sys.stderr.isatty():
                sys.stderr.write(f"\rfailure_map: {k + 1}/{len(jobs)} cells")
    sys.stderr.write("\n")
    total = time.monotonic() - t0
    summary = {"case": args.case, "param": args.param, "values": values, "freqs_hz": freqs,
               "families": fams, "harmonics": args.harmonics or "case", "jobs": args.jobs,
               "wall_s_total": total, "units": {"amplitude": "m", "wall": "s",
                                                "floquet": "1/s"}, "cells": cells}
    with open(os.path.join(args.out, "failure_map.json.tmp"), "w") as fh:
        json.dump(summary, fh, indent=1)
    os.replace(os.path.join(args.out, "failure_map.json.tmp"),
               os.path.join(args.out, "failure_map.json"))
    title = f"{os.path.basename(os.path.dirname(args.case))}/{os.path.basename(args.case)}"
    draw(cells, list(fams), values, freqs, args.param, title,
         os.path.join(args.out, "failure_map.png"))
    kinds = {}
    for c in cells:
        k = ("failed" if c["status"] != "converged" else "n/a" if c["stable"] is None else
             "stable" if c["stable"] else "unstable")
        kinds[k] = kinds.get(k, 0) + 1
    print(f"failure_map.py: {len(cells)} cells in {total:.1f} s ({args.jobs} jobs): {kinds}; "
          f"wrote {args.out}/failure_map.json, failure_map.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
