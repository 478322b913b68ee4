#!/usr/bin/python3
"""Fidelity and cost of the FE cascade bounds, one knob at a time (issue 11 §4).

Usage:
    /usr/bin/python3 scripts/fidelity_study.py [--case meshes/cascade3/coarse.toml]
        [--freq 1000] [--fricrom build/fricrom] [--out docs/figures/cascade_fidelity] [--replot]

Runs `fricrom bounds CASE --freq F --json` for each setting of each knob — Craig-Bampton modes
per blade (--set blade_modes=N), AFT samples per period (--samples N), α per node pair or per
interface (a copy of the case with `alpha = "interface"` on every interface), harmonics H
(--harmonics N, the whole search at H or on the harmonic ladder, --search-harmonics 1) — on one
thread, and writes
OUT.json (every run: knob, value, wall time [s], y_min, y_max [m], R, status) and OUT.png (R and
y_max against wall time per knob, the finest setting of each knob as its reference). The
reduction a new mode count needs is done first by `fricrom modes` and not counted in the bound's
wall time. Exit status 0, or 2 on a failed run (its stderr is printed).
"""

import json
import os
import subprocess
import sys
import tempfile
import time

sys.dont_write_bytecode = True
import fricrom_plot_common as common  # noqa: E402
from fricrom_plot_common import np, plt  # noqa: E402

KNOBS = [
    ("CB modes per blade", "blade_modes", [4, 6, 10, 20, 40]),
    ("AFT samples per period", "samples", [16, 32, 64, 128, 256]),
    ("alpha grouping", "alpha", ["interface", "pair"]),
    # "3L": H = 3 on the harmonic ladder (search at H = 1, optima refined at H); "3": the whole
    # search at H. The reference, last, is the direct search at the highest H.
    ("harmonics H (L: ladder)", "harmonics", ["1", "3L", "5L", "7L", "3", "5", "7"]),
]


def arg(name, default):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


def bounds(fricrom, case, freq, extra):
    # one thread: the wall times compare settings, not the machine's cores
    # each run in its own output folder: two studies (two frequencies) may run side by side
    with tempfile.TemporaryDirectory(prefix="fricrom-fidelity-") as out:
        cmd = [fricrom, "bounds", case, "--freq", str(freq), "--json", "--quiet", "--threads", "1",
               "--out", out]
        cmd += extra
        t0 = time.monotonic()
        p = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.monotonic() - t0
    if p.returncode not in (0, 1):
        raise common.InputError(f"{' '.join(cmd)} exited {p.returncode}: {p.stderr.strip()}")
    d = json.loads(p.stdout)
    return {"wall_s": wall, "y_min": d.get("y_min"), "y_max": d.get("y_max"), "R": d.get("R"),
            "status": d.get("status")}


def interface_copy(case):
    """The case with one α per interface, written next to it (relative paths hold)."""
    with open(case) as f:
        text = f.read()
    text = text.replace('mu = "mu"\n', 'mu = "mu"\nalpha = "interface"\n')
    path = os.path.join(os.path.dirname(case), ".fidelity_alpha_interface.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def run_all(fricrom, case, freq):
    runs = []
    for label, knob, values in KNOBS:
        for v in values:
            extra, target = [], case
            if knob == "blade_modes":
                extra = ["--set", f"blade_modes={v}"]
                subprocess.run([fricrom, "modes", case] + extra, capture_output=True, check=True)
            elif knob == "samples":
                extra = ["--samples", str(v)]
            elif knob == "harmonics":
                ladder = v.endswith("L")
                extra = ["--harmonics", v.rstrip("L"), "--search-harmonics", "1" if ladder else "0"]
            elif v == "interface":
                target = interface_copy(case)
            try:
                r = bounds(fricrom, target, freq, extra)
            finally:
                if target != case:
                    os.remove(target)
            r.update({"knob": knob, "label": label, "value": v})
            print(f"{label} = {v}: R {r['R']}, y_max {r['y_max']}, {r['wall_s']:.1f} s", flush=True)
            runs.append(r)
    return runs


def plot(runs, out_png, freq):
    fig, axes = plt.subplots(1, len(KNOBS), figsize=(15, 3.8))
    for ax, (label, knob, values) in zip(axes, KNOBS):
        pts = [r for r in runs if r["knob"] == knob and r["R"] is not None]
        ref = pts[-1]
        w = [r["wall_s"] for r in pts]
        style = "o" if knob == "harmonics" else "o-"  # two routes: points, not one line
        ax.plot(w, [100 * (r["R"] / ref["R"] - 1) for r in pts], style, color="#1f4e9c",
                label="R")
        ax.plot(w, [100 * (r["y_max"] / ref["y_max"] - 1) for r in pts],
                "s" if knob == "harmonics" else "s--", color="#b2182b", ms=4, label="y_max")
        if knob == "harmonics":
            ax.set_xscale("log")
        for r in pts:
            ax.annotate(str(r["value"]), (r["wall_s"], 100 * (r["R"] / ref["R"] - 1)), fontsize=7,
                        textcoords="offset points", xytext=(3, 3))
        ax.ticklabel_format(axis="y", useOffset=False)
        ax.set_xlabel("wall time of the bound [s]")
        ax.set_ylabel(f"deviation from {ref['value']} [%]")
        ax.set_title(label, fontsize=9)
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"Coarse FE cascade, bounds at {freq:g} Hz: accuracy against cost, one knob at a "
                 "time", fontsize=10)
    fig.tight_layout()
    common.save_figure(fig, out_png)


def work():
    case = arg("--case", "meshes/cascade3/coarse.toml")
    freq = float(arg("--freq", "1000"))
    fricrom = arg("--fricrom", "build/fricrom")
    out = arg("--out", "docs/figures/cascade_fidelity")
    if "--replot" in sys.argv:  # the figure again from OUT.json, without running
        with open(out + ".json") as f:
            runs = json.load(f)["runs"]
    else:
        runs = run_all(fricrom, case, freq)
        with open(out + ".json", "w") as f:
            json.dump({"case": case, "freq_hz": freq, "units": "SI", "runs": runs}, f, indent=1)
    plot(runs, out + ".png", freq)
    return f"wrote {out}.json and {out}.png"


if __name__ == "__main__":
    sys.exit(common.run("fidelity_study.py", work))
