#!/usr/bin/python3
"""Design by geometry: the most robust wedge angle of the FE cascade's dampers (issue 11, step 6).

The outer loop of the nested optimisation runs over a gmsh parameter shared by the blade and the
damper models (default `cham_deg`: the damper's wedge angle together with the matching platform
chamfers). At each value the script
  1. regenerates both meshes and their CalculiX matrices (scripts/make_meshes.sh --set NAME=VALUE),
  2. writes the cascade case on those models (the template's `../blade_sector/coarse/` and
     `../damper/coarse/` paths pointed at them; fricrom reduces on first use, cached by content),
  3. runs `fricrom bounds CASE --freq F --json` (the inner optimisation over alpha),
and maximises R = 1 - (y_max - y_min) / y_max: a global scan (--scan values, ends included), then a
bounded Brent search (scipy) between the neighbours of the best scanned value. A value whose
geometry gmsh rejects, or whose bounds do not converge, is reported with its message and scored as
the worst design (R = -1), so the search moves away from it.

Every design lives in OUT/designs/NAME_VALUE/ with its meshes, case, bounds and a design.json; a
rerun with the same OUT reuses finished designs of the same frequency, harmonics and case file
(resumable after a kill). Results, all written
atomically: OUT/geometry_noa.json (best value, R, evaluations, remeshes, wall time),
OUT/geometry_noa.csv, OUT/geometry_noa.png. Units SI; angles in degrees as the .geo files take them.

usage: scripts/geometry_noa.py [--case meshes/cascade3/coarse.toml] [--param cham_deg]
                               --from 30 --to 75 --freq 1000 [--scan 7] [--xtol 0.5]
                               [--max-evals 16]
                               [--out results/geometry_noa] [--fricrom build/fricrom] [--quiet]
                               [--harmonics H]
"""

import argparse
import csv
import io
import hashlib
import json
import math
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from atomic_write import write_text_atomically  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORST_R = -1.0  # score of a rejected design (R itself lies in [0, 1])
TEMPLATE_DIRS = {"../blade_sector/coarse/": "meshes/blade_sector/",
                 "../damper/coarse/": "meshes/damper/"}


class Fail(Exception):
    pass


class Budget(Exception):
    """--max-evals reached."""


def log(args, msg):
    if not args.quiet:
        print(f"geometry_noa: {msg}", file=sys.stderr, flush=True)


def design_dir(args, value):
    return os.path.join(args.out, "designs", f"{args.param}_{value:.6f}")


def first_error(text):
    for line in text.splitlines():
        if line.startswith("Error") or "error:" in line:
            return line.split(":", 1)[-1].strip() if line.startswith("Error") else line.strip()
    return text.strip().splitlines()[-1] if text.strip() else "no message"


def write_case(args, template, folder):
    text = template
    for old, new in TEMPLATE_DIRS.items():
        if old not in text:
            raise Fail(f"{args.case}: expected model paths under '{old}' (the coarse cascade's layout)")
        text = text.replace(old, new)
    text = f"# Written by scripts/geometry_noa.py: {args.case} on the models regenerated with " \
           f"{args.param} = {design_value(folder)}\n" + text
    path = os.path.join(folder, "cascade3.toml")
    write_text_atomically(path, text)
    return path


def design_value(folder):
    return os.path.basename(folder).rsplit("_", 1)[-1]


def evaluate(args, template, value, state):
    """One outer evaluation: remesh, case, bounds. Returns the design record (also on disk)."""
    folder = design_dir(args, value)
    record_path = os.path.join(folder, "design.json")
    # What the design's result depends on besides its value: reused only if the same.
    inputs = {"freq_hz": args.freq, "harmonics": args.harmonics, "search": args.search,
              "alpha_levels": args.alpha_levels,
              "case_sha256": hashlib.sha256(template.encode("utf-8")).hexdigest()}
    if os.path.exists(record_path):
        with open(record_path, encoding="utf-8") as f:
            record = json.load(f)
        if record.get("inputs") == inputs:
            record["reused"] = True
            log(args, f"{args.param} = {value:.4f}: reused {record_path}")
            return record
        log(args, f"{args.param} = {value:.4f}: {record_path} is of other inputs, recomputed")
    os.makedirs(folder, exist_ok=True)
    record = {"value": value, "status": "rejected", "message": "", "R": None, "y_min": None,
              "y_max": None, "mesh_s": None, "bounds_s": None, "reused": False, "inputs": inputs}
    t0 = time.monotonic()
    if not (args.valid_from < value < args.valid_to):
        record["message"] = f"{args.param} = {value} outside ({args.valid_from}, {args.valid_to})"
    else:
        mesh = subprocess.run(["bash", os.path.join(ROOT, "scripts", "make_meshes.sh"), "coarse",
                               "--out", os.path.join(folder, "meshes"),
                               "--set", f"{args.param}={value:.10g}"],
                              capture_output=True, text=True)
        record["mesh_s"] = time.monotonic() - t0
        state["remeshes"] += 1
        if mesh.returncode != 0:
            record["message"] = "invalid geometry: " + first_error(mesh.stderr)
        else:
            case = write_case(args, template, folder)
            t1 = time.monotonic()
            cmd = [args.fricrom, "bounds", case, "--freq", f"{args.freq:.10g}", "--json",
                   "--out", os.path.join(folder, "bounds")]
            if args.harmonics is not None:
                cmd += ["--harmonics", str(args.harmonics)]
            cmd += ["--search", args.search, "--alpha-levels", args.alpha_levels]
            run = subprocess.run(cmd, capture_output=True, text=True)
            record["bounds_s"] = time.monotonic() - t1
            try:
                result = json.loads(run.stdout)
            except json.JSONDecodeError:
                result = None
            if run.returncode != 0 or result is None:
                record["message"] = "fricrom bounds failed: " + first_error(run.stderr)
            elif result.get("status") != "converged" or result.get("R") is None:
                record["message"] = f"bounds status {result.get('status')}"
            else:
                record.update(status="ok", R=result["R"], y_min=result["y_min"],
                              y_max=result["y_max"], contact_pairs=result.get("contact_pairs"))
    record["wall_s"] = time.monotonic() - t0
    write_text_atomically(record_path, json.dumps(record, indent=1) + "\n")
    if record["status"] == "ok":
        log(args, f"{args.param} = {value:.4f}: R = {record['R']:.4f} "
                  f"(y in [{record['y_min']:.4e}, {record['y_max']:.4e}] m), {record['wall_s']:.1f} s")
    else:
        log(args, f"{args.param} = {value:.4f}: rejected: {record['message']}")
    return record


def write_outputs(args, records, best, wall, state):
    summary = {
        "case": args.case, "param": args.param, "from": args.lo, "to": args.hi,
        "freq_hz": args.freq, "units": "SI; the angle parameter in degrees",
        "status": state["status"] if best is not None else "failed",
        "message": state["message"],
        "p_opt": best["value"] if best else None, "R_opt": best["R"] if best else None,
        "y_min_opt": best["y_min"] if best else None, "y_max_opt": best["y_max"] if best else None,
        "evaluations": len(records), "remeshes": state["remeshes"],
        "rejected": sum(r["status"] != "ok" for r in records),
        "wall_s": wall, "designs": records,
    }
    write_text_atomically(os.path.join(args.out, "geometry_noa.json"),
                          json.dumps(summary, indent=1) + "\n")
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([args.param, "status", "R", "y_min_m", "y_max_m", "mesh_s", "bounds_s", "message"])
    for r in sorted(records, key=lambda r: r["value"]):
        w.writerow([r["value"], r["status"], "" if r["R"] is None else r["R"],
                    "" if r["y_min"] is None else r["y_min"],
                    "" if r["y_max"] is None else r["y_max"], r["mesh_s"], r["bounds_s"],
                    r["message"]])
    write_text_atomically(os.path.join(args.out, "geometry_noa.csv"), buf.getvalue())
    return summary


def plot(args, records, best):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        log(args, "matplotlib not available: no figure")
        return
    from atomic_write import replace_atomically
    ok = sorted((r for r in records if r["status"] == "ok"), key=lambda r: r["value"])
    bad = [r for r in records if r["status"] != "ok"]
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.4, 6.0), sharex=True)
    ax1.plot([r["value"] for r in ok], [r["R"] for r in ok], "o-", label="evaluated designs")
    if best:
        ax1.plot([best["value"]], [best["R"]], "r*", ms=14, label=f"best: {best['value']:.2f}, R = {best['R']:.3f}")
    for r in bad:
        ax1.axvline(r["value"], color="0.6", ls=":", lw=1)
    ax1.set_ylabel("robustness R")
    ax1.legend(loc="best", fontsize=8)
    ax1.grid(alpha=0.3)
    ax2.plot([r["value"] for r in ok], [r["y_max"] for r in ok], "^-", label="y_max")
    ax2.plot([r["value"] for r in ok], [r["y_min"] for r in ok], "v-", label="y_min")
    ax2.set_yscale("log")
    ax2.set_ylabel("response bounds [m]")
    ax2.set_xlabel(f"{args.param} [deg]: damper wedge angle = platform chamfer angle")
    ax2.legend(loc="best", fontsize=8)
    ax2.grid(alpha=0.3)
    fig.suptitle(f"Geometry NOA on the coarse FE cascade at {args.freq:g} Hz "
                 f"({len(records)} designs, {len(bad)} rejected)", fontsize=10)
    fig.tight_layout()
    replace_atomically(os.path.join(args.out, "geometry_noa.png"), ".png",
                       lambda tmp: fig.savefig(tmp, dpi=120, format="png"))


def parse(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--case", default=os.path.join(ROOT, "meshes", "cascade3", "coarse.toml"),
                   help="cascade case whose models live in ../blade_sector/coarse and ../damper/coarse")
    p.add_argument("--param", default="cham_deg",
                   help="gmsh parameter of both .geo files (default cham_deg: wedge angle [deg])")
    p.add_argument("--from", dest="lo", type=float, required=True, help="lower end of the interval")
    p.add_argument("--to", dest="hi", type=float, required=True, help="upper end of the interval")
    p.add_argument("--freq", type=float, required=True, help="reference frequency [Hz]")
    p.add_argument("--scan", type=int, default=7, help="values of the global scan (ends included)")
    p.add_argument("--xtol", type=float, default=0.5, help="Brent's tolerance on the parameter")
    p.add_argument("--max-evals", type=int, default=16, help="most outer evaluations (remeshes)")
    p.add_argument("--out", default=os.path.join(ROOT, "results", "geometry_noa"))
    p.add_argument("--fricrom", default=os.path.join(ROOT, "build", "fricrom"))
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.add_argument("--harmonics", type=int, default=None, help="harmonics H (default: the case's)")
    p.add_argument("--search", default="default", choices=["quick", "default", "thorough"],
                   help="the bound search preset of every design (fricrom bounds --search)")
    p.add_argument("--alpha-levels", dest="alpha_levels", default="auto", choices=["auto", "pair"],
                   help="alpha levels of the bound search (fricrom bounds --alpha-levels)")
    args = p.parse_args(argv)
    if not (math.isfinite(args.lo) and math.isfinite(args.hi) and args.lo < args.hi):
        p.error(f"--from {args.lo} --to {args.hi}: want finite values with from < to")
    if not (math.isfinite(args.freq) and args.freq > 0):
        p.error(f"--freq {args.freq}: want a positive frequency in Hz")
    if not (args.xtol > 0) or args.max_evals < 1 or args.scan < 2:
        p.error("--xtol must be > 0, --max-evals >= 1 and --scan >= 2")
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", args.param):
        p.error(f"--param '{args.param}' is not a gmsh parameter name")
    # An angle parameter outside (0, 90) degrees is no wedge; other parameters: gmsh decides.
    args.valid_from, args.valid_to = (0.0, 90.0) if args.param == "cham_deg" else (-math.inf, math.inf)
    if not os.access(args.fricrom, os.X_OK):
        p.error(f"--fricrom {args.fricrom}: not an executable (build first)")
    args.out = os.path.abspath(args.out)
    return args


def main(argv):
    args = parse(argv)
    from scipy.optimize import minimize_scalar
    try:
        with open(args.case, encoding="utf-8") as f:
            template = f.read()
    except OSError as e:
        print(f"geometry_noa: error: cannot read {args.case}: {e.strerror}", file=sys.stderr)
        return 2
    t0 = time.monotonic()
    state = {"remeshes": 0, "status": "failed", "message": "no valid design"}
    records = []
    by_value = {}

    def score(value):
        key = round(value, 6)
        if key not in by_value:
            if len(records) >= args.max_evals:
                raise Budget()
            by_value[key] = evaluate(args, template, key, state)
            records.append(by_value[key])
        r = by_value[key]
        return -(r["R"] if r["status"] == "ok" else WORST_R)

    try:
        # R over the geometry is rugged (the alpha-dependent lift-off pattern changes in steps),
        # so a global scan first, then Brent in the bracket around the best scanned value.
        scan = [args.lo + (args.hi - args.lo) * i / (args.scan - 1) for i in range(args.scan)]
        values = [round(v, 6) for v in scan]
        scores = [score(v) for v in values]
        i = min(range(len(values)), key=lambda k: scores[k])
        lo, hi = values[max(i - 1, 0)], values[min(i + 1, len(values) - 1)]
        if scores[i] < -WORST_R:  # a valid design: refine around it
            res = minimize_scalar(score, bounds=(lo, hi), method="bounded",
                                  options={"xatol": args.xtol, "maxiter": args.max_evals})
            state["status"] = "converged" if res.success else "not_converged"
            state["message"] = f"Brent on [{lo}, {hi}]: {res.message}"
    except Budget:
        state["status"] = "max_evaluations"
        state["message"] = f"stopped after --max-evals {args.max_evals} evaluations"
        log(args, state["message"])
    except Fail as e:
        print(f"geometry_noa: error: {e}", file=sys.stderr)
        return 2
    ok = [r for r in records if r["status"] == "ok"]
    best = max(ok, key=lambda r: r["R"]) if ok else None
    summary = write_outputs(args, records, best, time.monotonic() - t0, state)
    plot(args, records, best)
    if best is None:
        print(f"geometry_noa: error: no valid design in [{args.lo}, {args.hi}] "
              f"({len(records)} tried; see {args.out}/geometry_noa.csv)", file=sys.stderr)
        return 1
    log(args, f"best {args.param} = {best['value']:.4f}, R = {best['R']:.4f}; "
              f"{summary['evaluations']} designs, {summary['remeshes']} remeshes, "
              f"{summary['rejected']} rejected, {summary['wall_s']:.1f} s")
    print(json.dumps({k: v for k, v in summary.items() if k != "designs"}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
