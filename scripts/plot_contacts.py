#!/usr/bin/python3
"""Plot the contact-force time histories at the minimum and maximum response of a fricrom bounds
file (paper Fig. 10b/c, 12, 13, 15, 16).

Usage:
    /usr/bin/python3 scripts/plot_contacts.py BOUNDS.h5 OUT.png [--only min|max]
    /usr/bin/python3 scripts/plot_contacts.py BOUNDS.h5 OUT.svg [--only min|max]

Reads the HDF5 layout written by `fricrom bounds`:
  root attributes        fricrom_version, case_name, units, response_dof, command
  /histories/contacts    strings [nc]   contact names
  /histories/mu          float64 [nc]   friction coefficients
  /histories/{min,max}/time_s         float64 [N]      one period
  /histories/{min,max}/tangential_N   float64 [nc x N] T(t)
  /histories/{min,max}/normal_N       float64 [nc x N] N(t)
  /histories/{min,max}/states         int/float [nc x N]  0 stick, 1 positive slip,
                                                          2 negative slip, 3 lift-off
  /histories/{min,max}/regimes        strings [nc]
  /histories/{min,max} attributes freq_hz, amplitude_m; optional dataset alpha [nc]
One row per response (minimum, maximum), one column per contact. Each panel: T(t) (solid),
+mu N(t) and -mu N(t) (dashed), N(t) (thin grey); the background is shaded where the contact
slips and (hatched) where it is lifted off. Time in ms over one period.
fricrom writes no history group for a bound that did not converge: without --only, a missing
group is reported on stderr and the other one is drawn; with --only, or if both are missing, the
script fails.

Exit status: 0 on success, 2 on a missing dependency, a missing/unreadable file or dataset, or
inconsistent data. Only the Debian packages python3-matplotlib, python3-numpy and python3-h5py
are needed.
"""

import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import fricrom_plot_common as common  # noqa: E402  (checks numpy, matplotlib, h5py first)
from fricrom_plot_common import np, plt, h5py  # noqa: E402,F401
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

import argparse
import os

from fricrom_plot_common import InputError

SCRIPT = "plot_contacts.py"
ROW_TITLES = {"min": "Minimum response", "max": "Maximum response"}
COLOUR_T = "#1f4e9c"
COLOUR_MUN = "#c0392b"
COLOUR_N = "0.45"
COLOUR_SLIP = "#fdd9a0"
COLOUR_LIFT = "#cfcfcf"
STICK, SLIP_POS, SLIP_NEG, LIFT = 0, 1, 2, 3


def _read_history(h5, name, nc):
    g = f"histories/{name}"
    grp = common.require_group(h5, g)
    t = common.dataset(h5, f"{g}/time_s")
    n = len(t)
    if n < 2:
        raise InputError(f"{h5.filename}: '/{g}/time_s' needs at least 2 samples, has {n}")
    if not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0.0):
        raise InputError(f"{h5.filename}: '/{g}/time_s' must be finite and increasing")
    mats = {}
    for key in ("tangential_N", "normal_N", "states"):
        m = common.dataset(h5, f"{g}/{key}", ndim=2)
        if m.shape != (nc, n):
            raise InputError(f"{h5.filename}: '/{g}/{key}' has shape {m.shape}, expected "
                             f"({nc}, {n}) = (contacts, time samples)")
        mats[key] = m
    regimes = common.strings(h5, f"{g}/regimes")
    if len(regimes) != nc:
        raise InputError(f"{h5.filename}: '/{g}/regimes' has {len(regimes)} entries, "
                         f"expected {nc} (one per contact)")
    states = mats["states"]
    bad = ~np.isin(np.where(np.isfinite(states), states, -1.0), [STICK, SLIP_POS, SLIP_NEG, LIFT])
    if np.any(bad):
        common.warn(SCRIPT, f"'/{g}/states' has {int(np.count_nonzero(bad))} values outside "
                            "{0, 1, 2, 3}; they are not shaded")
    alpha = None
    if f"{g}/alpha" in h5:
        a = common.dataset(h5, f"{g}/alpha")
        if len(a) == nc:
            alpha = a
    freq = common.attr_float(grp, "freq_hz")
    period = None
    if freq is not None and np.isfinite(freq) and freq > 0.0:
        period = 1.0 / freq
    else:
        freq = None
        period = t[-1] - t[0] + (t[-1] - t[-2])  # the grid leaves out the end of the period
    return {
        "time": t, "T": mats["tangential_N"], "N": mats["normal_N"],
        "states": np.where(bad, -1, np.where(np.isfinite(states), states, -1)).astype(int),
        "regimes": regimes, "freq": freq, "period": period,
        "amplitude": common.attr_float(grp, "amplitude_m"), "alpha": alpha,
    }


def read_histories(path, only):
    h5 = common.open_h5(path)
    with h5:
        common.require_group(h5, "histories")
        names = common.strings(h5, "histories/contacts")
        nc = len(names)
        if nc == 0:
            raise InputError(f"{path}: '/histories/contacts' is empty")
        mu = common.dataset(h5, "histories/mu")
        if len(mu) == 1 and nc > 1:
            mu = np.full(nc, mu[0])
        if len(mu) != nc:
            raise InputError(f"{path}: '/histories/mu' has {len(mu)} entries, "
                             f"'/histories/contacts' has {nc}")
        wanted = [only] if only else ["min", "max"]
        present = [w for w in wanted if f"histories/{w}" in h5]
        if not only and not present:
            raise InputError(f"{path}: neither '/histories/min' nor '/histories/max' is present "
                             "(no bound converged?)")
        if not only and len(present) < len(wanted):
            missing = [w for w in wanted if w not in present][0]
            common.warn(SCRIPT, f"{path}: group '/histories/{missing}' is missing (that bound did "
                                "not converge?); drawing the other response only")
        rows = {w: _read_history(h5, w, nc) for w in (present if not only else wanted)}
        return {
            "case_name": common.attr_str(h5, "case_name", os.path.splitext(os.path.basename(path))[0]),
            "version": common.attr_str(h5, "fricrom_version", "?"),
            "response_dof": common.attr_str(h5, "response_dof"),
            "contacts": names, "mu": mu, "rows": rows,
        }


def _closed(t, y, period):
    """Appends the first sample at t0 + period when the grid leaves out the end of the period."""
    dt = t[-1] - t[-2]
    if abs((t[-1] + dt) - (t[0] + period)) <= 1e-3 * period:
        return np.append(t, t[0] + period), np.append(y, y[0])
    return t, y


def _state_runs(t, states, period):
    """(state, start, end) of the runs of equal states; sample i covers the half-way points to its
    neighbours; the first/last cells are repeated one period later/earlier so that the shading
    wraps around the period."""
    edges = np.empty(len(t) + 1)
    edges[1:-1] = 0.5 * (t[1:] + t[:-1])
    edges[0] = t[0] - 0.5 * (t[1] - t[0])
    edges[-1] = t[-1] + 0.5 * (t[-1] - t[-2])
    runs = []
    start = 0
    for i in range(1, len(states) + 1):
        if i == len(states) or states[i] != states[start]:
            runs.append((int(states[start]), edges[start], edges[i]))
            start = i
    wrapped = [(s, a + period, b + period) for s, a, b in runs[:1]]
    wrapped += [(s, a - period, b - period) for s, a, b in runs[-1:]]
    return runs + wrapped


def _format_alpha(alpha):
    return "(" + ", ".join(f"{a:.3g}" for a in alpha) + ")"


def _row_title(key, row, dof, width_in):
    details = []
    if row["freq"] is not None:
        details.append(f"{row['freq']:.2f} Hz")
    if row["amplitude"] is not None and np.isfinite(row["amplitude"]):
        details.append(f"amplitude of {dof or 'response DOF'} = {row['amplitude']:.4e} m")
    title = ROW_TITLES[key] + (": " + ", ".join(details) if details else "")
    if row["alpha"] is not None:
        alpha = "\u03b1 = " + _format_alpha(row["alpha"])
        # about 10 bold 11-pt characters per inch; wrap rather than run off the figure
        title += (", " if len(title) + len(alpha) + 2 <= 10 * width_in else "\n") + alpha
    return title


def make_figure(res):
    keys = [k for k in ("min", "max") if k in res["rows"]]
    nc = len(res["contacts"])
    nrows = len(keys)
    width = max(6.5, 3.3 * nc + 0.8)
    height = 3.0 * nrows + 0.9
    fig = plt.figure(figsize=(width, height), layout="constrained")
    subs = fig.subfigures(nrows + 1, 1, height_ratios=[1.0] * nrows + [0.16])

    # One force scale for every panel, so that contacts and responses compare at a glance.
    lo, hi = 0.0, 0.0
    for k in keys:
        r = res["rows"][k]
        mun = res["mu"][:, None] * r["N"]
        for arr in (r["T"], r["N"], mun, -mun):
            fin = arr[np.isfinite(arr)]
            if fin.size:
                lo, hi = min(lo, float(fin.min())), max(hi, float(fin.max()))
    pad = 0.06 * (hi - lo) if hi > lo else 1.0
    ylim = (lo - pad, hi + pad)

    any_slip = any_lift = False
    for ri, k in enumerate(keys):
        row = res["rows"][k]
        sf = subs[ri]
        axes = sf.subplots(1, nc, sharey=True, squeeze=False)[0]
        sf.suptitle(_row_title(k, row, res["response_dof"], width), fontsize=11,
                    fontweight="bold")
        t_ms = row["time"] * 1e3
        period_ms = row["period"] * 1e3
        for c, ax in enumerate(axes):
            for s, a, b in _state_runs(t_ms, row["states"][c], period_ms):
                if s in (SLIP_POS, SLIP_NEG):
                    ax.axvspan(a, b, color=COLOUR_SLIP, alpha=0.8, linewidth=0, zorder=0)
                    any_slip = True
                elif s == LIFT:
                    ax.axvspan(a, b, facecolor=COLOUR_LIFT, edgecolor="0.6", hatch="///",
                               linewidth=0, zorder=0)
                    any_lift = True
            mun = res["mu"][c] * row["N"][c]
            x, n = _closed(t_ms, row["N"][c], period_ms)
            ax.plot(x, n, color=COLOUR_N, linewidth=0.8, zorder=2)
            x, m = _closed(t_ms, mun, period_ms)
            ax.plot(x, m, color=COLOUR_MUN, linestyle="--", linewidth=1.2, zorder=3)
            ax.plot(x, -m, color=COLOUR_MUN, linestyle="--", linewidth=1.2, zorder=3)
            x, tt = _closed(t_ms, row["T"][c], period_ms)
            ax.plot(x, tt, color=COLOUR_T, linewidth=1.7, zorder=4)
            ax.axhline(0.0, color="0.75", linewidth=0.6, zorder=1)
            ax.set_xlim(t_ms[0], t_ms[0] + period_ms)
            ax.set_ylim(*ylim)
            name = res["contacts"][c]
            label = f"contact {c + 1}" if name in (f"c{c + 1}", str(c + 1), "") else \
                f"contact {c + 1} ({name})"
            ax.set_title(f"{label}: {row['regimes'][c]}", fontsize=10)
            ax.set_xlabel("time [ms]", fontsize=9)
            ax.tick_params(labelsize=8)
            ax.grid(True, color="0.9", linewidth=0.6)
            ax.set_axisbelow(True)
            if c == 0:
                ax.set_ylabel("force [N]", fontsize=9)

    handles = [Line2D([], [], color=COLOUR_T, linewidth=1.7, label="tangential force T"),
               Line2D([], [], color=COLOUR_MUN, linestyle="--", linewidth=1.2,
                      label="\u00b1\u03bcN (slip limit)"),
               Line2D([], [], color=COLOUR_N, linewidth=0.8, label="normal force N")]
    handles.append(Patch(facecolor=COLOUR_SLIP, alpha=0.8,
                         label="slip" + ("" if any_slip else " (none)")))
    handles.append(Patch(facecolor=COLOUR_LIFT, edgecolor="0.6", hatch="///",
                         label="lift-off" + ("" if any_lift else " (none)")))
    legend_fig = subs[-1]
    legend_fig.legend(handles=handles, loc="center", ncol=len(handles), fontsize=9, frameon=False)
    legend_fig.text(0.995, 0.0, f"fricrom {res['version']}  \u2013  {res['case_name']}",
                    ha="right", va="bottom", fontsize=7, color="0.5")
    return fig


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Plot the contact-force time histories at the response bounds of a fricrom "
                    "bounds file (HDF5) to PNG or SVG (paper Fig. 10, 12, 13, 15, 16).")
    parser.add_argument("bounds", metavar="BOUNDS.h5", help="fricrom bounds file")
    parser.add_argument("out", metavar="OUT.png", help="output image (.png or .svg)")
    parser.add_argument("--only", choices=("min", "max"),
                        help="draw only the minimum or only the maximum response")
    args = parser.parse_args(argv)

    def work():
        common.check_output(args.out)
        res = read_histories(args.bounds, args.only)
        fig = make_figure(res)
        common.save_figure(fig, args.out)
        return f"wrote {args.out}"

    return common.run(SCRIPT, work)


if __name__ == "__main__":
    sys.exit(main())
