#!/usr/bin/python3
"""Reduced FE cascade versus its lumped calibration (`fricrom lump`): the two bound curves with
their full-stick linear references, on one log axis.

Usage:
    /usr/bin/python3 scripts/plot_lumped_vs_fe.py FE_BOUNDS.h5 LUMPED_BOUNDS.h5 OUT.png

Both files are `fricrom bounds` curve outputs (/bounds/freq_hz, y_min_m, y_max_m and
/linear/freq_hz, stick_amplitude_m). The response of the lumped case is the FE response point's
(the lumped DOFs are scaled by the tip/platform ratio), so the two are drawn in metres as they
are. Exit status 0 on success, 2 on a missing or inconsistent file.
"""

import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import fricrom_plot_common as common  # noqa: E402  (checks numpy, matplotlib, h5py first)
from fricrom_plot_common import np, plt  # noqa: E402

SCRIPT = "plot_lumped_vs_fe.py"
STYLE = {"FE (reduced)": ("#1f4e9c", "#9ecae1"), "lumped": ("#b2182b", "#f4a582")}


def read(path):
    with common.open_h5(path) as h5:
        f, lo, hi = common.bound_curve(h5)
        lf = common.dataset(h5, "linear/freq_hz")
        ls = common.dataset(h5, "linear/stick_amplitude_m")
        common.same_length(h5, "linear", ["freq_hz", "stick_amplitude_m"], [lf, ls])
        name = common.attr_str(h5, "case_name", path)
    return name, f, lo, hi, lf, ls


def work():
    if len(sys.argv) != 4:
        raise common.InputError("usage: plot_lumped_vs_fe.py FE_BOUNDS.h5 LUMPED_BOUNDS.h5 OUT.png")
    out = sys.argv[3]
    common.check_output(out)
    fig, ax = plt.subplots(figsize=(7.5, 5.4))
    for label, path in (("FE (reduced)", sys.argv[1]), ("lumped", sys.argv[2])):
        name, f, lo, hi, lf, ls = read(path)
        line, band = STYLE[label]
        ok = np.isfinite(lo) & np.isfinite(hi)
        ax.fill_between(f[ok], lo[ok], hi[ok], color=band, alpha=0.6, lw=0)
        ax.plot(f[ok], hi[ok], color=line, lw=1.6, label=f"{label}: y_max ({name})")
        ax.plot(f[ok], lo[ok], color=line, lw=1.0, ls="--", label=f"{label}: y_min")
        ax.plot(lf, ls, color=line, lw=0.8, ls=":", label=f"{label}: full-stick linear")
    ax.set_yscale("log")
    ax.set_xlabel("excitation frequency [Hz]")
    ax.set_ylabel("response amplitude [m]")
    ax.set_title("Bounds of the blade-2 response: reduced FE cascade vs lumped calibration")
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    # Below the axes: the FE minima reach down to 1e-11 across the band, no corner is free.
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    fig.tight_layout()
    common.save_figure(fig, out)
    return f"wrote {out}"


if __name__ == "__main__":
    sys.exit(common.run(SCRIPT, work))
