#!/usr/bin/python3
"""Contact-state map of an FE assembly's bounds: every contact face drawn with its node pairs
coloured by their state over the period (stick / stick-slip / slip / lift-off) and sized by their
mean normal load, at the minimum and at the maximum response bound.

Usage:
    /usr/bin/python3 scripts/plot_contact_map.py BOUNDS.h5 OUT.png

Reads the HDF5 layout written by `fricrom bounds` on an FE assembly case:
  /contact_map/position_m        float64 [nc x 3]  placed A-side node of each contact [m]
  /contact_map/interface         float64 [nc]      interface index (-1: not on an interface)
  /contact_map/interface_names   strings [ni]
  /histories/{min,max}/states    [nc x N]  0 stick, 1 positive slip, 2 negative slip, 3 lift-off
  /histories/{min,max}/normal_N  [nc x N]  normal load N(t) [N]
  /histories/{min,max} attributes freq_hz, amplitude_m
Contacts at one position of one interface are one node pair (two tangential directions share
the pair's normal gap; their normal loads add up). A pair's state: lift-off if it separates at any
sample, slip if it slips at every sample, stick if it sticks at every sample, else stick-slip.
Each face is drawn in its own plane (the two principal directions of its nodes, in mm).

Exit status: 0 on success, 2 on a missing dependency, file, dataset or inconsistent data.
Needs the Debian packages python3-matplotlib, python3-numpy and python3-h5py.
"""
import sys

try:
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
except ImportError as e:
    print(f"plot_contact_map.py: missing dependency: {e}", file=sys.stderr)
    sys.exit(2)

STATES = ["stick", "stick-slip", "slip", "lift-off"]
COLOURS = ["#1f77b4", "#ff7f0e", "#d62728", "#7f7f7f"]


def fail(msg):
    print(f"plot_contact_map.py: {msg}", file=sys.stderr)
    sys.exit(2)


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def pair_state(samples):
    """samples: [contacts of the pair x N] state codes -> index into STATES."""
    lift = (samples == 3).any(axis=0)
    slip = ((samples == 1) | (samples == 2)).any(axis=0)
    if lift.any():
        return 3
    if slip.all():
        return 2
    if not slip.any():
        return 0
    return 1


def face_coordinates(points):
    """Project a face's points onto its two principal directions [mm]."""
    centred = points - points.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    return 1e3 * centred @ vt[:2].T


def main(argv):
    if len(argv) != 3:
        fail("usage: plot_contact_map.py BOUNDS.h5 OUT.png")
    try:
        f = h5py.File(argv[1], "r")
    except OSError as e:
        fail(f"cannot read {argv[1]}: {e}")
    with f:
        if "contact_map" not in f:
            fail(f"{argv[1]} has no /contact_map (not an FE assembly with interfaces)")
        pos = np.asarray(f["contact_map/position_m"], dtype=float)
        iface = np.asarray(f["contact_map/interface"], dtype=float).astype(int)
        names = [text(n) for n in f["contact_map/interface_names"]]
        if pos.ndim != 2 or pos.shape[1] != 3 or iface.shape[0] != pos.shape[0]:
            fail("inconsistent /contact_map datasets")
        bounds = []
        for which in ("min", "max"):
            g = f.get(f"histories/{which}")
            if g is None:
                print(f"plot_contact_map.py: no {which} history (bound not converged)",
                      file=sys.stderr)
                continue
            states = np.asarray(g["states"], dtype=float).astype(int)
            normal = np.asarray(g["normal_N"], dtype=float)
            if states.shape[0] != pos.shape[0] or normal.shape != states.shape:
                fail(f"histories/{which} does not match /contact_map")
            bounds.append((which, dict(g.attrs), states, normal))
    if not bounds:
        fail("neither bound converged: nothing to draw")

    faces = [i for i in range(len(names)) if (iface == i).any()]
    # Pairs: contacts of one interface at one position.
    pairs = {}
    for i in faces:
        idx = np.flatnonzero(iface == i)
        keys = {}
        for c in idx:
            keys.setdefault(tuple(np.round(pos[c] * 1e9).astype(np.int64)), []).append(c)
        pairs[i] = list(keys.values())
    load_max = max(
        max(normal[p].sum(axis=0).mean() for i in faces for p in pairs[i])
        for _, _, _, normal in bounds)
    load_max = max(load_max, 1e-300)

    fig, axes = plt.subplots(len(bounds), len(faces), figsize=(3.2 * len(faces), 3.0 * len(bounds)),
                             squeeze=False)
    for r, (which, attrs, states, normal) in enumerate(bounds):
        for col, i in enumerate(faces):
            ax = axes[r][col]
            members = pairs[i]
            xy = face_coordinates(np.array([pos[p[0]] for p in members]))
            st = np.array([pair_state(states[p]) for p in members])
            load = np.array([normal[p].sum(axis=0).mean() for p in members])
            size = 10 + 140 * np.clip(load, 0, None) / load_max
            for s in range(4):
                m = st == s
                if m.any():
                    ax.scatter(xy[m, 0], xy[m, 1], s=size[m], c=COLOURS[s], edgecolors="k",
                               linewidths=0.4)
            counts = ", ".join(f"{(st == s).sum()} {STATES[s]}" for s in range(4) if (st == s).any())
            ax.set_title(f"{names[i]}\n{counts}", fontsize=7)
            ax.set_aspect("equal", adjustable="datalim")
            ax.tick_params(labelsize=6)
            ax.text(0.02, 0.02, f"ΣN̄ = {load.sum():.3g} N", transform=ax.transAxes, fontsize=7)
            if col == 0:
                amp = attrs.get("amplitude_m", float("nan"))
                freq = attrs.get("freq_hz", float("nan"))
                ax.set_ylabel(f"{which}imum response\n{amp:.3e} m at {freq:.1f} Hz\n[mm]",
                              fontsize=7)
    handles = [plt.Line2D([], [], marker="o", ls="", color=COLOURS[s], markeredgecolor="k",
                          label=STATES[s]) for s in range(4)]
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=8,
               title="node-pair state over the period (marker area ∝ mean normal load)",
               title_fontsize=8)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    fig.savefig(argv[2], dpi=150)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
