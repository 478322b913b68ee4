#!/usr/bin/python3
"""Plot the forced response (FRF) stored in a fricrom results file.

Usage:
    /usr/bin/python3 scripts/plot_frf.py RESULTS.h5 OUT.png [--normalise]
    /usr/bin/python3 scripts/plot_frf.py RESULTS.h5 OUT.svg [--normalise]

Reads the HDF5 layout written by `fricrom frf`:
  root attributes   fricrom_version, case_name, units, (optional) response_dof
  /frf*/freq_hz     float64 [P]   frequency of each point [Hz]
  /frf*/amplitude_m float64 [P]   first-harmonic amplitude of the response DOF [m]
  /frf*/status      strings [P]   "converged" or a failure status
  /frf*/stable      int [P]       (optional, frf --stability) 1 stable, 0 unstable (dashed), -1 n/a
  /frf*/jump_before int [P]       (optional) 1 where a trace jumped over a stall (line broken)
  /linear/freq_hz, /linear/free_amplitude_m, /linear/stick_amplitude_m   float64 [F]
Every root group whose name starts with "frf" is drawn as its own curve (label = the group's
`label` attribute, else the group name). Non-converged points are marked with red crosses.

Exit status: 0 on success, 2 on a missing dependency, a missing/unreadable file or dataset, or
inconsistent data. Only the Debian packages python3-matplotlib, python3-numpy and python3-h5py
are needed.
"""

import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import fricrom_plot_common as common  # noqa: E402  (checks numpy, matplotlib, h5py first)
from fricrom_plot_common import np, plt, h5py  # noqa: E402,F401

import argparse
import os

from fricrom_plot_common import InputError, SUPPORTED_EXTENSIONS  # noqa: E402,F401

_to_str = common.to_str
_attr = common.attr_str
_dataset = common.dataset
_strings = common.strings
_same_length = common.same_length


def _frf_sort_key(name):
    return (name != "frf", name)


def read_results(path):
    if not os.path.isfile(path):
        raise InputError(f"results file '{path}' does not exist")
    try:
        h5 = h5py.File(path, "r")
    except OSError as e:
        raise InputError(f"cannot open '{path}' as HDF5: {e}") from e
    with h5:
        res = {
            "case_name": _attr(h5, "case_name", os.path.splitext(os.path.basename(path))[0]),
            "version": _attr(h5, "fricrom_version", "?"),
            "units": _attr(h5, "units", ""),
            "response_dof": _attr(h5, "response_dof"),
            "frf": [],
        }
        names = sorted(
            (k for k in h5.keys() if k.startswith("frf") and isinstance(h5[k], h5py.Group)),
            key=_frf_sort_key,
        )
        if not names:
            raise InputError(f"{path}: no FRF group (a root group named 'frf*') found")
        for g in names:
            f = _dataset(h5, f"{g}/freq_hz")
            a = _dataset(h5, f"{g}/amplitude_m")
            s = _strings(h5, f"{g}/status")
            _same_length(h5, g, ["freq_hz", "amplitude_m", "status"], [f, a, s])
            label = _attr(h5[g], "label", g)
            # Optional: Hill stability per point (1, 0, -1 not computed) and the trace's jumps.
            stable = np.asarray(h5[f"{g}/stable"][()]) if f"{g}/stable" in h5 else None
            jump = np.asarray(h5[f"{g}/jump_before"][()]) if f"{g}/jump_before" in h5 else None
            for name, v in (("stable", stable), ("jump_before", jump)):
                if v is not None and len(v) != len(f):
                    raise InputError(f"{path}: {g}/{name} has {len(v)} entries, expected {len(f)}")
            res["frf"].append({"name": g, "label": label, "freq": f, "amp": a, "status": s,
                               "stable": stable, "jump": jump})
        lf = _dataset(h5, "linear/freq_hz")
        free = _dataset(h5, "linear/free_amplitude_m")
        stick = _dataset(h5, "linear/stick_amplitude_m")
        _same_length(h5, "linear", ["freq_hz", "free_amplitude_m", "stick_amplitude_m"],
                     [lf, free, stick])
        res["linear"] = {"freq": lf, "free": free, "stick": stick}
    return res


def make_figure(res, normalise):
    lin = res["linear"]
    scale = common.full_stick_scale(lin, normalise)

    fig, ax = plt.subplots(figsize=(8.0, 5.0))
    colours = plt.rcParams["axes.prop_cycle"].by_key().get("color", ["C0"])
    reliable = []  # values that set the y range

    order = np.argsort(lin["freq"], kind="stable")
    lf = lin["freq"][order]
    free = lin["free"][order] / scale
    stick = lin["stick"][order] / scale
    ax.plot(lf, free, linestyle="--", color="0.55", linewidth=1.4, label="free (blades only)")
    ax.plot(lf, stick, linestyle=":", color="black", linewidth=1.8, label="full stick")
    reliable += [free, stick]

    bad_f, bad_a = [], []
    for i, curve in enumerate(res["frf"]):
        # Points are kept in file order: continuation traces may turn back in frequency.
        amp = curve["amp"] / scale
        ok = np.array([s == "converged" for s in curve["status"]], dtype=bool)
        shown = np.where(ok & np.isfinite(amp), amp, np.nan)
        n_ok = int(np.count_nonzero(ok))
        label = curve["label"]
        if n_ok < len(ok):
            label += f" ({len(ok) - n_ok} of {len(ok)} not converged)"
        freq = np.asarray(curve["freq"], dtype=float)
        if curve["jump"] is not None:
            # A jump over a stall: the branch between is not traced, so no line is drawn there.
            cut = np.flatnonzero(curve["jump"] == 1)
            freq = np.insert(freq, cut, np.nan)
            shown = np.insert(shown, cut, np.nan)
        colour = colours[i % len(colours)]
        unstable = None
        if curve["stable"] is not None:
            flags = np.asarray(curve["stable"])
            if curve["jump"] is not None:
                flags = np.insert(flags, np.flatnonzero(curve["jump"] == 1), -1)
            unstable = flags == 0
        if unstable is not None and unstable.any():
            # Unstable stretches dashed (with their neighbours, so the line stays joined).
            near = unstable | np.roll(unstable, 1) | np.roll(unstable, -1)
            ax.plot(freq, np.where(~unstable, shown, np.nan), linestyle="-", linewidth=1.8,
                    color=colour, label=label)
            ax.plot(freq, np.where(near, shown, np.nan), linestyle="--", linewidth=1.8,
                    color=colour, label="unstable (Hill)")
        else:
            ax.plot(freq, shown, linestyle="-", linewidth=1.8,
                    marker="." if n_ok < 60 else None, markersize=4, color=colour, label=label)
        reliable.append(shown)
        keep = ~ok & np.isfinite(amp) & np.isfinite(curve["freq"])
        bad_f += list(curve["freq"][keep])
        bad_a += list(amp[keep])

    finite = np.concatenate([r[np.isfinite(r)] for r in reliable] + [np.zeros(1)])
    top = float(np.max(finite)) * 1.08 if np.max(finite) > 0.0 else 1.0
    if bad_f:
        bad_a = np.asarray(bad_a)
        clipped = bool(np.any(bad_a > top))
        ax.plot(bad_f, np.minimum(bad_a, top), linestyle="none", marker="x", color="red",
                markersize=7, markeredgewidth=1.6, clip_on=False,
                label="not converged" + (" (clipped to axis)" if clipped else ""))
    ax.set_ylim(0.0, top)

    ax.set_xlabel("Frequency [Hz]")
    if normalise:
        ax.set_ylabel("Normalised amplitude (/ max full-stick) [-]")
    else:
        dof = res["response_dof"] or "response DOF"
        ax.set_ylabel(f"Amplitude of {dof} [m]")
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3), useMathText=True)
    ax.set_title(f"Forced response: {res['case_name']}")
    ax.grid(True, color="0.9", linewidth=0.8)
    ax.legend(loc="best", fontsize=9, framealpha=0.9)
    fig.text(0.995, 0.005, f"fricrom {res['version']}", ha="right", va="bottom",
             fontsize=7, color="0.5")
    fig.tight_layout()
    return fig


def save_atomically(fig, out):
    common.save_figure(fig, out)


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Plot the FRF curves of a fricrom results file (HDF5) to PNG or SVG.")
    parser.add_argument("results", metavar="RESULTS.h5", help="fricrom results file")
    parser.add_argument("out", metavar="OUT.png", help="output image (.png or .svg)")
    parser.add_argument("--normalise", "--normalize", action="store_true",
                        help="divide every curve by the maximum of the full-stick curve")
    args = parser.parse_args(argv)
    try:
        if os.path.splitext(args.out)[1].lower() not in SUPPORTED_EXTENSIONS:
            raise InputError(f"output '{args.out}' must end in .png or .svg")
        res = read_results(args.results)
        fig = make_figure(res, args.normalise)
        save_atomically(fig, args.out)
        plt.close(fig)
    except InputError as e:
        sys.stderr.write(f"plot_frf.py: error: {e}\n")
        return 2
    except OSError as e:
        sys.stderr.write(f"plot_frf.py: error: {e}\n")
        return 2
    print(f"plot_frf.py: wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
