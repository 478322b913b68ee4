#!/usr/bin/env python3
"""Writes a CalculiX deck: a cantilever beam of C3D20R bricks, clamped at z = 0, node set TIP at
z = L, *FREQUENCY SOLVER=MATRIXSTORAGE (ccx writes JOB.sti, JOB.mas, JOB.dof).
Usage: gen_beam.py NX NY NZ LX LY LZ > job.inp   (SI: m; steel E = 210 GPa, nu = 0.3, 7800 kg/m^3)"""
import sys

nx, ny, nz = (int(v) for v in sys.argv[1:4])
lx, ly, lz = (float(v) for v in sys.argv[4:7])
gx, gy, gz = 2 * nx + 1, 2 * ny + 1, 2 * nz + 1
ids = {}
lines = ["** C3D20R cantilever beam %dx%dx%d elements, %g x %g x %g m (tests/data/c3d20r_beam/gen_beam.py)"
         % (nx, ny, nz, lx, ly, lz), "*NODE, NSET=NALL"]
for k in range(gz):
    for j in range(gy):
        for i in range(gx):
            if (i % 2) + (j % 2) + (k % 2) > 1:
                continue  # face and body centres are not C3D20 nodes
            ids[(i, j, k)] = len(ids) + 1
            lines.append("%d, %.10g, %.10g, %.10g" % (ids[(i, j, k)], lx * i / (gx - 1),
                                                       ly * j / (gy - 1), lz * k / (gz - 1)))
corner = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2)]
mid = [(1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0), (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),
       (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1)]
lines.append("*ELEMENT, TYPE=C3D20R, ELSET=EALL")
e = 0
for ek in range(nz):
    for ej in range(ny):
        for ei in range(nx):
            e += 1
            n = [ids[(2 * ei + a, 2 * ej + b, 2 * ek + c)] for a, b, c in corner + mid]
            lines.append("%d, " % e + ", ".join(str(v) for v in n[:15]) + ",")
            lines.append(", ".join(str(v) for v in n[15:]))
def nset(name, kk):
    nodes = [v for (i, j, k), v in ids.items() if k == kk]
    lines.append("*NSET, NSET=%s" % name)
    for s in range(0, len(nodes), 10):
        lines.append(", ".join(str(v) for v in nodes[s:s + 10]) + ",")
nset("ROOT", 0)
nset("TIP", gz - 1)
lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", "2.1E11, 0.3", "*DENSITY", "7800.",
          "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL", "*BOUNDARY", "ROOT, 1, 3", "*STEP",
          "*FREQUENCY, SOLVER=MATRIXSTORAGE", "*END STEP"]
print("\n".join(lines))
