"""Atomic file output for the fricrom scripts (standard library only): write to a temporary file
in the target's directory, then os.replace, so an interrupted run never leaves a half-written
file. Used by fricrom_plot_common.py (figures), make_report.py, reduction_accuracy.py and
benchmarks/reduce_vs_scipy.py."""

import os
import tempfile


def replace_atomically(out, suffix, write):
    """Calls write(tmp_path) for a temporary file beside `out`, then renames it to `out` with the
    permissions a new file would get (umask); the temporary file is removed on any error."""
    directory = os.path.dirname(os.path.abspath(out))
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(out) + ".", suffix=suffix, dir=directory)
    os.close(fd)
    try:
        write(tmp)
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


def write_text_atomically(path, text):
    """Writes `text` (UTF-8) to `path` atomically."""
    def write(tmp):
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
    replace_atomically(path, ".tmp", write)
