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
  /linear/freq_hz, /linear/free_amplitude_m, /linear/stick_amplitude_m   float64 [F]
Every root group whose name starts with "frf" is drawn as its own curve (label = the group's
`label` attribute, else the group name). Non-converged points are marked with red crosses.

Exit status: 0 on success, 2 on a missing dependency, a missing/unreadable file or dataset, or
inconsistent data. Only the Debian packages python3-matplotlib, python3-numpy and python3-h5py
are needed.
"""

import sys

_MISSING = []
try:
    import numpy as np
except ImportError:
    _MISSING.append(("numpy", "python3-numpy"))
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    _MISSING.append(("matplotlib", "python3-matplotlib"))
try:
    import h5py
except ImportError:
    _MISSING.append(("h5py", "python3-h5py"))
if _MISSING:
    for module, package in _MISSING:
        sys.stderr.write(
            f"plot_frf.py: error: Python module '{module}' is not available; "
            f"install the Debian package {package} (apt-get install {package}) "
            f"and run with /usr/bin/python3\n"
        )
    sys.exit(2)

import argparse
import os
import tempfile

SUPPORTED_EXTENSIONS = (".png", ".svg")


class InputError(Exception):
    """A problem with the input file or arguments (exit status 2)."""


def _to_str(value):
    """Decodes an HDF5 string (bytes, numpy bytes/str, 0-d/1-element array) to str."""
    if isinstance(value, np.ndarray):
        if value.size != 1:
            raise InputError(f"expected a scalar string, got an array of shape {value.shape}")
        value = value.reshape(()).item()
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).decode("utf-8", errors="replace")
    return str(value)


def _attr(obj, name, default=None):
    if name not in obj.attrs:
        return default
    return _to_str(obj.attrs[name])


def _dataset(h5, path):
    """Returns the object at `path` as a 1-D float64 array; InputError if missing/wrong."""
    if path not in h5:
        raise InputError(f"{h5.filename}: dataset '/{path}' is missing")
    obj = h5[path]
    if not isinstance(obj, h5py.Dataset):
        raise InputError(f"{h5.filename}: '/{path}' is not a dataset")
    try:
        data = np.asarray(obj[()], dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InputError(f"{h5.filename}: dataset '/{path}' is not numeric ({e})") from e
    if data.ndim != 1:
        raise InputError(f"{h5.filename}: dataset '/{path}' must be 1-D, has shape {data.shape}")
    return data


def _strings(h5, path):
    if path not in h5:
        raise InputError(f"{h5.filename}: dataset '/{path}' is missing")
    obj = h5[path]
    if not isinstance(obj, h5py.Dataset):
        raise InputError(f"{h5.filename}: '/{path}' is not a dataset")
    raw = obj[()]
    if np.ndim(raw) == 0:
        raw = [raw]
    elif np.ndim(raw) != 1:
        raise InputError(f"{h5.filename}: dataset '/{path}' must be 1-D, has shape {np.shape(raw)}")
    return [_to_str(s).strip() for s in raw]


def _same_length(h5, group, names, arrays):
    n = len(arrays[0])
    for name, a in zip(names[1:], arrays[1:]):
        if len(a) != n:
            raise InputError(
                f"{h5.filename}: '/{group}/{name}' has {len(a)} entries, "
                f"'/{group}/{names[0]}' has {n}"
            )


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
            res["frf"].append({"name": g, "label": label, "freq": f, "amp": a, "status": s})
        lf = _dataset(h5, "linear/freq_hz")
        free = _dataset(h5, "linear/free_amplitude_m")
        stick = _dataset(h5, "linear/stick_amplitude_m")
        _same_length(h5, "linear", ["freq_hz", "free_amplitude_m", "stick_amplitude_m"],
                     [lf, free, stick])
        res["linear"] = {"freq": lf, "free": free, "stick": stick}
    return res


def make_figure(res, normalise):
    lin = res["linear"]
    scale = 1.0
    if normalise:
        stick = lin["stick"][np.isfinite(lin["stick"])]
        if stick.size == 0 or not np.max(stick) > 0.0:
            raise InputError("--normalise: the full-stick curve has no positive finite maximum")
        scale = float(np.max(stick))

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
        ax.plot(curve["freq"], shown, linestyle="-", linewidth=1.8,
                marker="." if n_ok < 60 else None, markersize=4,
                color=colours[i % len(colours)], label=label)
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
    ext = os.path.splitext(out)[1].lower()
    directory = os.path.dirname(os.path.abspath(out))
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(out) + ".", suffix=ext, dir=directory)
    os.close(fd)
    try:
        fig.savefig(tmp, dpi=150, format=ext[1:])
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, out)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


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
