#!/usr/bin/python3
"""Post-process gmsh Abaqus/CalculiX (.inp) exports for CalculiX, and check mesh pairs.

Usage:
  fix_gmsh_inp.py clean IN.inp OUT.inp --elset NAME [--require SET[,SET...]] [--single SET[,SET...]]
                                        [--title TEXT] [--summary FILE]
  fix_gmsh_inp.py pairs A.inp SET_A B.inp SET_B [--shift DX,DY,DZ] [--tol TOL]
  fix_gmsh_inp.py mass PREFIX

clean: gmsh (Mesh.SaveGroupsOfNodes = 1) writes every mesh entity of the physical groups as its own
*ELEMENT block, including the line/surface elements (T3D*, CPS6, ...) of lower-dimensional
groups, which CalculiX rejects (no section). The output keeps
  *NODE, NSET=NALL            all nodes used by the volume elements (ids unchanged)
  *ELEMENT, TYPE=C3D10, ELSET=NAME   the C3D10 elements only, renumbered 1..n in gmsh order
  *NSET, NSET=...             the node sets of the physical groups, except the volume's own set
                              (node ids sorted, 16 per line)
and checks: only C3D10 volume elements, the volume's physical group = all of them, every --require
set present and non-empty, every --single set exactly one node. Prints a one-line summary per set;
--summary FILE also writes them as shell-readable lines (nodes=N, elements=N, set_<NAME>=count,
node_<NAME>=id for one-node sets).

pairs: for every node of SET_A (in A.inp), finds the node of SET_B (in B.inp, coordinates shifted
by DX,DY,DZ) at the same place (within TOL, default 1e-9 m); prints how many match. Exit 1 unless
both sets have the same size and every node has a partner.

mass: reads the CalculiX matrix files PREFIX.mas and PREFIX.dof (*FREQUENCY, SOLVER=MATRIXSTORAGE)
and prints the translational mass u_d^T M u_d of a unit rigid translation along x, y, z (the mass
carried by the free DOFs: all of it for a free body, less the constrained nodes' share otherwise).

Plain python3 standard library; deterministic output. Exit status: 0 ok, 1 check failed, 2 usage.
"""

import os
import sys


def fail(msg, code=1):
    sys.stderr.write("fix_gmsh_inp.py: error: " + msg + "\n")
    sys.exit(code)


def parse_keyword(line):
    """'*ELEMENT, type=C3D10, ELSET=Volume1' -> ('ELEMENT', {'TYPE': 'C3D10', 'ELSET': 'Volume1'})."""
    parts = [p.strip() for p in line[1:].split(",")]
    params = {}
    for p in parts[1:]:
        if not p:
            continue
        if "=" in p:
            k, v = p.split("=", 1)
            params[k.strip().upper()] = v.strip()
        else:
            params[p.upper()] = ""
    return parts[0].upper(), params


def ints(line):
    return [int(t) for t in line.replace(",", " ").split()]


def read_gmsh_inp(path):
    """Returns (nodes: list of (id, 'x, y, z' text, (x, y, z))), blocks: list of (type, [ids + conn]),
    elsets: {name: [ids]}, nsets: {name: [ids]} (in file order)."""
    nodes, blocks, elsets, nsets = [], [], {}, {}
    mode, cur = None, None
    with open(path) as f:
        for number, raw in enumerate(f, 1):
            line = raw.strip()
            if not line or line.startswith("**"):
                continue
            if line.startswith("*"):
                name, params = parse_keyword(line)
                mode, cur = None, None
                if name == "NODE":
                    mode = "node"
                elif name == "ELEMENT":
                    mode = "elem"
                    cur = []
                    blocks.append((params.get("TYPE", "").upper(), cur))
                elif name == "ELSET":
                    mode = "set"
                    cur = elsets.setdefault(params["ELSET"].upper(), [])
                elif name == "NSET":
                    mode = "set"
                    cur = nsets.setdefault(params["NSET"].upper(), [])
                elif name == "HEADING":
                    mode = "skip"
                else:
                    fail("%s:%d: unexpected keyword %s" % (path, number, name))
                continue
            try:
                if mode == "node":
                    fields = [t.strip() for t in line.split(",")]
                    if len(fields) != 4:
                        raise ValueError("expected 'id, x, y, z'")
                    xyz = tuple(float(t) for t in fields[1:])
                    nodes.append((int(fields[0]), ", ".join(fields[1:]), xyz))
                elif mode == "elem":
                    cur.append(ints(line))
                elif mode == "set":
                    cur.extend(ints(line))
                elif mode == "skip":
                    pass
                else:
                    raise ValueError("data line outside a known block")
            except ValueError as e:
                fail("%s:%d: %s" % (path, number, e))
    return nodes, blocks, elsets, nsets


def write_ids(out, ids):
    for i in range(0, len(ids), 16):
        out.write(", ".join(str(n) for n in ids[i:i + 16]) + "\n")


def cmd_clean(args):
    if len(args) < 2:
        fail("clean needs IN.inp OUT.inp", 2)
    src, dst = args[0], args[1]
    elset, require, single, title, summary = None, [], [], "", None
    i = 2
    while i < len(args):
        if i + 1 >= len(args):
            fail("option %s needs a value" % args[i], 2)
        opt, val = args[i], args[i + 1]
        if opt == "--elset":
            elset = val.upper()
        elif opt == "--require":
            require += [s.upper() for s in val.split(",") if s]
        elif opt == "--single":
            single += [s.upper() for s in val.split(",") if s]
        elif opt == "--title":
            title = val
        elif opt == "--summary":
            summary = val
        else:
            fail("unknown option " + opt, 2)
        i += 2
    if not elset:
        fail("clean needs --elset NAME", 2)

    nodes, blocks, elsets, nsets = read_gmsh_inp(src)
    vol = []
    dropped = {}
    for etype, rows in blocks:
        if etype == "C3D10":
            for r in rows:
                if len(r) != 11:
                    fail("%s: C3D10 element %d has %d nodes" % (src, r[0], len(r) - 1))
            vol.extend(rows)
        elif etype.startswith("C3D"):
            fail("%s: volume elements of type %s (want C3D10 only; Mesh.ElementOrder = 2?)" % (src, etype))
        else:
            dropped[etype] = dropped.get(etype, 0) + len(rows)
    if not vol:
        fail("%s: no C3D10 elements" % src)
    vol_ids = sorted(r[0] for r in vol)
    if elset not in elsets:
        fail("%s: no physical volume group %s (have %s)" % (src, elset, ", ".join(sorted(elsets)) or "none"))
    if sorted(elsets[elset]) != vol_ids:
        fail("%s: physical group %s is not exactly the set of C3D10 elements" % (src, elset))

    used = set()
    for r in vol:
        used.update(r[1:])
    node_ids = [n[0] for n in nodes]
    if len(set(node_ids)) != len(node_ids):
        fail("%s: duplicate node ids" % src)
    missing = used - set(node_ids)
    if missing:
        fail("%s: elements use undefined nodes, e.g. %d" % (src, min(missing)))
    kept = [n for n in nodes if n[0] in used]

    out_sets = []
    for name, ids in nsets.items():
        if name == elset:
            continue  # all nodes of the volume: written as NSET=NALL on *NODE
        ids = sorted(set(ids))
        bad = [n for n in ids if n not in used]
        if bad:
            fail("%s: set %s has nodes outside the volume mesh, e.g. %d" % (src, name, bad[0]))
        out_sets.append((name, ids))
    have = dict(out_sets)
    for name in require + single:
        if name not in have or not have[name]:
            fail("%s: node set %s missing or empty (have %s)" % (src, name, ", ".join(sorted(have)) or "none"))
    for name in single:
        if len(have[name]) != 1:
            fail("%s: node set %s has %d nodes, want exactly 1" % (src, name, len(have[name])))

    tmp = dst + ".tmp"
    with open(tmp, "w") as out:
        out.write("** %s\n" % (title or "mesh"))
        out.write("** gmsh export cleaned by scripts/fix_gmsh_inp.py: C3D10 volume elements, node sets.\n")
        out.write("** Units: m. Nodes %d, elements %d.\n" % (len(kept), len(vol)))
        out.write("*NODE, NSET=NALL\n")
        for nid, text, _ in kept:
            out.write("%d, %s\n" % (nid, text))
        out.write("*ELEMENT, TYPE=C3D10, ELSET=%s\n" % elset)
        for k, r in enumerate(vol, 1):
            out.write("%d, %s\n" % (k, ", ".join(str(n) for n in r[1:])))
        for name, ids in out_sets:
            out.write("*NSET, NSET=%s\n" % name)
            write_ids(out, ids)
    os.replace(tmp, dst)

    if summary:
        with open(summary, "w") as out:
            out.write("nodes=%d\nelements=%d\n" % (len(kept), len(vol)))
            for name, ids in out_sets:
                out.write("set_%s=%d\n" % (name, len(ids)))
                if len(ids) == 1:
                    out.write("node_%s=%d\n" % (name, ids[0]))
    coords = {n[0]: n[2] for n in kept}
    print("%s: %d nodes, %d C3D10 elements (ELSET=%s); dropped %s" % (
        os.path.basename(dst), len(kept), len(vol), elset,
        ", ".join("%d %s" % (dropped[t], t) for t in sorted(dropped)) or "nothing"))
    for name, ids in out_sets:
        if len(ids) == 1:
            x, y, z = coords[ids[0]]
            print("  NSET %-14s node %d at (%.6g, %.6g, %.6g)" % (name, ids[0], x, y, z))
        else:
            print("  NSET %-14s %d nodes" % (name, len(ids)))
    return 0


def read_set_coords(path, set_name):
    nodes, _, _, nsets = read_gmsh_inp(path)
    set_name = set_name.upper()
    if set_name not in nsets:
        fail("%s: no node set %s" % (path, set_name))
    coords = {n[0]: n[2] for n in nodes}
    return [(n, coords[n]) for n in sorted(set(nsets[set_name]))]


def cmd_pairs(args):
    if len(args) < 4:
        fail("pairs needs A.inp SET_A B.inp SET_B", 2)
    a_path, a_set, b_path, b_set = args[:4]
    shift, tol = (0.0, 0.0, 0.0), 1e-9
    i = 4
    while i < len(args):
        if i + 1 >= len(args):
            fail("option %s needs a value" % args[i], 2)
        if args[i] == "--shift":
            shift = tuple(float(t) for t in args[i + 1].split(","))
            if len(shift) != 3:
                fail("--shift wants DX,DY,DZ", 2)
        elif args[i] == "--tol":
            tol = float(args[i + 1])
        else:
            fail("unknown option " + args[i], 2)
        i += 2
    a = read_set_coords(a_path, a_set)
    b = read_set_coords(b_path, b_set)
    matched, worst = 0, 0.0
    for _, (x, y, z) in a:
        best = min(max(abs(x - (bx + shift[0])), abs(y - (by + shift[1])), abs(z - (bz + shift[2])))
                   for _, (bx, by, bz) in b)
        worst = max(worst, best)
        if best <= tol:
            matched += 1
    ok = matched == len(a) == len(b)
    print("  %s %s (%d nodes) <-> %s %s (%d nodes, shift %s): %d coincide, max distance %.3g m%s" % (
        a_path.rsplit("/", 1)[-1], a_set.upper(), len(a), b_path.rsplit("/", 1)[-1], b_set.upper(), len(b),
        ",".join("%g" % s for s in shift), matched, worst, "" if ok else "  <-- NOT node-to-node"))
    return 0 if ok else 1


def cmd_mass(args):
    if len(args) != 1:
        fail("mass needs PREFIX", 2)
    prefix = args[0]
    try:
        with open(prefix + ".dof") as f:
            dirs = [int(line.strip().split(".")[1]) for line in f if line.strip()]
        total = [0.0, 0.0, 0.0]
        with open(prefix + ".mas") as f:
            for line in f:
                t = line.split()
                if not t:
                    continue
                i, j, v = int(t[0]) - 1, int(t[1]) - 1, float(t[2])
                if dirs[i] == dirs[j] and 1 <= dirs[i] <= 3:
                    total[dirs[i] - 1] += v if i == j else 2.0 * v
    except (OSError, ValueError, IndexError) as e:
        fail("%s.mas/.dof: %s" % (prefix, e))
    print("  translational mass (free DOFs): x %.6g kg, y %.6g kg, z %.6g kg" % tuple(total))
    return 0


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        sys.stdout.write(__doc__)
        return 0 if len(argv) >= 2 else 2
    if argv[1] == "clean":
        return cmd_clean(argv[2:])
    if argv[1] == "pairs":
        return cmd_pairs(argv[2:])
    if argv[1] == "mass":
        return cmd_mass(argv[2:])
    fail("unknown command %s (clean, pairs or mass)" % argv[1], 2)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
