#!/usr/bin/python3
"""R over the preload asymmetry gamma on the FE cascade and on its calibrated lumped model, side by
side (issue 11, step 3; docs/lumped-vs-fe.md).

FE side: `fricrom sweep CASE --param gamma --freq F` per reference frequency. Lumped side: for every
gamma, `fricrom lump CASE --set gamma=g` (the damper preloads P = m a_z (1 -/+ gamma) are numbers in
the lumped file) and `fricrom bounds LUMPED --freq F`. Finished steps are kept in OUT as JSON and
reused by a rerun of the same command with the same binary and input files (the FE sweeps take
minutes near the resonance). Writes OUT/gamma_study.json and
the figure (atomically). Units SI.

usage: scripts/gamma_study.py [--case meshes/cascade3/coarse.toml] [--freqs 1000,1080]
                              [--from 0 --to 0.4 --steps 5] [--out results/gamma_study]
                              [--figure FILE.png] [--fricrom build/fricrom] [--harmonics H]
"""

import argparse
import hashlib
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from atomic_write import replace_atomically, write_text_atomically  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def file_digest(path, h):
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)


def step_key(cmd, outputs):
    """What a kept step depends on: the command line, the fricrom binary and every file the
    command reads (`outputs`, the files it writes, excluded)."""
    h = hashlib.sha256("\0".join(cmd).encode())
    for i, arg in enumerate(cmd):
        if os.path.isfile(arg) and arg not in outputs:  # inputs, not outputs
            file_digest(arg, h)
    return h.hexdigest()


def run_json(cmd, path, outputs=()):
    """Runs cmd (which prints one JSON object) unless `path` holds the result of this very
    command, binary and input files already (a changed binary or case reruns the step)."""
    key = step_key(cmd, outputs)
    if os.path.exists(path) and all(os.path.exists(o) for o in outputs):
        with open(path, encoding="utf-8") as f:
            kept = json.load(f)
        if isinstance(kept, dict) and kept.get("step_key") == key and "result" in kept:
            return kept["result"]
    print("gamma_study: " + " ".join(cmd), file=sys.stderr, flush=True)
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"gamma_study: error: {' '.join(cmd)} failed:\n{run.stderr.strip()}")
    result = json.loads(run.stdout)
    write_text_atomically(path, json.dumps({"step_key": key, "result": result}) + "\n")
    return result


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--case", default=os.path.join(ROOT, "meshes", "cascade3", "coarse.toml"))
    p.add_argument("--freqs", default="1000,1080", help="reference frequencies [Hz], comma-separated")
    p.add_argument("--from", dest="lo", type=float, default=0.0)
    p.add_argument("--to", dest="hi", type=float, default=0.4)
    p.add_argument("--steps", type=int, default=5)
    p.add_argument("--out", default=os.path.join(ROOT, "results", "gamma_study"))
    p.add_argument("--figure", default=None, help="figure path (default OUT/gamma_study.png)")
    p.add_argument("--fricrom", default=os.path.join(ROOT, "build", "fricrom"))
    p.add_argument("--harmonics", type=int, default=None,
                   help="harmonics H of both models (default: each case's)")
    p.add_argument("--search", default="default", choices=["quick", "default", "thorough"],
                   help="the FE sweep's bound search preset (fricrom sweep --search)")
    a = p.parse_args()
    freqs = [float(f) for f in a.freqs.split(",")]
    if a.steps < 2 or not a.lo < a.hi or not all(f > 0 for f in freqs):
        p.error("want --steps >= 2, --from < --to and positive --freqs")
    os.makedirs(a.out, exist_ok=True)
    gammas = [a.lo + (a.hi - a.lo) * i / (a.steps - 1) for i in range(a.steps)]
    h_args = [] if a.harmonics is None else ["--harmonics", str(a.harmonics)]
    study = {"case": a.case, "units": "SI (m, Hz)", "gamma": gammas, "fe": {}, "lumped": {}}
    for f in freqs:
        fe = run_json([a.fricrom, "sweep", a.case, "--param", "gamma", "--from", repr(a.lo), "--to",
                       repr(a.hi), "--steps", str(a.steps), "--freq", repr(f), "--json", "--quiet",
                       *h_args, "--search", a.search, "--out", os.path.join(a.out, f"fe_sweep_{f:g}")],
                      os.path.join(a.out, f"fe_sweep_{f:g}.json"))
        study["fe"][f"{f:g}"] = {k: fe[k] for k in ("values", "robustness", "y_min", "y_max",
                                                     "status", "wall_s")}
        lumped = {"robustness": [], "y_min": [], "y_max": [], "status": [], "wall_s": 0.0}
        for g in gammas:
            lcase = os.path.join(a.out, f"lumped_gamma_{g:g}.toml")
            run_json([a.fricrom, "lump", a.case, "--set", f"gamma={g!r}", "--to", lcase, "--json"],
                     os.path.join(a.out, f"lump_gamma_{g:g}.json"), outputs=(lcase,))
            b = run_json([a.fricrom, "bounds", lcase, "--freq", repr(f), "--json", "--quiet",
                          *h_args, "--out", os.path.join(a.out, f"lumped_bounds_{g:g}_{f:g}")],
                         os.path.join(a.out, f"lumped_bounds_{g:g}_{f:g}.json"))
            for k, key in (("robustness", "R"), ("y_min", "y_min"), ("y_max", "y_max"),
                           ("status", "status")):
                lumped[k].append(b[key])
            lumped["wall_s"] += b["wall_s"]
        study["lumped"][f"{f:g}"] = lumped
    write_text_atomically(os.path.join(a.out, "gamma_study.json"), json.dumps(study, indent=1) + "\n")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    def nan_for_null(values):  # a failed bound is null in the JSON: a gap in the curve, not 0
        return [float("nan") if v is None else v for v in values]

    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for i, f in enumerate(freqs):
        key = f"{f:g}"
        fe, lu = study["fe"][key], study["lumped"][key]
        ax.plot(gammas, nan_for_null(fe["robustness"]), "o-", color=f"C{i}",
                label=f"FE cascade, {key} Hz")
        ax.plot(gammas, nan_for_null(lu["robustness"]), "s--", color=f"C{i}", mfc="none",
                label=f"calibrated lumped, {key} Hz")
    ax.set_xlabel("preload asymmetry γ (damper 1 × (1 − γ), damper 2 × (1 + γ))")
    ax.set_ylabel("robustness R")
    ax.set_ylim(-0.02, 1.05)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="center right")
    ax.set_title("R(γ): FE cascade (108 pairs, 216 α) vs its lumped calibration", fontsize=10)
    fig.tight_layout()
    out = a.figure or os.path.join(a.out, "gamma_study.png")
    replace_atomically(out, ".png", lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    print(json.dumps({"json": os.path.join(a.out, "gamma_study.json"), "figure": out}))


if __name__ == "__main__":
    main()
