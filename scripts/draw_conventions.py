#!/usr/bin/python3
"""Draw docs/figures/contact_conventions.png: geometry and sign conventions of the wedge
under-platform damper contacts of the lumped 3-blade / 2-damper system.

Usage:
    /usr/bin/python3 scripts/draw_conventions.py [OUT.png]
(default OUT: docs/figures/contact_conventions.png relative to the repository root).

Conventions drawn (they must match src/model/case_file.cpp and docs/theory.md):
  x to the right, y up; dampers pushed up (+y) by the preload F0 into the platforms.
  theta = base angle between the damper's horizontal base and an inclined face.
  left face  (contact with the blade on the left):  n = (-sin th, cos th), t = (cos th,  sin th)
  right face (contact with the blade on the right): n = ( sin th, cos th), t = (cos th, -sin th)
  v = n.(q_damper - q_blade) (> 0 pressing), u = t.(q_damper - q_blade)
  N = max(N0 + kn v, 0), stick T = kt (u - w); F = N n + T t on the blade, -F on the damper.
  Contacts: 1 = damper 1 / blade 1 (left face), 2 = damper 1 / blade 2 (right face),
            3 = damper 2 / blade 2 (left face), 4 = damper 2 / blade 3 (right face).
  Eq. 12: th1 = th4 = th_ref (1 - beta), th2 = th3 = th_ref (1 + beta).
  Eq. 11: F0 on damper 1 = F0_ref (1 - gamma), on damper 2 = F0_ref (1 + gamma).
"""

import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fricrom_plot_common  # noqa: E402  (checks numpy and matplotlib first, exit 2 if missing)
from fricrom_plot_common import np, plt  # noqa: E402
from matplotlib.patches import Arc, FancyArrowPatch, Polygon, Rectangle  # noqa: E402

BLADE_FACE = "#dfe6ee"
BLADE_EDGE = "#44546a"
DAMPER_FACE = "#f3d9a4"
DAMPER_EDGE = "#7a5200"
CONTACT = "#c0392b"
NORMAL = "#1f5fbf"
TANGENT = "#1e8449"
LOAD = "#6c3483"


def arrow(ax, p, q, color, lw=1.8, ms=12, z=6, style="-|>"):
    ax.add_patch(FancyArrowPatch(p, q, arrowstyle=style, mutation_scale=ms, color=color,
                                 linewidth=lw, zorder=z, shrinkA=0, shrinkB=0))


def left_normal(th):
    return np.array([-np.sin(th), np.cos(th)])


def left_tangent(th):
    return np.array([np.cos(th), np.sin(th)])


def right_normal(th):
    return np.array([np.sin(th), np.cos(th)])


def right_tangent(th):
    return np.array([np.cos(th), -np.sin(th)])


def axes_triad(ax, origin, size=0.6, fs=9):
    o = np.asarray(origin, dtype=float)
    arrow(ax, o, o + [size, 0], "black", lw=1.2, ms=9)
    arrow(ax, o, o + [0, size], "black", lw=1.2, ms=9)
    ax.text(o[0] + size + 0.08, o[1], "$x$", fontsize=fs, va="center")
    ax.text(o[0], o[1] + size + 0.08, "$y$", fontsize=fs, ha="center", va="bottom")


def circled(ax, xy, text, fs=9):
    ax.text(xy[0], xy[1], text, ha="center", va="center", fontsize=fs, color="white",
            fontweight="bold", zorder=10,
            bbox=dict(boxstyle="circle,pad=0.22", fc=CONTACT, ec="none"))


def spring(ax, p, q, n_coils=6, amp=0.12, color="0.35"):
    p, q = np.asarray(p, float), np.asarray(q, float)
    d = q - p
    length = np.linalg.norm(d)
    e = d / length
    perp = np.array([-e[1], e[0]])
    lead = 0.18 * length
    pts = [p, p + lead * e]
    m = 2 * n_coils
    for i in range(m):
        s = lead + (length - 2 * lead) * (i + 0.5) / m
        pts.append(p + s * e + (amp if i % 2 == 0 else -amp) * perp)
    pts += [q - lead * e, q]
    pts = np.array(pts)
    ax.plot(pts[:, 0], pts[:, 1], color=color, lw=1.0, zorder=2)


# --------------------------------------------------------------------------------------------
# (a) the lumped system
# --------------------------------------------------------------------------------------------
def panel_system(ax):
    th = np.deg2rad(45.0)
    tan = np.tan(th)
    pitch = 4.4
    centres = [0.0, pitch, 2 * pitch]
    joints = [pitch / 2, 1.5 * pitch]
    plat_top, plat_bot = 0.6, 0.0
    g = 0.1          # half gap between adjacent platforms
    yc = 0.45        # height where a platform chamfer meets the gap
    damper_bot = -1.05
    shank_bot, ground = -2.2, -2.55
    foil_top = 3.6

    # Blades: platform with chamfered ends + shank, airfoil above.
    for i, xc in enumerate(centres):
        left_edge = xc - pitch / 2 + g
        right_edge = xc + pitch / 2 - g
        pts = [(left_edge, plat_top), (right_edge, plat_top)]
        if i < 2:   # right end: chamfer touching the left face of the damper under it
            xj = joints[i]
            pts += [(xj - g, yc), (xj - g - (yc - plat_bot) / tan, plat_bot)]
        else:
            pts += [(right_edge, plat_bot)]
        pts += [(xc + 0.35, plat_bot), (xc + 0.35, shank_bot), (xc - 0.35, shank_bot),
                (xc - 0.35, plat_bot)]
        if i > 0:   # left end: chamfer touching the right face of the damper under it
            xj = joints[i - 1]
            pts += [(xj + g + (yc - plat_bot) / tan, plat_bot), (xj + g, yc)]
        else:
            pts += [(left_edge, plat_bot)]
        ax.add_patch(Polygon(pts, closed=True, fc=BLADE_FACE, ec=BLADE_EDGE, lw=1.2, zorder=3))
        ax.add_patch(Rectangle((xc - 0.45, plat_top), 0.9, foil_top - plat_top, fc=BLADE_FACE,
                               ec=BLADE_EDGE, lw=1.2, zorder=3))
        ax.text(xc, 2.1, f"blade {i + 1}", ha="center", va="center", fontsize=9, rotation=90,
                zorder=4)
        # Ground (disk) connection under the shank.
        ax.plot([xc - 0.6, xc + 0.6], [ground, ground], color="0.3", lw=1.2, zorder=2)
        for k in range(5):
            x0 = xc - 0.6 + 0.26 * k
            ax.plot([x0, x0 + 0.18], [ground, ground - 0.2], color="0.3", lw=0.8, zorder=2)
        spring(ax, (xc, shank_bot), (xc, ground), n_coils=3, amp=0.1)
    ax.text(centres[0] - 0.2, (shank_bot + ground) / 2, "$k,\\ c$", fontsize=8, ha="right",
            va="center", color="0.3")

    # Blade-blade coupling springs k_C.
    for xj in joints:
        spring(ax, (xj - pitch / 2 + 0.45, 3.3), (xj + pitch / 2 - 0.45, 3.3), n_coils=6)
        ax.text(xj, 3.5, "$k_C$", ha="center", va="bottom", fontsize=8, color="0.3")

    # Dampers and contacts.
    names = [("1", "2"), ("3", "4")]
    thetas = [(r"$\theta_1$", r"$\theta_2$"), (r"$\theta_3$", r"$\theta_4$")]
    preloads = [r"$F_0^{\mathrm{ref}}(1-\gamma)$", r"$F_0^{\mathrm{ref}}(1+\gamma)$"]
    for d, xj in enumerate(joints):
        apex = (xj, yc + g * tan)
        xl = xj - g - (yc - damper_bot) / tan
        xr = xj + g + (yc - damper_bot) / tan
        ax.add_patch(Polygon([(xl, damper_bot), (xr, damper_bot), apex], closed=True,
                             fc=DAMPER_FACE, ec=DAMPER_EDGE, lw=1.2, zorder=4))
        ax.text(xj, -0.5, f"damper {d + 1}", ha="center", va="center", fontsize=8, zorder=5)
        # Contact segments (platform chamfers) in red, numbered as in the paper.
        x_lo = xj - g - (yc - plat_bot) / tan
        x_hi = xj + g + (yc - plat_bot) / tan
        ax.plot([x_lo, xj - g], [plat_bot, yc], color=CONTACT, lw=3.0, zorder=5,
                solid_capstyle="butt")
        ax.plot([xj + g, x_hi], [yc, plat_bot], color=CONTACT, lw=3.0, zorder=5,
                solid_capstyle="butt")
        for sgn, name, xm in ((-1, names[d][0], (x_lo + xj - g) / 2),
                              (1, names[d][1], (x_hi + xj + g) / 2)):
            c = (xj + sgn * 0.95, 1.1)
            ax.plot([c[0], xm], [c[1], yc / 2], color=CONTACT, lw=0.9, zorder=5)
            circled(ax, c, name)
        # Base angles.
        r = 0.5
        ax.add_patch(Arc((xl, damper_bot), 2 * r, 2 * r, theta1=0, theta2=45, color="black",
                         lw=0.9, zorder=6))
        ax.add_patch(Arc((xr, damper_bot), 2 * r, 2 * r, theta1=135, theta2=180, color="black",
                         lw=0.9, zorder=6))
        ax.text(xl + r + 0.05, damper_bot + 0.16, thetas[d][0], fontsize=8.5, zorder=6,
                va="center")
        ax.text(xr - r - 0.05, damper_bot + 0.16, thetas[d][1], fontsize=8.5, zorder=6,
                va="center", ha="right")
        # Preload (centrifugal), pushing the damper up into the platforms.
        arrow(ax, (xj, -2.15), (xj, damper_bot - 0.02), LOAD, lw=2.0)
        ax.text(xj, -2.2, preloads[d], fontsize=8.5, color=LOAD, ha="center", va="top")

    # Harmonic excitation on blades 1 and 3.
    for xc, sx, k in ((centres[0], 1.0, 1), (centres[2], -1.0, 3)):
        arrow(ax, (xc, foil_top), (xc + 0.25 * sx, foil_top + 1.0), LOAD, lw=2.0)
        ax.text(xc + 0.25 * sx - 0.15 * sx, foil_top + 1.05,
                r"$\mathbf{f}_{%d}\cos\omega t$" % k, fontsize=9, color=LOAD,
                ha="right" if sx > 0 else "left", va="center")

    axes_triad(ax, (-2.3, 3.9))
    ax.text(pitch, -3.1,
            "contacts: 1 = damper 1 (left face) / blade 1,   2 = damper 1 (right face) / blade 2,\n"
            "3 = damper 2 (left face) / blade 2,   4 = damper 2 (right face) / blade 3\n"
            r"Eq. 12: $\theta_1=\theta_4=\theta_{\mathrm{ref}}(1-\beta)$,  "
            r"$\theta_2=\theta_3=\theta_{\mathrm{ref}}(1+\beta)$" "\n"
            r"Eq. 11: preload $F_0$ on damper 1 $=F_0^{\mathrm{ref}}(1-\gamma)$, "
            r"on damper 2 $=F_0^{\mathrm{ref}}(1+\gamma)$",
            ha="center", va="top", fontsize=7.8, linespacing=1.55)
    ax.set_xlim(-2.7, 2 * pitch + 2.7)
    ax.set_ylim(-5.2, 5.0)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title("(a) lumped system: 3 blades, 2 wedge dampers, contacts 1-4", fontsize=10)


# --------------------------------------------------------------------------------------------
# (b) close-up of one damper
# --------------------------------------------------------------------------------------------
def panel_closeup(ax):
    thl, thr = np.deg2rad(38.0), np.deg2rad(52.0)   # drawn unequal on purpose
    half = 2.7
    bl, br = np.array([-half, 0.0]), np.array([half, 0.0])
    xa = (2 * half * np.tan(thr)) / (np.tan(thl) + np.tan(thr)) - half
    apex = np.array([xa, (xa + half) * np.tan(thl)])
    ax.add_patch(Polygon([bl, br, apex], closed=True, fc=DAMPER_FACE, ec=DAMPER_EDGE, lw=1.4,
                         zorder=3))
    ax.text(0.1, 0.28, "damper", ha="center", va="center", fontsize=9, zorder=4)
    ax.plot([bl[0] - 0.4, br[0] + 0.4], [0, 0], color="0.5", lw=0.6, ls="--", zorder=1)

    faces = (
        # side, start, end, n, t, where on the face the arrows start (fraction from start)
        ("left", bl, apex, left_normal(thl), left_tangent(thl), 0.45),
        ("right", apex, br, right_normal(thr), right_tangent(thr), 0.3),
    )
    for side, p0, p1, n, t, frac in faces:
        length = np.linalg.norm(p1 - p0)
        # The blade platform touching this face, drawn as a detached strip (exploded view).
        g0, g1 = 0.12, 0.45
        s0, s1 = 0.1 * length, 0.9 * length
        strip = [p0 + s0 * t + g0 * n, p0 + s1 * t + g0 * n, p0 + s1 * t + g1 * n,
                 p0 + s0 * t + g1 * n]
        ax.add_patch(Polygon(strip, closed=True, fc=BLADE_FACE, ec=BLADE_EDGE, lw=1.0,
                             hatch="////", zorder=2))
        m = p0 + frac * length * t
        ax.plot(*m, "o", color="black", ms=3.5, zorder=8)
        arrow(ax, m, m + 1.2 * n, NORMAL, lw=2.0, ms=13, z=8)
        arrow(ax, m, m + 1.0 * t, TANGENT, lw=2.0, ms=13, z=8)
        pn = m + 1.3 * n
        ax.text(pn[0], pn[1], r"$\mathbf{n}$", color=NORMAL, fontsize=12, zorder=9,
                ha="center", va="center")
        pt = m + 0.95 * t - 0.32 * n
        ax.text(pt[0], pt[1], r"$\mathbf{t}$", color=TANGENT, fontsize=12, zorder=9,
                ha="center", va="center")
        if side == "left":
            q = p0 + s0 * t + g1 * n
            ax.text(q[0] - 0.05, q[1] + 0.1, "left blade\n(platform)", fontsize=8,
                    color=BLADE_EDGE, ha="right", va="bottom")
        else:
            q = p0 + s1 * t + g1 * n
            ax.text(q[0] + 0.08, q[1] + 0.1, "right blade\n(platform)", fontsize=8,
                    color=BLADE_EDGE, ha="left", va="bottom")

    # Base angles at both corners.
    r = 0.75
    ax.add_patch(Arc(bl, 2 * r, 2 * r, theta1=0, theta2=np.rad2deg(thl), lw=1.1, zorder=6))
    ax.add_patch(Arc(br, 2 * r, 2 * r, theta1=180 - np.rad2deg(thr), theta2=180, lw=1.1,
                     zorder=6))
    ax.text(bl[0] + r + 0.08, 0.2, r"$\theta$", fontsize=11, va="center", zorder=6)
    ax.text(br[0] - r - 0.08, 0.25, r"$\theta$", fontsize=11, va="center", ha="right", zorder=6)

    # Unit vectors of each face, under its base corner.
    ax.text(-4.45, -0.15,
            "left face (blade on the left):\n"
            r"$\mathbf{n}=(-\sin\theta,\ \cos\theta)$" "\n"
            r"$\mathbf{t}=(\cos\theta,\ \sin\theta)$",
            fontsize=8.5, ha="left", va="top", linespacing=1.45)
    ax.text(4.45, -0.15,
            "right face (blade on the right):\n"
            r"$\mathbf{n}=(\sin\theta,\ \cos\theta)$" "\n"
            r"$\mathbf{t}=(\cos\theta,\ -\sin\theta)$",
            fontsize=8.5, ha="right", va="top", linespacing=1.45)

    # Preload.
    arrow(ax, (0.1, -1.25), (0.1, -0.02), LOAD, lw=2.2)
    ax.text(0.22, -0.85, r"$F_0$", color=LOAD, fontsize=10, va="center")
    axes_triad(ax, (-4.3, 2.9), size=0.55)

    ax.text(0.0, -1.75,
            r"$v=\mathbf{n}^T(\mathbf{q}_{\mathrm{damper}}-\mathbf{q}_{\mathrm{blade}})$"
            r"  ($v>0$: pressing into the blade)" "\n"
            r"$u=\mathbf{t}^T(\mathbf{q}_{\mathrm{damper}}-\mathbf{q}_{\mathrm{blade}})$" "\n"
            r"$N=\max(N_0+k_n v,\ 0)\geq 0$;  stick: $T=k_t(u-w)$, slip: $|T|=\mu N$" "\n"
            r"$\mathbf{F}=N\,\mathbf{n}+T\,\mathbf{t}$ acts on the blade, $-\mathbf{F}$ "
            r"on the damper" "\n"
            r"$\theta$: base angle of that face ($\theta_1\ldots\theta_4$, drawn unequal here)" "\n"
            r"$F_0$: centrifugal preload on the damper, along $+y$",
            ha="center", va="top", fontsize=8, linespacing=1.55,
            bbox=dict(boxstyle="round,pad=0.4", fc="#f7f7f7", ec="0.7"))
    ax.set_xlim(-4.6, 4.6)
    ax.set_ylim(-5.0, 4.0)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title("(b) one damper: faces, normals, tangents, signs", fontsize=10)


def main(argv):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = argv[1] if len(argv) > 1 else os.path.join(root, "docs", "figures",
                                                     "contact_conventions.png")
    plt.rcParams.update({"mathtext.fontset": "dejavusans"})
    fig = plt.figure(figsize=(10.0, 5.0))
    gs = fig.add_gridspec(1, 2, width_ratios=[1.2, 1.0], wspace=0.02, left=0.005, right=0.995,
                          top=0.93, bottom=0.01)
    panel_system(fig.add_subplot(gs[0, 0]))
    panel_closeup(fig.add_subplot(gs[0, 1]))

    if os.path.splitext(out)[1].lower() not in fricrom_plot_common.SUPPORTED_EXTENSIONS:
        out += ".png"
    fricrom_plot_common.save_figure(fig, out)
    plt.close(fig)
    print(f"draw_conventions.py: wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
