#!/usr/bin/python3
"""Draw the blade-sector and damper FE models with their node sets (docs/figures/fe_models.png).

Usage:
    /usr/bin/python3 scripts/plot_mesh.py [--blade DECK] [--damper DECK] [--out OUT.png]
Reads the nodes and *NSET node sets of the CalculiX mesh decks (meshes/*/coarse/*_mesh.inp) with
scripts/fix_gmsh_inp.py's reader and draws the nodes in 3-D, the contact, excitation and
response sets highlighted. Needs python3-matplotlib and python3-numpy.
"""

import argparse
import os
import sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fricrom_plot_common as common  # noqa: E402  (checks numpy, matplotlib, h5py first)
from fricrom_plot_common import InputError, np, plt  # noqa: E402
from fix_gmsh_inp import read_gmsh_inp  # noqa: E402  (the mesh-deck reader of make_meshes.sh)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_deck(path):
    """Nodes {id: (x, y, z)} and node sets {NAME: [ids]} of a cleaned mesh deck (*_mesh.inp)."""
    if not os.path.exists(path):
        raise InputError(f"{path}: no such file (regenerate with: bash scripts/make_meshes.sh)")
    nodes, _blocks, _elsets, nsets = read_gmsh_inp(path)  # exits with a message on bad input
    return {i: xyz for i, _text, xyz in nodes}, nsets


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--blade", default=os.path.join(ROOT, "meshes/blade_sector/coarse/blade_sector_mesh.inp"))
    ap.add_argument("--damper", default=os.path.join(ROOT, "meshes/damper/coarse/damper_mesh.inp"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs/figures/fe_models.png"))
    args = ap.parse_args()

    def work():
        common.check_output(args.out)
        bn, bs = read_deck(args.blade)
        dn, ds = read_deck(args.damper)
        fig = plt.figure(figsize=(11, 5.2))
        for k, (elev, azim, title) in enumerate(((22, -60, "blade sector + damper"),
                                                  (0, 0, "view along x (axial): platform chamfers and damper wedge"))):
            ax = fig.add_subplot(1, 2, k + 1, projection="3d")
            xyz = np.array(list(bn.values()))
            ax.scatter(xyz[:, 0], xyz[:, 1], xyz[:, 2], s=1.5, c="0.6", alpha=0.5, label=f"blade nodes ({len(bn)})")
            d = np.array(list(dn.values()))
            ax.scatter(d[:, 0], d[:, 1], d[:, 2], s=2, c="#c98a00", alpha=0.6, label=f"damper nodes ({len(dn)})")
            styles = (("ROOT", bs, "k", 3, "ROOT (clamped)"),
                      ("CONTACT_LEFT", bs, "#1f5fbf", 10, "blade CONTACT_LEFT"),
                      ("CONTACT_RIGHT", bs, "#c0392b", 10, "blade CONTACT_RIGHT = damper CONTACT_LEFT"),
                      ("EXCITATION", bs, "#1e8449", 60, "EXCITATION"),
                      ("RESPONSE", bs, "#6c3483", 60, "RESPONSE"))
            for name, sets, color, size, label in styles:
                ids = sets.get(name, [])
                if not ids:
                    raise InputError(f"{args.blade}: no node set {name}")
                p = np.array([bn[i] for i in ids])
                ax.scatter(p[:, 0], p[:, 1], p[:, 2], s=size, c=color, label=f"{label} ({len(ids)})", depthshade=False)
            ax.view_init(elev=elev, azim=azim)
            ax.set_xlabel("x axial [m]")
            ax.set_ylabel("y circumf. [m]")
            ax.set_zlabel("z radial [m]")
            ax.set_title(title, fontsize=9)
            ax.set_box_aspect(np.ptp(np.vstack([xyz, d]), axis=0))
            ax.locator_params(nbins=4)
            ax.tick_params(labelsize=7)
            if k == 1:
                ax.set_xticks([])
                ax.set_xlabel("")
            if k == 0:
                ax.legend(fontsize=6.5, loc="upper left", markerscale=1.5)
        fig.suptitle("FE models (gmsh C3D10, CalculiX matrices), coarse variants; units m", fontsize=10)
        fig.tight_layout()
        common.save_figure(fig, args.out)
        return f"wrote {args.out}"

    return common.run("plot_mesh.py", work)


if __name__ == "__main__":
    sys.exit(main())
