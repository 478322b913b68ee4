"""Helpers shared by the fricrom plotting scripts (plot_bounds.py, plot_contacts.py,
plot_sweep.py). Same conventions as scripts/plot_frf.py:
  * HDF5 strings may be bytes or str; attributes and datasets are checked and every problem with an
    input file raises InputError, which the scripts turn into a one-line message and exit status 2;
  * figures are written atomically (temporary file in the output directory + os.replace), dpi 150.

Importing this module checks numpy, matplotlib (Agg) and h5py and exits with status 2 naming the
missing Debian package, so the scripts import it before anything else.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from atomic_write import replace_atomically, write_text_atomically  # noqa: E402,F401

# Debian's packages, for /usr/bin/python3; a missing one stops the calling script with exit 2.
_MISSING = []
try:
    import numpy as np
except ImportError:
    _MISSING.append(("numpy", "python3-numpy"))
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: F401
except ImportError:
    _MISSING.append(("matplotlib", "python3-matplotlib"))
try:
    import h5py
except ImportError:
    _MISSING.append(("h5py", "python3-h5py"))
if _MISSING:
    for _module, _package in _MISSING:
        sys.stderr.write(
            f"{os.path.basename(sys.argv[0])}: error: Python module '{_module}' is not available; "
            f"install the Debian package {_package} (apt-get install {_package}) "
            f"and run with /usr/bin/python3\n"
        )
    sys.exit(2)

SUPPORTED_EXTENSIONS = (".png", ".svg")
DPI = 150

# Greek names of the design parameters of the paper (Eq. 11: gamma, Eq. 12: beta).
_GREEK = {"gamma": "\u03b3", "beta": "\u03b2", "alpha": "\u03b1", "theta": "\u03b8", "mu": "\u03bc"}


class InputError(Exception):
    """A problem with an input file or an argument (exit status 2)."""


def param_symbol(name):
    """'gamma' -> 'γ'; other names are returned unchanged."""
    return _GREEK.get(str(name).strip().lower(), str(name))


def to_str(value):
    """Decodes an HDF5 string (bytes, numpy bytes/str, 0-d/1-element array) to str."""
    if isinstance(value, np.ndarray):
        if value.size != 1:
            raise InputError(f"expected a scalar string, got an array of shape {value.shape}")
        value = value.reshape(()).item()
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).decode("utf-8", errors="replace")
    return str(value)


def attr_str(obj, name, default=None):
    if name not in obj.attrs:
        return default
    return to_str(obj.attrs[name])


def attr_float(obj, name, default=None):
    """A numeric attribute as float (NaN allowed); `default` if absent or not numeric."""
    if name not in obj.attrs:
        return default
    raw = obj.attrs[name]
    try:
        arr = np.asarray(raw, dtype=np.float64)
    except (TypeError, ValueError):
        try:
            return float(to_str(raw))
        except (InputError, ValueError):
            return default
    if arr.size != 1:
        return default
    return float(arr.reshape(()))


def open_h5(path):
    """Opens an HDF5 file read-only; InputError if missing or not HDF5."""
    if not os.path.isfile(path):
        raise InputError(f"results file '{path}' does not exist")
    try:
        return h5py.File(path, "r")
    except OSError as e:
        raise InputError(f"cannot open '{path}' as HDF5: {e}") from e


def require_group(h5, path):
    if path not in h5:
        raise InputError(f"{h5.filename}: group '/{path}' is missing")
    obj = h5[path]
    if not isinstance(obj, h5py.Group):
        raise InputError(f"{h5.filename}: '/{path}' is not a group")
    return obj


def dataset(h5, path, ndim=1):
    """The dataset at `path` as a float64 array with `ndim` dimensions; InputError otherwise."""
    if path not in h5:
        raise InputError(f"{h5.filename}: dataset '/{path}' is missing")
    obj = h5[path]
    if not isinstance(obj, h5py.Dataset):
        raise InputError(f"{h5.filename}: '/{path}' is not a dataset")
    try:
        data = np.asarray(obj[()], dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InputError(f"{h5.filename}: dataset '/{path}' is not numeric ({e})") from e
    if ndim == 1 and data.ndim == 0:
        data = data.reshape(1)
    if data.ndim != ndim:
        raise InputError(
            f"{h5.filename}: dataset '/{path}' must have {ndim} dimension(s), has shape {data.shape}")
    return data


def strings(h5, path):
    """The dataset at `path` as a list of str (a scalar string gives a one-element list)."""
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
    return [to_str(s).strip() for s in raw]


def same_length(h5, group, names, arrays):
    n = len(arrays[0])
    for name, a in zip(names[1:], arrays[1:]):
        if len(a) != n:
            raise InputError(
                f"{h5.filename}: '/{group}/{name}' has {len(a)} entries, "
                f"'/{group}/{names[0]}' has {n}")


def bound_curve(h5):
    """/bounds/{freq_hz, y_min_m, y_max_m} of an open bounds.h5, checked for equal lengths."""
    f = dataset(h5, "bounds/freq_hz")
    lo = dataset(h5, "bounds/y_min_m")
    hi = dataset(h5, "bounds/y_max_m")
    same_length(h5, "bounds", ["freq_hz", "y_min_m", "y_max_m"], [f, lo, hi])
    return f, lo, hi


def full_stick_scale(lin, normalise):
    """Divisor of the response curves: the full-stick peak with --normalise, else 1."""
    if not normalise:
        return 1.0
    stick = lin["stick"][np.isfinite(lin["stick"])]
    if stick.size == 0 or not np.max(stick) > 0.0:
        raise InputError("--normalise: the full-stick curve has no positive finite maximum")
    return float(np.max(stick))


def check_output(out):
    if os.path.splitext(out)[1].lower() not in SUPPORTED_EXTENSIONS:
        raise InputError(f"output '{out}' must end in .png or .svg")


def footer(fig, version):
    fig.text(0.995, 0.005, f"fricrom {version}", ha="right", va="bottom", fontsize=7, color="0.5")


def save_figure(fig, out):
    """Saves `fig` to `out` (.png/.svg) at DPI through a temporary file in the same directory."""
    ext = os.path.splitext(out)[1].lower()
    replace_atomically(out, ext, lambda tmp: fig.savefig(tmp, dpi=DPI, format=ext[1:]))


def run(script, work):
    """Runs work() -> message; prints errors as '<script>: error: ...' and returns the exit status."""
    try:
        message = work()
    except InputError as e:
        sys.stderr.write(f"{script}: error: {e}\n")
        return 2
    except OSError as e:
        sys.stderr.write(f"{script}: error: {e}\n")
        return 2
    finally:
        plt.close("all")
    if message:
        print(f"{script}: {message}")
    return 0


def warn(script, text):
    sys.stderr.write(f"{script}: warning: {text}\n")
