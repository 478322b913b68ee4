#!/usr/bin/python3
"""Craig-Bampton reduction of a CalculiX job with NumPy/SciPy: the reference implementation that
benchmarks/reduce_vs_scipy.py times against `fricrom reduce`.

Same algorithm as src/reduction/craig_bampton.cpp:
  * K, M: full symmetric CSC from prefix.sti / prefix.mas (1-based `row col value`, upper triangle),
    DOF map from prefix.dof (`node.direction`), node sets from prefix.inp (*NSET, *NODE NSET=,
    GENERATE, set names inside *NSET, *INCLUDE relative to the including file).
  * boundary DOFs: set by set, node by node in the set's order, components ascending, a node named
    by several sets taken once (fricrom's SelectBoundaryDofs); interior: the rest, ascending.
  * K_ii factorised once. SciPy has no sparse Cholesky, so this is SuperLU (scipy.sparse.linalg.splu)
    in its symmetric mode (MMD on A^T + A, diagonal pivoting) -- fricrom uses CHOLMOD (supernodal
    Cholesky).
  * constraint modes Psi = -K_ii^-1 K_ib (one multi-RHS solve with the factor),
  * fixed-interface modes: ARPACK shift-invert at sigma = 0 (scipy.sparse.linalg.eigsh, reusing
    the factor through OPinv; ncv = max(2k+1, 20) as fricrom; tol = 0, i.e. machine precision,
    unless --eigen-tol), or dense
    (scipy.linalg.eigh) when n_i <= 200 or k > n_i - 2 (fricrom's dense_eigen_max_size), then
    M-normalised column by column,
  * K_r = T^T K T, M_r = T^T M T with T = [[I, 0], [Psi, Phi]], and fricrom's structural checks.

Usage (normally run by reduce_vs_scipy.py in its own process, so that its peak RSS is its own):
  benchmarks/cb_scipy.py PREFIX --boundary SET1,SET2 --modes 50 [--save-npz OUT.npz] [--json]
"""
import argparse
import json
import math
import os
import resource
import sys
import time

PROG = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else "cb_scipy.py"


def _missing(module, package):
    sys.stderr.write(
        f"{PROG}: error: Python module '{module}' is not available to {sys.executable}.\n"
        f"  Install the Debian package and run the script with /usr/bin/python3:\n"
        f"    apt-get install {package}\n")
    sys.exit(2)


try:
    import numpy as np
except ImportError:
    _missing("numpy", "python3-numpy")
try:
    import scipy
    import scipy.linalg
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla
except ImportError:
    _missing("scipy", "python3-scipy")

DENSE_EIGEN_MAX_SIZE = 200  # fricrom CraigBamptonOptions::dense_eigen_max_size
TWO_PI = 2.0 * math.pi


class ModelError(Exception):
    """A problem with the input files (reported without a traceback)."""


# ----------------------------------------------------------------------------------------------
# Reading
# ----------------------------------------------------------------------------------------------

def model_files(prefix):
    """The four files of a CalculiX job prefix (prefix may end in .inp)."""
    if prefix.endswith(".inp"):
        prefix = prefix[:-4]
    return {ext: prefix + "." + ext for ext in ("sti", "mas", "dof", "inp")}


def read_dof(path):
    """prefix.dof: one `node.direction` per matrix row -> (nodes int64, components int64)."""
    with open(path, "rb") as f:
        tokens = f.read().split()
    if not tokens:
        raise ModelError(f"{path}: empty .dof file")
    nodes = np.empty(len(tokens), dtype=np.int64)
    comps = np.empty(len(tokens), dtype=np.int64)
    try:
        for k, tok in enumerate(tokens):
            node, dot, comp = tok.partition(b".")
            if not dot:
                raise ValueError
            nodes[k] = int(node)
            comps[k] = int(comp)
    except ValueError:
        raise ModelError(f"{path}: token {k + 1}: expected 'node.direction', got {tokens[k]!r}")
    if nodes.min() <= 0 or comps.min() < 0 or comps.max() > 6:
        raise ModelError(f"{path}: node numbers must be > 0 and directions 0..6")
    key = nodes * 8 + comps
    if np.unique(key).size != key.size:
        raise ModelError(f"{path}: a (node, direction) pair is listed twice")
    return nodes, comps


_TRIPLET = np.dtype([("r", np.int64), ("c", np.int64), ("v", np.float64)])


def read_triplets(path):
    """`row col value` lines -> (rows, cols, values), 0-based. numpy >= 1.23 has a C parser in
    loadtxt (measured ~1.9x faster than numpy.fromfile(sep=' ') here); older numpy: fromfile."""
    if tuple(int(x) for x in np.__version__.split(".")[:2]) >= (1, 23):
        data = np.loadtxt(path, dtype=_TRIPLET, ndmin=1)
        return data["r"] - 1, data["c"] - 1, data["v"]
    flat = np.fromfile(path, sep=" ")
    if flat.size % 3:
        raise ModelError(f"{path}: expected 'row col value' lines (value count not a multiple of 3)")
    flat = flat.reshape(-1, 3)
    return flat[:, 0].astype(np.int64) - 1, flat[:, 1].astype(np.int64) - 1, flat[:, 2].copy()


def symmetric_csc(path, rows, cols, vals, n):
    """Full symmetric CSC from one stored triangle (fricrom rejects duplicates and entries given in
    both triangles; so does this)."""
    if rows.size == 0:
        raise ModelError(f"{path}: no matrix entries")
    if rows.min() < 0 or cols.min() < 0 or rows.max() >= n or cols.max() >= n:
        raise ModelError(f"{path}: entry index out of range (the .dof file lists {n} DOFs)")
    lo = np.minimum(rows, cols)
    hi = np.maximum(rows, cols)
    key = np.sort(lo * n + hi)
    if key.size > 1 and np.any(key[1:] == key[:-1]):
        raise ModelError(f"{path}: duplicate entry or an entry stored in both triangles")
    off = lo != hi
    r = np.concatenate([lo, hi[off]])
    c = np.concatenate([hi, lo[off]])
    v = np.concatenate([vals, vals[off]])
    a = sp.csc_matrix((v, (r, c)), shape=(n, n))
    a.sum_duplicates()
    a.sort_indices()
    return a


def _keyword(line):
    """'*NSET, NSET=Left, GENERATE' -> ('NSET', {'NSET': 'Left', 'GENERATE': ''})."""
    parts = line[1:].split(",")
    name = parts[0].strip().upper()
    params = {}
    for item in parts[1:]:
        item = item.strip()
        if not item:
            continue
        k, eq, v = item.partition("=")
        params[k.strip().upper()] = v.strip() if eq else ""
    return name, params


def read_node_sets(path):
    """Node sets of an Abaqus/CalculiX deck, as fricrom's ReadInpNodesAndSets: upper-case names,
    members in order of first appearance, no repeats; *NODE, NSET=; *NSET with node ids or names
    of sets defined above; *NSET, GENERATE; *INCLUDE, INPUT= (relative to the including file)."""
    sets = {}            # name -> list of nodes
    members = {}         # name -> set of nodes
    defined_nodes = set()

    def add(name, node):
        if node not in members[name]:
            members[name].add(node)
            sets[name].append(node)

    def open_set(name, where):
        if not name:
            raise ModelError(f"{where}: expected a set name after NSET=")
        name = name.upper()
        if name not in sets:
            sets[name] = []
            members[name] = set()
        return name

    def read(p, depth):
        if depth > 16:
            raise ModelError(f"{p}: *INCLUDE nested deeper than 16 levels")
        try:
            with open(p, "r", encoding="latin-1") as f:
                lines = f.read().splitlines()
        except OSError as e:
            raise ModelError(f"{p}: cannot read the deck: {e.strerror}")
        block, current = None, None
        for number, raw in enumerate(lines, 1):
            t = raw.strip()
            if not t or t.startswith("**"):
                continue
            where = f"{p}:{number}"
            if t.startswith("*"):
                name, params = _keyword(t)
                block = None
                if name == "INCLUDE":
                    inc = params.get("INPUT", "")
                    if not inc:
                        raise ModelError(f"{where}: *INCLUDE without INPUT=<file>")
                    if not os.path.isabs(inc):
                        inc = os.path.join(os.path.dirname(p), inc)
                    read(inc, depth + 1)
                elif name == "NODE":
                    block = "node"
                    current = open_set(params["NSET"], where) if "NSET" in params else None
                elif name == "NSET":
                    if "NSET" not in params:
                        raise ModelError(f"{where}: *NSET without NSET=<name>")
                    current = open_set(params["NSET"], where)
                    block = "generate" if "GENERATE" in params else "nset"
                continue
            if block is None:
                continue
            toks = [x.strip() for x in t.split(",")]
            toks = [x for x in toks if x]
            try:
                if block == "node":
                    node = int(toks[0])
                    defined_nodes.add(node)
                    if current is not None:
                        add(current, node)
                elif block == "generate":
                    first, last = int(toks[0]), int(toks[1])
                    step = int(toks[2]) if len(toks) > 2 else 1
                    if first <= 0 or last < first or step <= 0:
                        raise ModelError(f"{where}: bad 'first, last[, step]' under *NSET, GENERATE")
                    for node in range(first, last + 1, step):
                        add(current, node)
                else:
                    for tok in toks:
                        try:
                            add(current, int(tok))
                        except ValueError:
                            ref = tok.upper()
                            if ref not in sets:
                                raise ModelError(f"{where}: '{tok}' is neither a node id nor a set "
                                                 "defined above")
                            for node in list(sets[ref]):
                                add(current, node)
            except (ValueError, IndexError):
                raise ModelError(f"{where}: cannot parse {t!r}")

    read(path, 0)
    for name, nodes in sets.items():
        missing = [n for n in nodes if n not in defined_nodes]
        if missing:
            raise ModelError(f"{path}: node set {name} lists node {missing[0]}, which no *NODE "
                             "block defines")
    return sets


def boundary_dofs(node_sets, set_names, dof_nodes, dof_comps, inp_path):
    """Row indices of the boundary DOFs in fricrom's order (SelectBoundaryDofs)."""
    order = np.lexsort((dof_comps, dof_nodes))  # by node, then component
    rows_of_node = {}
    sorted_nodes = dof_nodes[order]
    starts = np.flatnonzero(np.r_[True, sorted_nodes[1:] != sorted_nodes[:-1]])
    ends = np.r_[starts[1:], sorted_nodes.size]
    for s, e in zip(starts.tolist(), ends.tolist()):
        rows_of_node[int(sorted_nodes[s])] = order[s:e]
    out, nodes, taken = [], [], set()
    for name in set_names:
        key = name.upper()
        if key not in node_sets:
            known = ", ".join(node_sets) or "none"
            raise ModelError(f"unknown node set '{name}' in {inp_path} (sets in the deck: {known})")
        if not node_sets[key]:
            raise ModelError(f"node set {key} is empty")
        for node in node_sets[key]:
            if node in taken:
                continue
            taken.add(node)
            rows = rows_of_node.get(node)
            if rows is None:
                raise ModelError(f"node {node} of set {key} has no DOF in the matrices "
                                 "(constrained by *BOUNDARY?)")
            out.extend(rows.tolist())
            nodes.append(node)
    return np.asarray(out, dtype=np.int64), nodes


def read_model(prefix, set_names):
    """Everything the reduction needs, with the reading time of each part."""
    files = model_files(prefix)
    for ext in ("sti", "mas", "dof", "inp"):
        if not os.path.isfile(files[ext]):
            raise ModelError(f"missing {files[ext]}")
    t = {}
    t0 = time.perf_counter()
    dof_nodes, dof_comps = read_dof(files["dof"])
    n = dof_nodes.size
    t["read_dof_s"] = time.perf_counter() - t0
    mats = {}
    for ext in ("sti", "mas"):
        t0 = time.perf_counter()
        r, c, v = read_triplets(files[ext])
        t[f"parse_{ext}_s"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        mats[ext] = symmetric_csc(files[ext], r, c, v, n)
        del r, c, v
        t[f"build_{ext}_csc_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    node_sets = read_node_sets(files["inp"])
    b, b_nodes = boundary_dofs(node_sets, set_names, dof_nodes, dof_comps, files["inp"])
    t["read_sets_s"] = time.perf_counter() - t0
    t["read_s"] = sum(t.values())
    return {"K": mats["sti"], "M": mats["mas"], "dof_nodes": dof_nodes, "dof_comps": dof_comps,
            "boundary": b, "boundary_nodes": b_nodes, "timings": t,
            "stored_entries": {"K": int(mats["sti"].nnz), "M": int(mats["mas"].nnz)}}


# ----------------------------------------------------------------------------------------------
# Craig-Bampton
# ----------------------------------------------------------------------------------------------

def _max_abs(a):
    if sp.issparse(a):
        return float(abs(a).max()) if a.nnz else 0.0
    return float(np.abs(a).max()) if a.size else 0.0


def _add_sparse_into(dense, a):
    """dense += a (a sparse, no duplicate entries), in place, without a dense copy of a."""
    coo = a.tocoo()
    dense[coo.row, coo.col] += coo.data


def _lu_factor(a, ordering):
    if ordering == "symmetric":
        # SuperLU's symmetric mode: minimum degree on A^T + A, diagonal pivots preferred.
        return spla.splu(a, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                         options={"SymmetricMode": True})
    return spla.splu(a, permc_spec=ordering)


def craig_bampton(K, M, boundary, num_modes, ordering="symmetric",
                  dense_max=DENSE_EIGEN_MAX_SIZE, eigen_tol=0.0):
    n = K.shape[0]
    nb = int(boundary.size)
    t, info = {}, {}
    t_start = time.perf_counter()

    # ---- partition [boundary in the given order | interior ascending]
    t0 = time.perf_counter()
    is_b = np.zeros(n, dtype=bool)
    is_b[boundary] = True
    if np.count_nonzero(is_b) != nb:
        raise ModelError("duplicate boundary DOF")
    interior = np.flatnonzero(~is_b)
    ni = int(interior.size)
    blocks = {}
    for name, a in (("K", K), ("M", M)):
        cols_i = a[:, interior]            # CSC column slicing
        cols_b = a[:, boundary]
        ii = cols_i.tocsr()[interior].tocsc()
        ib = cols_b.tocsr()[interior].tocsc()
        bb = cols_b.tocsr()[boundary].toarray()
        ii.sort_indices()
        blocks[name] = (ii, ib, bb)
    Kii, Kib, Kbb = blocks["K"]
    Mii, Mib, Mbb = blocks["M"]
    t["partition_s"] = time.perf_counter() - t0
    if ni == 0:
        raise ModelError("the boundary sets hold every DOF: empty interior")

    # ---- factor K_ii once (SuperLU; SciPy has no sparse Cholesky)
    t0 = time.perf_counter()
    try:
        lu = _lu_factor(Kii, ordering)
    except RuntimeError as e:
        raise ModelError(f"K_ii could not be factorised ({e}): the boundary DOFs must suppress "
                         "every rigid-body motion of the interior")
    t["factor_s"] = time.perf_counter() - t0
    info["factor"] = {"library": "SuperLU (scipy.sparse.linalg.splu)", "ordering": ordering,
                      "factor_stored_entries": int(lu.nnz)}  # SuperLU L+U storage (lu.L, lu.U would copy it)

    # ---- constraint modes Psi = -K_ii^-1 K_ib
    t0 = time.perf_counter()
    if nb > 0:
        rhs = np.asfortranarray(Kib.toarray())
        Psi = lu.solve(rhs)
        del rhs
        np.negative(Psi, out=Psi)
    else:
        Psi = np.zeros((ni, 0))
    t["constraint_modes_s"] = time.perf_counter() - t0

    # ---- fixed-interface modes
    t0 = time.perf_counter()
    k = min(num_modes, ni)
    dense = ni <= dense_max or k > ni - 2
    if dense:
        lam, Phi = scipy.linalg.eigh(Kii.toarray(), Mii.toarray())
        lam, Phi = lam[:k], Phi[:, :k]
        info["eigen"] = {"method": "dense scipy.linalg.eigh"}
    else:
        applications = [0]

        def counted(x):
            applications[0] += 1
            return lu.solve(x)
        opinv = spla.LinearOperator((ni, ni), matvec=counted, dtype=np.float64)
        lam, Phi = spla.eigsh(Kii, k=k, M=Mii, sigma=0.0, which="LM", OPinv=opinv, tol=eigen_tol,
                              ncv=min(ni, max(2 * k + 1, 20)), maxiter=1000)
        order = np.argsort(lam)
        lam, Phi = lam[order], Phi[:, order]
        info["eigen"] = {"method": "ARPACK shift-invert (scipy.sparse.linalg.eigsh, sigma=0, "
                                   "OPinv = the K_ii factor)",
                         "ncv": min(ni, max(2 * k + 1, 20)), "tol": eigen_tol,
                         "operator_applications": applications[0]}
    # M-normalisation, column by column
    Phi = np.ascontiguousarray(Phi)
    mphi = Mii @ Phi
    Phi /= np.sqrt(np.einsum("ij,ij->j", Phi, mphi))
    del mphi
    t["eigen_s"] = time.perf_counter() - t0
    freqs = np.sqrt(np.maximum(lam, 0.0)) / TWO_PI

    # ---- reduced matrices T^T A T and the structural checks of fricrom
    t0 = time.perf_counter()

    def reduce(aii, aib, abb):
        aii_psi = aii @ Psi
        aii_phi = aii @ Phi
        x = aii_psi  # A_ib + A_ii Psi, in place
        _add_sparse_into(x, aib)
        q = Phi.shape[1]
        r = np.empty((nb + q, nb + q))
        r[:nb, :nb] = abb + (aib.T @ Psi) + Psi.T @ x
        r[:nb, nb:] = (aib.T @ Phi) + Psi.T @ aii_phi
        r[nb:, :nb] = Phi.T @ x
        r[nb:, nb:] = Phi.T @ aii_phi
        return r

    Kr = reduce(Kii, Kib, Kbb)
    Mr = reduce(Mii, Mib, Mbb)
    q = Phi.shape[1]
    checks = {}
    kmax, mmax = _max_abs(Kr), _max_abs(Mr)
    checks["stiffness_symmetry"] = _max_abs(Kr - Kr.T) / kmax if kmax > 0 else 0.0
    checks["mass_symmetry"] = _max_abs(Mr - Mr.T) / mmax if mmax > 0 else 0.0
    kbq = max(_max_abs(Kr[:nb, nb:]), _max_abs(Kr[nb:, :nb]))
    scale = _max_abs(K) * _max_abs(Phi) * (1.0 + _max_abs(Psi))
    checks["stiffness_coupling_Kbq"] = kbq / scale if scale > 0 else 0.0
    if q:
        checks["modal_mass_Mqq_minus_I"] = _max_abs(Mr[nb:, nb:] - np.eye(q))
        lscale = max(float(np.abs(lam).max()), 1e-300)
        checks["modal_stiffness_Kqq_minus_diag"] = _max_abs(Kr[nb:, nb:] - np.diag(lam)) / lscale
        kp, mp = Kii @ Phi, Mii @ Phi
        den = (_max_abs(Kii) + np.abs(lam) * _max_abs(Mii)) * np.linalg.norm(Phi, axis=0)
        res = np.linalg.norm(kp - mp * lam, axis=0) / den
        checks["eigen_residual"] = float(res.max())
        del kp, mp
    Kr = 0.5 * (Kr + Kr.T)
    Mr = 0.5 * (Mr + Mr.T)
    t["assembly_s"] = time.perf_counter() - t0
    t["reduction_s"] = time.perf_counter() - t_start
    return {"full_dofs": n, "boundary_dofs": nb, "interior_dofs": ni, "modes": q,
            "lambda": lam, "fixed_interface_hz": freqs, "Kr": Kr, "Mr": Mr,
            "timings": t, "info": info, "checks": checks}


def peak_rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: KB


def run(prefix, set_names, num_modes, save_npz=None, ordering="symmetric", eigen_tol=0.0):
    """Read + reduce (+ save): the SciPy counterpart of one `fricrom reduce` command."""
    t_start = time.perf_counter()
    model = read_model(prefix, set_names)
    res = craig_bampton(model["K"], model["M"], model["boundary"], num_modes, ordering=ordering,
                        eigen_tol=eigen_tol)
    t = dict(model["timings"])
    t.update(res["timings"])
    t0 = time.perf_counter()
    if save_npz:
        b = model["boundary"]
        tmp = save_npz + ".tmp.npz"
        np.savez(tmp, stiffness=res["Kr"], mass=res["Mr"], fixed_interface_hz=res["fixed_interface_hz"],
                 dof_node=model["dof_nodes"][b], dof_component=model["dof_comps"][b])
        os.replace(tmp, save_npz)
    t["write_s"] = time.perf_counter() - t0
    t["total_s"] = time.perf_counter() - t_start
    return {
        "status": "SUCCESS", "model": prefix, "boundary_sets": list(set_names),
        "full_dofs": res["full_dofs"], "boundary_dofs": res["boundary_dofs"],
        "boundary_nodes": len(model["boundary_nodes"]), "interior_dofs": res["interior_dofs"],
        "modes": res["modes"], "fixed_interface_hz": res["fixed_interface_hz"].tolist(),
        "boundary_dof_node": model["dof_nodes"][model["boundary"]].tolist(),
        "boundary_dof_component": model["dof_comps"][model["boundary"]].tolist(),
        "stored_entries": model["stored_entries"],
        "timings": t, "info": res["info"], "checks": res["checks"], "peak_rss_mb": peak_rss_mb(),
        "python": sys.version.split()[0], "numpy": np.__version__, "scipy": scipy.__version__,
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("model", help="CalculiX job prefix (prefix.sti/.mas/.dof/.inp) or prefix.inp")
    ap.add_argument("--boundary", required=True, help="boundary node sets SET1,SET2,...")
    ap.add_argument("--modes", type=int, default=50, help="fixed-interface modes (default 50)")
    ap.add_argument("--ordering", default="symmetric",
                    help="SuperLU column ordering: symmetric (MMD on A^T+A, symmetric mode; default), "
                         "COLAMD, MMD_AT_PLUS_A, MMD_ATA, NATURAL")
    ap.add_argument("--eigen-tol", type=float, default=0.0,
                    help="ARPACK relative tolerance of the Ritz values (default 0: machine precision)")
    ap.add_argument("--save-npz", help="write the reduced K, M (and boundary DOFs) to this .npz")
    ap.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    a = ap.parse_args(argv)
    if a.modes < 1:
        ap.error("--modes must be >= 1")
    sets = [s.strip() for s in a.boundary.split(",") if s.strip()]
    try:
        out = run(a.model, sets, a.modes, a.save_npz, a.ordering, a.eigen_tol)
    except ModelError as e:
        if a.json:
            print(json.dumps({"status": "ERROR", "message": str(e), "peak_rss_mb": peak_rss_mb()}))
        sys.stderr.write(f"{PROG}: error: {e}\n")
        return 1
    if a.json:
        print(json.dumps(out))
    else:
        t = out["timings"]
        print(f"{a.model}: {out['full_dofs']} DOFs -> {out['boundary_dofs']} boundary + "
              f"{out['modes']} modes; read {t['read_s']:.3f} s, reduction {t['reduction_s']:.3f} s "
              f"(factor {t['factor_s']:.3f}, psi {t['constraint_modes_s']:.3f}, eigen "
              f"{t['eigen_s']:.3f}, assembly {t['assembly_s']:.3f}), peak RSS "
              f"{out['peak_rss_mb']:.0f} MB")
        print("fixed-interface Hz:", " ".join(f"{f:.6g}" for f in out["fixed_interface_hz"]))
        print("checks:", json.dumps(out["checks"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
