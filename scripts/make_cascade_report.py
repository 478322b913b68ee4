#!/usr/bin/python3
"""The FE cascade part of the main job's results: the reduced FE cascade beside its lumped
calibration (modes, bound curve, R, R over gamma, the NOA, wall times), as markdown.

Usage:
    /usr/bin/python3 scripts/make_cascade_report.py --dir results/cascade3 --out results/cascade3/report.md

Reads from --dir: fe_modes.json, fe_bounds.json, lump.json, lumped_modes.json,
lumped_bounds.json (outputs of `fricrom modes|bounds|lump --json`; the bounds are curves or single
frequencies), fe_peak.json (`fricrom bounds --freq --json` at the resonance, optional),
fe_verify.json (`fricrom verify --json`, optional), fe_noa.json (`fricrom noa
--json`, optional), gamma_study/gamma_study.json
(scripts/gamma_study.py, optional) and timings.json ({step: seconds}). Exit status 0, or 2 on a
missing or malformed file.
"""

import json
import os
import sys


def load(d, name):
    path = os.path.join(d, name)
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        raise SystemExit(f"make_cascade_report.py: error: {path}: {e}")


def num(x, fmt="{:.4e}"):
    return "n/a" if x is None else fmt.format(x)


def curve_section(fb, lb):
    """The bound curves point by point, FE beside lumped (when both are curves)."""
    fp, lpts = fb.get("points"), lb.get("points")
    if not fp or not lpts or len(fp) != len(lpts):
        return []
    out = ["", "## Bound curve", "",
           "![bound curves, FE and lumped](figures/bounds_fe_vs_lumped.png)", "",
           "| f [Hz] | FE y_min [m] | FE y_max [m] | FE R | FE point wall [s] | lumped y_min [m] "
           "| lumped y_max [m] | lumped R |", "|---|---|---|---|---|---|---|---|"]
    for a, b in zip(fp, lpts):
        out.append(f"| {a['freq_hz']:g} | {num(a['y_min'])} | {num(a['y_max'])} | "
                   f"{num(a['R'], '{:.4f}')} | {a['point_wall_s']:.1f} | {num(b['y_min'])} | "
                   f"{num(b['y_max'])} | {num(b['R'], '{:.4f}')} |")
    return out


def verify_section(d):
    """The certification of the FE bounds by alpha sampling, when the main job ran it."""
    path = os.path.join(d, "fe_verify.json")
    if not os.path.exists(path):
        return []
    v = load(d, "fe_verify.json")
    s = v["sampling"]
    verdict = "certified" if v["certified"] else "NOT certified: " + "; ".join(v["not_certified_because"])
    runs = v.get("time_integration", [])
    out = ["", f"## Certification of the FE bounds at {v['freq_hz']:g} Hz", "",
           f"`fricrom verify` (bounds with a 200-sample check, then {s['samples']} random per-pair alpha "
           f"samples and {len(runs)} time integrations): bounds [{num(v['y_min'])}, {num(v['y_max'])}] m; "
           f"{s['converged']} of {s['samples']} samples solved ({s['failed']} failed), {s['inside']} inside, "
           f"{s['outside']} outside, sampled range [{num(s['sampled_min'])}, {num(s['sampled_max'])}] m; "
           f"**{verdict}** ({v['wall_s']:.1f} s)."]
    if runs:
        out += ["", "Time integrations of the reduced cascade (implicit modal scheme, from static states set "
                "by alpha: 0, the two alternating corners; amplitude = Hann-windowed first harmonic; free "
                "vibration = spread of the one-period amplitudes over the last window, relative to the "
                "amplitude: what the start left of the full-stick modes' free decay):", "",
                "![verify](figures/verify.png)", "",
                "| run | status | amplitude [m] | HBM refined from its state [m] | inside | periods | "
                "free vibration | modes | wall [s] |",
                "|---|---|---|---|---|---|---|---|---|"]
        for i, r in enumerate(runs):
            hbm = (r.get("hbm_from_state") or {}).get("amplitude")
            out.append(f"| {i + 1} | {r['status']} | {num(r['amplitude'])} | {num(hbm)} | {r['inside']} | "
                       f"{r['periods']} | "
                       f"{num(r.get('free_vibration'), '{:.3f}')} | {r.get('modes_integrated', '')} | "
                       f"{num(r.get('wall_s'), '{:.1f}')} |")
    return out


def peak_section(d):
    """The bound run at the cascade's resonance, level by level (fe_peak.json, optional)."""
    if not os.path.exists(os.path.join(d, "fe_peak.json")):
        return []
    p = load(d, "fe_peak.json")
    out = ["", f"## Bounds at the resonance ({p['freq_hz']:g} Hz), level by level", "",
           "The bound run searches coarse to fine over the alpha levels (`docs/theory.md` 7a); each "
           "finer level holds the coarser levels' optima, so its bounds contain theirs.", "",
           "| level | alpha parameters | y_min [m] | y_max [m] | R | wall [s] |",
           "|---|---|---|---|---|---|"]
    for lv in p.get("levels", []):
        out.append(f"| {lv['level']} | {lv['parameters']} | {num(lv['y_min'])} | {num(lv['y_max'])} | "
                   f"{num(lv['R'], '{:.4f}')} | {lv['wall_s']:.1f} |")
    out += ["", f"Status {p['status']}, {p['wall_s']:.1f} s (`--search quick`, one thread)."]
    return out


def design_section(d):
    """R over gamma (both models) and the FE NOA, when the main job ran them."""
    out = []
    gpath = os.path.join(d, "gamma_study", "gamma_study.json")
    if os.path.exists(gpath):
        g = load(os.path.join(d, "gamma_study"), "gamma_study.json")
        for f, fe in g["fe"].items():
            lu = g["lumped"][f]
            out += ["", f"## R over gamma at {f} Hz", "", "![R over gamma](figures/r_gamma.png)", "",
                    "| gamma | FE R | lumped R |", "|---|---|---|"]
            out += [f"| {x:.4g} | {num(a, '{:.4f}')} | {num(b, '{:.4f}')} |"
                    for x, a, b in zip(g["gamma"], fe["robustness"], lu["robustness"])]
            out += ["", f"Wall time: FE sweep {fe['wall_s']:.1f} s, lumped {lu['wall_s']:.2f} s."]
    npath = os.path.join(d, "fe_noa.json")
    if os.path.exists(npath):
        n = load(d, "fe_noa.json")
        out += ["", f"## NOA over gamma on the FE cascade at {n['reference_freq_hz']:g} Hz", "",
                f"Objective {n['objective']}: p_opt = {n['p_opt']:.4g}, R = {num(n['R_opt'], '{:.4f}')}, "
                f"{n['outer_iterations']} outer evaluations, {n['inner_solves']} inner bound solves, "
                f"{n['wall_s']:.1f} s on {n['units']['threads']} threads"
                + (f" ({n['message']})" if n.get("message") else "") + "."]
    return out


def main():
    args = dict(zip(sys.argv[1::2], sys.argv[2::2]))
    if "--dir" not in args or "--out" not in args:
        print(__doc__, file=sys.stderr)
        return 2
    d = args["--dir"]
    fm, fb, lp = load(d, "fe_modes.json"), load(d, "fe_bounds.json"), load(d, "lump.json")
    lm, lb, t = load(d, "lumped_modes.json"), load(d, "lumped_bounds.json"), load(d, "timings.json")
    rows = [
        ("DOFs (stick system)", len(fm.get("stick_hz", [])), len(lm.get("stick_hz", []))),
        ("contact pairs / alpha", f"{fb['contact_pairs']} / {fb['alpha_count']}",
         f"{lb['contact_pairs']} / {lb['alpha_count']}"),
        ("free modes, first family [Hz]", ", ".join(f"{f:.2f}" for f in fm["free_hz"][:3]),
         ", ".join(f"{f:.2f}" for f in lm["free_hz"][:3])),
        ("full-stick modes, first family [Hz]", ", ".join(f"{f:.2f}" for f in fm["stick_hz"][:3]),
         ", ".join(f"{f:.2f}" for f in lm["stick_hz"][:3])),
        (f"bounds at {fb['freq_hz']:g} Hz{' (peak of the curve)' if 'points' in fb else ''}: y_min [m]",
         num(fb["y_min"]), num(lb["y_min"])),
        ("y_max [m]", num(fb["y_max"]), num(lb["y_max"])),
        ("R", num(fb["R"], "{:.4f}"), num(lb["R"], "{:.4f}")),
        ("status", fb["status"], lb["status"]),
        ("wall time of the bounds [s]" if "points" not in fb else "wall time of the bound curve [s]", f"{t.get('fe_bounds', float('nan')):.1f}",
         f"{t.get('lumped_bounds', float('nan')):.2f}"),
    ]
    out = ["# FE cascade: reduced FE model and its lumped calibration", "",
           "Case `meshes/cascade3/coarse.toml` (3 coarse blade sectors, 2 wedge dampers, Craig-Bampton "
           "bodies, node-to-node friction) and the lumped case `fricrom lump` writes from it "
           "(route and the full comparison with bound curves: `docs/lumped-vs-fe.md`). "
           "Units SI. The response is blade 2's response node (the lumped DOFs are scaled to it: "
           f"s = {lp['response_scale']:.2f}).", "",
           "| | reduced FE | lumped |", "|---|---|---|"]
    out += [f"| {a} | {b} | {c} |" for a, b, c in rows]
    out += ["", "Lumped calibration: " + "; ".join(
        f"{b['name']} mode {b['mode']} at {b['mode_hz']:.2f} Hz, platform mass {b['modal_mass_kg']:.3g} kg"
        for b in lp["blades"]) + "; " + "; ".join(
        f"{c['name']} kn {c['kn_n_per_m']:.3g} N/m, mu {c['mu']:.2f}, theta {c['theta_rad']:.4f} rad"
        for c in lp["contacts"]) + ".", "",
        "![contact-state map at the bounds](figures/contact_map.png)", "",
        "Step wall times [s]: " + ", ".join(f"{k} {v:.1f}" for k, v in sorted(t.items())) + "."]
    out += curve_section(fb, lb)
    out += peak_section(d)
    out += verify_section(d)
    out += design_section(d)
    tmp = args["--out"] + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(out) + "\n")
    os.replace(tmp, args["--out"])
    print(f"make_cascade_report.py: wrote {args['--out']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
