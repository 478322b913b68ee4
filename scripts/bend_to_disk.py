#!/usr/bin/python3
"""Bend flat-cascade FE meshes onto a bladed disk of N sectors (cyclic symmetry), and check them.

Usage:
  bend_to_disk.py mesh IN_mesh.inp OUT_mesh.inp --sectors N --pitch P
  bend_to_disk.py deck IN_deck.inp OUT_deck.inp --sectors N --pitch P
  bend_to_disk.py check BLADE_mesh.inp DAMPER_mesh.inp --sectors N [--axis AX,AY,AZ] [--tol TOL]
  bend_to_disk.py centroid PREFIX

The flat cascade frame (meshes/README.md): x axial, y circumferential, z radial; the next sector is
this one translated by the pitch P in +y. The bending map puts the plane z = 0 (the blade's root
face) on the hub cylinder of radius R_h = N P / (2 pi) about the x axis:

    theta = y / R_h,  r = R_h + z;   x' = x,  y' = r sin(theta),  z' = r cos(theta)

so a translation by P in y becomes a rotation by 2 pi / N, about the axis [-1, 0, 0] through the
origin (right hand: +theta runs from +z towards +y). Every node is mapped, mid-side nodes included
(the C3D10 elements follow the arcs). The map stretches the circumferential direction by r / R_h
(volume and mass grow by the same factor); the radial direction and the axial one are unchanged.

mesh: maps the *NODE coordinates of a mesh deck written by fix_gmsh_inp.py clean (read with its
reader); every other line is copied unchanged, and one comment line after the header records the
map. Coordinates are written with Python's shortest round-trip repr, or in fixed point where that
would exceed the 20 characters CalculiX reads per field: deterministic.

deck: copies a CalculiX deck (meshes/*/<model>_deck.inp) with one comment line after its header
saying that the included mesh is bent.

check: the node-to-node coincidences of a bent blade sector and its bent damper (the damper in its
flat cascade position, between this blade's +y platform edge and the next blade's -y edge):
  damper CONTACT_LEFT  = blade CONTACT_RIGHT                                 (same sector)
  damper CONTACT_RIGHT = blade CONTACT_LEFT rotated by +2 pi / N about AXIS  (next sector)
(AXIS default -1,0,0, through the origin). Prints the largest distance of each; exit 1 unless every
node has a partner within TOL (default 1e-9 m).

centroid: the centre of mass of a free-free body from its CalculiX matrices PREFIX.mas, PREFIX.dof
and its mesh PREFIX_mesh.inp: c = (1^T M_x x) / (1^T M_x 1) per direction (exact for the
consistent mass matrix: sum_ij M_ij x_j = int rho x dV). Prints the mass, the centroid, its angle
theta_d = atan2(y, z) about the x axis and its radius sqrt(y^2 + z^2): the case file's theta_d and
radius (meshes/disk24/coarse.toml).

Plain python3 standard library. Exit status: 0 ok, 1 check failed, 2 usage.
"""

import math
import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ beside the scripts
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fix_gmsh_inp  # noqa: E402  (the mesh reader)


def fail(msg, code=1):
    sys.stderr.write("bend_to_disk.py: error: " + msg + "\n")
    sys.exit(code)


def options(args, known):
    """--name value pairs -> dict (values as text)."""
    out = {}
    i = 0
    while i < len(args):
        if args[i] not in known or i + 1 >= len(args):
            fail("unknown option or missing value: %s" % args[i], 2)
        out[args[i]] = args[i + 1]
        i += 2
    return out


def disk(opts):
    try:
        n = int(opts["--sectors"])
        p = float(opts["--pitch"])
    except (KeyError, ValueError):
        fail("give --sectors N (integer >= 2) and --pitch P [m]", 2)
    if n < 2 or not p > 0:
        fail("give --sectors N (integer >= 2) and --pitch P [m] > 0", 2)
    return n, p, n * p / (2.0 * math.pi)


def bend(xyz, r_hub):
    x, y, z = xyz
    theta = y / r_hub
    r = r_hub + z
    return (x, r * math.sin(theta), r * math.cos(theta))


def number(v):
    """A coordinate as text of at most 20 characters (CalculiX reads at most 20 per field): the
    shortest round-trip repr if it fits, else fixed point with as many decimals as fit (1e-17 m or
    finer below 1 m; the tiny values this rounds are round-off of the map, e.g. sin of -1e-18)."""
    text = repr(v)
    if len(text) <= 20 and "e" not in text and "E" not in text:
        return text
    whole = len("%.0f" % abs(v)) + (1 if v < 0 else 0)
    text = ("%.*f" % (20 - whole - 1, v)).rstrip("0")
    if text.endswith("."):
        text += "0"
    return "0.0" if text == "-0.0" else text


def map_line(n, p, r_hub):
    return ("** bent onto a disk by scripts/bend_to_disk.py: N = %d sectors, pitch %r m, "
            "R_h = N p / (2 pi) = %r m; theta = y / R_h, r = R_h + z, (x, y, z) -> "
            "(x, r sin theta, r cos theta); next sector = +2 pi / N about [-1, 0, 0] through the origin\n"
            % (n, p, r_hub))


def cmd_mesh(args):
    if len(args) < 2:
        fail("mesh needs IN_mesh.inp OUT_mesh.inp", 2)
    src, dst = args[0], args[1]
    n, p, r_hub = disk(options(args[2:], ("--sectors", "--pitch")))
    nodes, _, _, _ = fix_gmsh_inp.read_gmsh_inp(src)
    mapped = {nid: bend(xyz, r_hub) for nid, _, xyz in nodes}
    with open(src) as f:
        lines = f.readlines()
    tmp = dst + ".tmp"
    in_node, header_done, count = False, False, 0
    with open(tmp, "w") as out:
        for raw in lines:
            line = raw.strip()
            if not header_done and not line.startswith("**"):
                out.write(map_line(n, p, r_hub))
                header_done = True
            if line.startswith("*") and not line.startswith("**"):
                in_node = fix_gmsh_inp.parse_keyword(line)[0] == "NODE"
                out.write(raw)
                continue
            if in_node and line and not line.startswith("**"):
                nid = int(line.split(",", 1)[0])
                x, y, z = mapped[nid]
                out.write("%d, %s, %s, %s\n" % (nid, number(x), number(y), number(z)))
                count += 1
                continue
            out.write(raw)
    if count != len(nodes):
        os.remove(tmp)
        fail("%s: mapped %d node lines, the reader found %d nodes" % (src, count, len(nodes)))
    os.replace(tmp, dst)
    rs = [math.hypot(y, z) for x, y, z in mapped.values()]
    ts = [math.atan2(y, z) for x, y, z in mapped.values()]
    print("  %s: %d nodes bent onto R_h = %.9g m (N = %d, pitch %g m): r %.6g .. %.6g m, "
          "theta %.6g .. %.6g rad" % (os.path.basename(dst), count, r_hub, n, p, min(rs), max(rs),
                                     min(ts), max(ts)))
    return 0


def cmd_deck(args):
    if len(args) < 2:
        fail("deck needs IN_deck.inp OUT_deck.inp", 2)
    src, dst = args[0], args[1]
    n, p, r_hub = disk(options(args[2:], ("--sectors", "--pitch")))
    with open(src) as f:
        lines = f.readlines()
    k = 0
    while k < len(lines) and lines[k].startswith("**"):
        k += 1
    extra = ("** The included mesh is bent onto a disk of %d sectors (R_h = %.9g m, scripts/bend_to_disk.py);\n"
             "** a *BOUNDARY on ROOT clamps the root: the disk is taken as rigid.\n" % (n, r_hub))
    tmp = dst + ".tmp"
    with open(tmp, "w") as out:
        out.writelines(lines[:k])
        out.write(extra)
        out.writelines(lines[k:])
    os.replace(tmp, dst)
    return 0


def rotation(axis, angle):
    """Right-hand rotation matrix by angle about the unit vector along axis (Rodrigues)."""
    norm = math.sqrt(sum(a * a for a in axis))
    ux, uy, uz = (a / norm for a in axis)
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return ((c + ux * ux * t, ux * uy * t - uz * s, ux * uz * t + uy * s),
            (uy * ux * t + uz * s, c + uy * uy * t, uy * uz * t - ux * s),
            (uz * ux * t - uy * s, uz * uy * t + ux * s, c + uz * uz * t))


def apply(m, v):
    return tuple(sum(m[i][k] * v[k] for k in range(3)) for i in range(3))


def match(a, b, tol):
    """Every point of a has a partner in b (and the sizes agree)? -> (matched, worst distance)."""
    matched, worst = 0, 0.0
    for pa in a:
        best = min(math.dist(pa, pb) for pb in b)
        worst = max(worst, best)
        matched += best <= tol
    return matched, worst


def cmd_check(args):
    if len(args) < 2:
        fail("check needs BLADE_mesh.inp DAMPER_mesh.inp", 2)
    blade, damper = args[0], args[1]
    opts = options(args[2:], ("--sectors", "--axis", "--tol"))
    try:
        n = int(opts["--sectors"])
        axis = tuple(float(t) for t in opts.get("--axis", "-1,0,0").split(","))
        tol = float(opts.get("--tol", "1e-9"))
    except (KeyError, ValueError):
        fail("check needs --sectors N [--axis AX,AY,AZ] [--tol TOL]", 2)
    if len(axis) != 3:
        fail("--axis wants AX,AY,AZ", 2)
    rot = rotation(axis, 2.0 * math.pi / n)
    ok = True
    for d_set, b_set, turn, what in (("CONTACT_LEFT", "CONTACT_RIGHT", False, "same sector"),
                                     ("CONTACT_RIGHT", "CONTACT_LEFT", True,
                                      "next sector: +2 pi/%d about [%s]" % (n, ",".join("%g" % a for a in axis)))):
        d = [xyz for _, xyz in fix_gmsh_inp.read_set_coords(damper, d_set)]
        b = [xyz for _, xyz in fix_gmsh_inp.read_set_coords(blade, b_set)]
        if turn:
            b = [apply(rot, xyz) for xyz in b]
        matched, worst = match(d, b, tol)
        good = matched == len(d) == len(b)
        ok = ok and good
        print("  damper %s (%d nodes) <-> blade %s (%d nodes, %s): %d coincide, max distance %.3g m%s" % (
            d_set, len(d), b_set, len(b), what, matched, worst, "" if good else "  <-- NOT node-to-node"))
    return 0 if ok else 1


def cmd_centroid(args):
    if len(args) != 1:
        fail("centroid needs PREFIX", 2)
    prefix = args[0]
    nodes, _, _, _ = fix_gmsh_inp.read_gmsh_inp(prefix + "_mesh.inp")
    coords = {nid: xyz for nid, _, xyz in nodes}
    try:
        with open(prefix + ".dof") as f:
            dofs = []
            for line in f:
                if line.strip():
                    node, comp = line.strip().split(".")
                    dofs.append((int(node), int(comp)))
        mass = [0.0, 0.0, 0.0]
        moment = [0.0, 0.0, 0.0]
        with open(prefix + ".mas") as f:
            for line in f:
                t = line.split()
                if not t:
                    continue
                i, j, v = int(t[0]) - 1, int(t[1]) - 1, float(t[2])
                (ni, ci), (nj, cj) = dofs[i], dofs[j]
                if ci != cj or not 1 <= ci <= 3:
                    continue
                k = ci - 1
                # upper triangle: M_ij and M_ji
                mass[k] += v if i == j else 2.0 * v
                moment[k] += v * coords[nj][k] + (0.0 if i == j else v * coords[ni][k])
    except (OSError, ValueError, IndexError, KeyError) as e:
        fail("%s.mas/.dof: %s" % (prefix, e))
    if len({(n, c) for n, c in dofs}) != 3 * len(coords):
        fail("%s: not a free-free body (the .dof lacks some nodes' translations)" % prefix)
    c = [moment[k] / mass[k] for k in range(3)]
    theta = math.atan2(c[1], c[2])
    radius = math.hypot(c[1], c[2])
    print("  %s: mass %.9g kg, centroid (%.9g, %.9g, %.9g) m: theta_d = %.12g rad (%.9g deg), "
          "radius %.12g m" % (os.path.basename(prefix), mass[0], c[0], c[1], c[2], theta,
                              math.degrees(theta), radius))
    return 0


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        sys.stdout.write(__doc__)
        return 0 if len(argv) >= 2 else 2
    commands = {"mesh": cmd_mesh, "deck": cmd_deck, "check": cmd_check, "centroid": cmd_centroid}
    if argv[1] not in commands:
        fail("unknown command %s (mesh, deck, check or centroid)" % argv[1], 2)
    return commands[argv[1]](argv[2:])


if __name__ == "__main__":
    sys.exit(main(sys.argv))
