#!/usr/bin/python3
"""Benchmark: fricrom's Craig-Bampton reduction (`fricrom reduce`) against the same reduction done
with SciPy (benchmarks/cb_scipy.py) on the same CalculiX-exported matrices.

Both sides run in their own process (peak RSS of each is its own, measured by the kernel through
wait4 and reported by the process itself); the model files are read once beforehand so that both
see a warm page cache. The fixed-interface frequencies of the two must agree (default 1e-8
relative); with python3-h5py the reduced matrices written by fricrom (OUT.h5) are compared too
(boundary DOF order, K_bb, M_bb, K_qq, M_bq up to the sign of each mode).

usage: benchmarks/reduce_vs_scipy.py --model PREFIX [--boundary SETS] [--modes 50]
           [--fricrom build/fricrom] [--out benchmarks/results/reduce_vs_scipy_<name>.json]
           [--repeat 1]
example:
  benchmarks/reduce_vs_scipy.py --model build/meshes/blade_sector_fine/blade_sector
"""
import argparse
import datetime
import json
import os
import platform
import shutil
import signal
import subprocess
import sys
import tempfile

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts"))
from atomic_write import write_text_atomically  # noqa: E402
import time

PROG = "reduce_vs_scipy.py"
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import cb_scipy  # noqa: E402  (exits with the Debian package name when numpy/scipy are missing)
import numpy as np  # noqa: E402
import scipy  # noqa: E402

BLADE_SETS = "CONTACT_LEFT,CONTACT_RIGHT,EXCITATION,RESPONSE"
PHASES = ("factor_s", "constraint_modes_s", "eigen_s", "assembly_s")


def die(msg, code=2):
    sys.stderr.write(f"{PROG}: error: {msg}\n")
    sys.exit(code)


def note(msg):
    sys.stderr.write(f"{PROG}: {msg}\n")
    sys.stderr.flush()


# ----------------------------------------------------------------------------------------------
# Processes
# ----------------------------------------------------------------------------------------------

def busy_cpu_seconds():
    """CPU time spent by the whole machine so far (all CPUs, /proc/stat), or None."""
    try:
        with open("/proc/stat") as f:
            v = [int(x) for x in f.readline().split()[1:]]
        return (sum(v[:8]) - v[3] - v[4]) / os.sysconf("SC_CLK_TCK")  # minus idle, iowait
    except (OSError, ValueError, IndexError):
        return None


def run_measured(cmd, env=None):
    """Run cmd; return (returncode, stdout, stderr, measures) where measures holds the wall time,
    the child's peak RSS and CPU time (kernel, wait4) and the CPU time other processes used
    meanwhile (machine busy time from /proc/stat minus the child's)."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        busy0 = busy_cpu_seconds()
        t0 = time.perf_counter()
        p = subprocess.Popen(cmd, stdout=out, stderr=err, env=env)
        _, status, usage = os.wait4(p.pid, 0)
        wall = time.perf_counter() - t0
        busy1 = busy_cpu_seconds()
        p.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        cpu = usage.ru_utime + usage.ru_stime
        measures = {"process_wall_s": wall, "process_peak_rss_mb": usage.ru_maxrss / 1024.0,
                    "process_user_s": usage.ru_utime, "process_sys_s": usage.ru_stime,
                    "other_processes_cpu_s": None if busy0 is None or busy1 is None
                    else max(0.0, busy1 - busy0 - cpu)}
        return (p.returncode, out.read().decode(errors="replace"), err.read().decode(errors="replace"),
                measures)


def last_json_line(text):
    for line in reversed(text.strip().splitlines()):
        line = line.strip()
        if line.startswith("{"):
            return json.loads(line)
    raise ValueError("no JSON object in the output")


def _exit_text(rc):
    if rc < 0:
        try:
            return f"killed by signal {signal.Signals(-rc).name}"
        except ValueError:
            return f"killed by signal {-rc}"
    return f"exit {rc}"


def run_fricrom(fricrom, inp, sets, modes, h5, env, shown):
    """shown: the executable's name in messages (fricrom may be a private copy of it)."""
    args = ["reduce", inp, "--boundary", sets, "--modes", str(modes), "--to", h5,
            "--json", "--quiet", "--no-reference"]
    rc, out, err, measures = run_measured([fricrom] + args, env)
    line = " ".join([shown] + args)
    try:
        res = last_json_line(out)
    except ValueError:
        die(f"fricrom failed ({_exit_text(rc)}): {line}\n{err.strip()}{out.strip()}", 3)
    if rc != 0 or res.get("status") != "SUCCESS":
        die(f"fricrom reduce: {_exit_text(rc)}, status {res.get('status')}: {res.get('message')}\n"
            f"  {line}\n{err.strip()}", 3)
    res.update(measures)
    return res


def run_scipy(prefix, sets, modes, npz, ordering, eigen_tol, env):
    cmd = [sys.executable, os.path.join(HERE, "cb_scipy.py"), prefix, "--boundary", sets,
           "--modes", str(modes), "--save-npz", npz, "--ordering", ordering,
           "--eigen-tol", repr(eigen_tol), "--json"]
    rc, out, err, measures = run_measured(cmd, env)
    try:
        res = last_json_line(out)
    except ValueError:
        die(f"SciPy reduction failed ({_exit_text(rc)}): {' '.join(cmd)}\n{err.strip()}", 3)
    if rc != 0 or res.get("status") != "SUCCESS":
        die(f"SciPy reduction: exit {rc}: {res.get('message')}\n{err.strip()}", 3)
    res.update(measures)
    return res


# ----------------------------------------------------------------------------------------------
# Machine information
# ----------------------------------------------------------------------------------------------

def _read(path):
    try:
        with open(path) as f:
            return f.read()
    except OSError:
        return ""


def _cmd(cmd, cwd=None):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=30, cwd=cwd).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


def _loaded_libs(pattern_words):
    """Shared libraries of this process matching any word (e.g. the BLAS numpy loaded)."""
    libs = set()
    for line in _read("/proc/self/maps").splitlines():
        path = line.split()[-1] if line.split() else ""
        base = os.path.basename(path)
        if path.startswith("/") and base.startswith("lib") and any(w in base for w in pattern_words):
            libs.add(os.path.realpath(path))
    return sorted(libs)


def _sha256(path):
    import hashlib
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def machine_info(fricrom, fricrom_origin):
    """fricrom: the executable that is run (a copy of fricrom_origin, the build tree's)."""
    cpuinfo = _read("/proc/cpuinfo")
    model = next((l.split(":", 1)[1].strip() for l in cpuinfo.splitlines()
                  if l.startswith("model name")), platform.processor() or "unknown")
    physical = {(l.split(":")[1].strip()) for l in cpuinfo.splitlines() if l.startswith("core id")}
    mem_kb = next((int(l.split()[1]) for l in _read("/proc/meminfo").splitlines()
                   if l.startswith("MemTotal:")), 0)
    os_name = next((l.split("=", 1)[1].strip().strip('"') for l in _read("/etc/os-release").splitlines()
                    if l.startswith("PRETTY_NAME=")), platform.system())
    fr_version = _cmd([fricrom, "--version"])
    build_dir = os.path.dirname(os.path.abspath(fricrom_origin))
    cache = _read(os.path.join(build_dir, "CMakeCache.txt"))
    build_type = next((l.split("=", 1)[1] for l in cache.splitlines()
                       if l.startswith("CMAKE_BUILD_TYPE:")), None)
    fr_libs = []
    for line in _cmd(["ldd", fricrom]).splitlines():
        if any(w in line for w in ("blas", "lapack", "cholmod", "arpack", "gomp")) and "=>" in line:
            lib = line.split("=>")[1].split("(")[0].strip()
            fr_libs.append(os.path.realpath(lib))
    return {
        "cpu_model": model,
        "logical_cpus": os.cpu_count(),
        "physical_cores": len(physical) or None,
        "ram_gib": round(mem_kb / 1024.0 ** 2, 2),
        "os": os_name,
        "kernel": platform.release(),
        "machine": platform.machine(),
        "python": sys.version.split()[0],
        "python_executable": sys.executable,
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "numpy_blas_libs": _loaded_libs(("blas", "lapack", "mkl")),
        "fricrom": os.path.abspath(fricrom_origin),
        "fricrom_version": fr_version or None,
        "fricrom_sha256": _sha256(fricrom),
        "fricrom_mtime": datetime.datetime.fromtimestamp(os.path.getmtime(fricrom_origin), datetime.timezone.utc)
        .isoformat(timespec="seconds"),
        "fricrom_build_type": build_type,
        "fricrom_libs": sorted(set(fr_libs)),
        "git_head": _cmd(["git", "rev-parse", "HEAD"], cwd=ROOT) or None,
        "thread_env": {k: os.environ[k] for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                                  "MKL_NUM_THREADS") if k in os.environ},
        "date_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }


# ----------------------------------------------------------------------------------------------
# Comparison
# ----------------------------------------------------------------------------------------------

def rel_max(a, b):
    """max |a - b| / max |b|."""
    scale = float(np.abs(b).max()) if b.size else 0.0
    return float(np.abs(a - b).max()) / scale if scale > 0 else float(np.abs(a - b).max(initial=0.0))


def compare_reduced(h5_path, npz_path, nb, sci):
    """Reduced matrices of fricrom (HDF5) against SciPy's (.npz). Needs h5py; None otherwise."""
    try:
        import h5py
    except ImportError:
        return {"skipped": "python3-h5py not installed (apt-get install python3-h5py)"}
    with h5py.File(h5_path, "r") as f:
        kf = f["reduced/stiffness"][()]
        mf = f["reduced/mass"][()]
        nodes_f = f["reduced/dof_node"][()][:nb]
        comps_f = f["reduced/dof_component"][()][:nb]
    z = np.load(npz_path)
    ks, ms = z["stiffness"], z["mass"]
    nodes_s, comps_s = z["dof_node"], z["dof_component"]
    out = {}
    same_order = bool(np.array_equal(nodes_f, nodes_s) and np.array_equal(comps_f, comps_s))
    out["boundary_order_identical"] = same_order
    if not same_order:
        diff = np.flatnonzero((nodes_f != nodes_s) | (comps_f != comps_s)) if nodes_f.size == nodes_s.size \
            else np.array([0])
        k = int(diff[0])
        out["first_boundary_order_difference"] = {
            "index": k, "fricrom": [int(nodes_f[k]), int(comps_f[k])] if k < nodes_f.size else None,
            "scipy": [int(nodes_s[k]), int(comps_s[k])] if k < nodes_s.size else None}
        out["boundary_same_dof_set"] = bool(
            set(zip(nodes_f.tolist(), comps_f.tolist())) == set(zip(nodes_s.tolist(), comps_s.tolist())))
    if kf.shape != ks.shape:
        out["shape_mismatch"] = [list(kf.shape), list(ks.shape)]
        return out
    b, q = slice(0, nb), slice(nb, None)
    out["K_bb_rel_diff"] = rel_max(kf[b, b], ks[b, b])
    out["M_bb_rel_diff"] = rel_max(mf[b, b], ms[b, b])
    out["K_qq_rel_diff"] = rel_max(kf[q, q], ks[q, q])
    out["M_qq_rel_diff"] = rel_max(mf[q, q], ms[q, q])
    # Mode shapes are defined up to their sign (and, for repeated frequencies, up to a rotation in
    # their eigenspace): align SciPy's columns of M_bq on fricrom's, for simple modes only.
    mbq_f, mbq_s = mf[b, q], ms[b, q]
    if mbq_f.size:
        lam = np.diag(kf)[nb:]
        gap = np.full(lam.size, np.inf)
        if lam.size > 1:
            d = np.abs(np.diff(lam)) / np.abs(lam).max()
            gap[:-1] = np.minimum(gap[:-1], d)
            gap[1:] = np.minimum(gap[1:], d)
        simple = gap > 1e-6
        out["repeated_frequency_modes"] = int(np.count_nonzero(~simple))
        if simple.any():
            sign = np.sign(np.einsum("ij,ij->j", mbq_f[:, simple], mbq_s[:, simple]))
            sign[sign == 0] = 1.0
            out["M_bq_rel_diff_up_to_mode_signs"] = rel_max(mbq_f[:, simple], mbq_s[:, simple] * sign)
        # sign- and basis-invariant form: M_bq M_qb
        out["M_bq_M_qb_rel_diff"] = rel_max(mbq_f @ mbq_f.T, mbq_s @ mbq_s.T)
    out["max_rel_diff"] = max(v for k, v in out.items() if k.endswith("rel_diff") or
                              k.endswith("up_to_mode_signs"))
    return out


def best(runs, key_path):
    vals = []
    for r in runs:
        v = r
        for k in key_path:
            v = v.get(k) if isinstance(v, dict) else None
        if v is not None:
            vals.append(v)
    return min(vals) if vals else None


def summarise(fr_runs, sp_runs):
    """Best (minimum) of each figure over the repetitions."""
    f = {"reduction_s": best(fr_runs, ("timings", "reduction_s")),
         "wall_s": best(fr_runs, ("wall_s",)),
         "process_wall_s": best(fr_runs, ("process_wall_s",)),
         "process_cpu_s": min(r["process_user_s"] + r["process_sys_s"] for r in fr_runs),
         "peak_rss_mb": best(fr_runs, ("peak_rss_mb",)),
         "process_peak_rss_mb": best(fr_runs, ("process_peak_rss_mb",))}
    for p in PHASES:
        f[p] = best(fr_runs, ("timings", p))
    # fricrom's wall_s = reading + reduction + checks of the boundary sets + HDF5 writing.
    f["read_and_write_s"] = min(r["wall_s"] - r["timings"]["reduction_s"] for r in fr_runs)
    f["reduction_other_s"] = min(r["timings"]["reduction_s"] - sum(r["timings"][p] for p in PHASES)
                                 for r in fr_runs)
    s = {k: best(sp_runs, ("timings", k)) for k in
         ("read_s", "partition_s", "reduction_s", "write_s", "total_s", "read_dof_s", "parse_sti_s",
          "parse_mas_s", "build_sti_csc_s", "build_mas_csc_s", "read_sets_s") + PHASES}
    s["reduction_other_s"] = min(r["timings"]["reduction_s"] - sum(r["timings"][p] for p in PHASES)
                                 for r in sp_runs)
    s["process_wall_s"] = best(sp_runs, ("process_wall_s",))
    s["process_cpu_s"] = min(r["process_user_s"] + r["process_sys_s"] for r in sp_runs)
    s["peak_rss_mb"] = best(sp_runs, ("peak_rss_mb",))
    s["process_peak_rss_mb"] = best(sp_runs, ("process_peak_rss_mb",))
    ratio = {
        "reduction": s["reduction_s"] / f["reduction_s"],
        "total_incl_reading": s["total_s"] / f["wall_s"],
        "process_wall": s["process_wall_s"] / f["process_wall_s"],
        "process_cpu": s["process_cpu_s"] / f["process_cpu_s"] if f["process_cpu_s"] else None,
        "peak_rss": s["process_peak_rss_mb"] / f["process_peak_rss_mb"],
    }
    for p in PHASES:
        ratio[p.replace("_s", "")] = s[p] / f[p] if f[p] else None
    return f, s, ratio


def default_name(prefix):
    base = os.path.basename(prefix)
    parent = os.path.basename(os.path.dirname(os.path.abspath(prefix)))
    grand = os.path.basename(os.path.dirname(os.path.dirname(os.path.abspath(prefix))))
    if parent.startswith(base):
        return parent                   # build/meshes/blade_sector_fine/blade_sector
    if grand == base:
        return f"{base}_{parent}"       # meshes/blade_sector/coarse/blade_sector
    return base


def write_json_atomic(path, obj):
    write_text_atomically(path, json.dumps(obj, indent=2) + "\n")


def warm_page_cache(paths):
    for p in paths:
        with open(p, "rb") as f:
            while f.read(1 << 24):
                pass


# ----------------------------------------------------------------------------------------------

def fmt_t(v):
    return f"{'-':>9s}" if v is None else f"{v:9.3f}"


def print_table(r):
    f, s, ratio = r["fricrom"]["summary"], r["scipy"]["summary"], r["ratio_scipy_over_fricrom"]
    m = r["model"]
    print(f"\nCraig-Bampton reduction: fricrom vs SciPy -- {m['prefix']}")
    print(f"  DOFs {m['full_dofs']}, boundary DOFs {m['boundary_dofs']} ({m['boundary_nodes']} nodes: "
          f"{m['boundary_sets']}), interior {m['interior_dofs']}, modes {m['modes']}, "
          f"repeat {r['repeat']} (best of)")
    print(f"  factor: fricrom CHOLMOD supernodal Cholesky | SciPy {r['scipy']['runs'][0]['info']['factor']['library']}"
          f" ({r['scipy']['runs'][0]['info']['factor']['ordering']})")
    print(f"\n  {'phase [s]':40s} {'fricrom':>9s} {'SciPy':>9s} {'SciPy/fricrom':>14s}")
    rows = [("read input files (fricrom: + write) *", f["read_and_write_s"], s["read_s"], None),
            ("write output (.npz / .h5)", None, s["write_s"], None),
            ("partition, symmetry checks, other", f["reduction_other_s"], s["reduction_other_s"], None),
            ("factor K_ii", f["factor_s"], s["factor_s"], ratio["factor"]),
            ("constraint modes Psi", f["constraint_modes_s"], s["constraint_modes_s"], ratio["constraint_modes"]),
            ("fixed-interface modes (eigen)", f["eigen_s"], s["eigen_s"], ratio["eigen"]),
            ("assembly T^T K T, T^T M T, checks", f["assembly_s"], s["assembly_s"], ratio["assembly"]),
            ("REDUCTION total (excl. reading)", f["reduction_s"], s["reduction_s"], ratio["reduction"]),
            ("TOTAL incl. reading and writing", f["wall_s"], s["total_s"], ratio["total_incl_reading"]),
            ("process wall (incl. start-up)", f["process_wall_s"], s["process_wall_s"], ratio["process_wall"]),
            ("process CPU time (user + sys)", f["process_cpu_s"], s["process_cpu_s"], ratio["process_cpu"])]
    for name, a, b, q in rows:
        print(f"  {name:40s} {fmt_t(a)} {fmt_t(b)} {'' if q is None else f'{q:14.2f}'}")
    print(f"  {'peak RSS [MB] (kernel wait4 / self)':40s} {f['process_peak_rss_mb']:9.0f} {s['process_peak_rss_mb']:9.0f} "
          f"{ratio['peak_rss']:14.2f}")
    print(f"  {'':40s} {f['peak_rss_mb']:9.0f} {s['peak_rss_mb']:9.0f}")
    print("  * fricrom reports no separate reading time: wall_s - reduction_s (reading, boundary "
          "selection, HDF5 output)")
    c = r["cross_check"]
    print(f"\n  fixed-interface frequencies {c['f_min_hz']:.6g} .. {c['f_max_hz']:.6g} Hz: "
          f"max rel. difference SciPy vs fricrom = {c['max_rel_freq_diff']:.3e} (mode {c['worst_mode']}), "
          f"tolerance {c['tolerance']:.0e} -> {'OK' if c['frequencies_agree'] else 'MISMATCH'}")
    red = c.get("reduced_matrices")
    if red and "skipped" not in red:
        extra = ", ".join(f"{k} {v:.2e}" for k, v in red.items() if isinstance(v, float))
        print(f"  reduced matrices: boundary order {'identical' if red['boundary_order_identical'] else 'DIFFERENT'}; "
              f"{extra}" + (f" ({red['repeated_frequency_modes']} modes of repeated frequencies left out of "
                            "the sign-aligned M_bq)" if red.get("repeated_frequency_modes") else ""))
    elif red:
        print(f"  reduced matrices: not compared ({red['skipped']})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--model", required=True, help="CalculiX job prefix: PREFIX.sti/.mas/.dof/.inp")
    ap.add_argument("--boundary", default=BLADE_SETS, help=f"boundary node sets (default {BLADE_SETS})")
    ap.add_argument("--modes", type=int, default=50, help="fixed-interface modes (default 50)")
    ap.add_argument("--fricrom", default=os.path.join(ROOT, "build", "fricrom"),
                    help="fricrom executable (default build/fricrom)")
    ap.add_argument("--out", help="result JSON (default benchmarks/results/reduce_vs_scipy_<name>.json)")
    ap.add_argument("--repeat", type=int, default=1, help="runs of each side; the best is reported")
    ap.add_argument("--ordering", default="symmetric",
                    help="SuperLU ordering for SciPy's K_ii factor (default symmetric: MMD on A^T+A, "
                         "symmetric mode; or COLAMD, MMD_ATA, NATURAL)")
    ap.add_argument("--eigen-tol", type=float, default=0.0,
                    help="ARPACK tolerance on the SciPy side (default 0: machine precision; fricrom "
                         "uses its CraigBamptonOptions::eigen_tolerance, not settable from the CLI)")
    ap.add_argument("--threads", type=int,
                    help="set OMP_NUM_THREADS, OPENBLAS_NUM_THREADS, MKL_NUM_THREADS for both sides "
                         "(default: inherit the environment)")
    ap.add_argument("--tolerance", type=float, default=1e-8,
                    help="max relative frequency difference accepted (default 1e-8)")
    a = ap.parse_args()
    if a.modes < 1 or a.repeat < 1:
        ap.error("--modes and --repeat must be >= 1")

    prefix = a.model[:-4] if a.model.endswith(".inp") else a.model
    files = cb_scipy.model_files(prefix)
    missing = [files[e] for e in ("sti", "mas", "dof", "inp") if not os.path.isfile(files[e])]
    if missing:
        die("model files missing: " + ", ".join(missing) + "\n  The blade-sector models are made by "
            "scripts/make_meshes.sh (gmsh + CalculiX): `bash scripts/make_meshes.sh fine` writes "
            "build/meshes/blade_sector_fine/blade_sector.*, `bash scripts/make_meshes.sh coarse` "
            "meshes/blade_sector/coarse/blade_sector.*")
    fricrom = a.fricrom
    if not (os.path.isfile(fricrom) and os.access(fricrom, os.X_OK)):
        die(f"fricrom executable not found: {fricrom}\n  build it: cd build && make -j2 fricrom_cli "
            "(or give --fricrom PATH)")
    fricrom = os.path.abspath(fricrom)
    out_path = a.out or os.path.join(HERE, "results", f"reduce_vs_scipy_{default_name(prefix)}.json")
    sets = ",".join(s.strip() for s in a.boundary.split(",") if s.strip())

    env = dict(os.environ)
    if a.threads is not None:
        if a.threads < 1:
            ap.error("--threads must be >= 1")
        for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
            env[k] = str(a.threads)

    warm_page_cache([files[e] for e in ("sti", "mas", "dof", "inp")])
    load_before = _read("/proc/loadavg").split()[:3]
    tmp = tempfile.mkdtemp(prefix="reduce_vs_scipy.")
    # Run a private copy of the executable: a concurrent rebuild of build/fricrom must not swap the
    # binary between (or during) the runs. Its hash goes into the result.
    fricrom_copy = os.path.join(tmp, "fricrom")
    shutil.copy2(fricrom, fricrom_copy)
    fricrom_info = machine_info(fricrom_copy, fricrom)
    try:
        fr_runs, sp_runs = [], []
        for k in range(a.repeat):
            note(f"run {k + 1}/{a.repeat}: fricrom reduce ...")
            fr_runs.append(run_fricrom(fricrom_copy, files["inp"], sets, a.modes, os.path.join(tmp, "fricrom.h5"), env,
                                       fricrom))
            note(f"run {k + 1}/{a.repeat}: fricrom {fr_runs[-1]['wall_s']:.2f} s; SciPy ...")
            sp_runs.append(run_scipy(prefix, sets, a.modes, os.path.join(tmp, "scipy.npz"), a.ordering,
                                     a.eigen_tol, env))
            note(f"run {k + 1}/{a.repeat}: SciPy {sp_runs[-1]['timings']['total_s']:.2f} s")
        load_after = _read("/proc/loadavg").split()[:3]
        fr, sc = fr_runs[-1], sp_runs[-1]
        for key in ("full_dofs", "boundary_dofs", "modes"):
            if fr[key] != sc[key]:
                die(f"fricrom and SciPy disagree on {key}: {fr[key]} vs {sc[key]}", 4)
        ff = np.asarray(fr["fixed_interface_hz"])
        fs = np.asarray(sc["fixed_interface_hz"])
        rel = np.abs(fs - ff) / np.abs(ff)
        worst = int(np.argmax(rel))
        cross = {"max_rel_freq_diff": float(rel.max()), "worst_mode": worst + 1,
                 "f_min_hz": float(ff.min()), "f_max_hz": float(ff.max()),
                 "tolerance": a.tolerance, "frequencies_agree": bool(rel.max() <= a.tolerance),
                 "rel_freq_diff": rel.tolist(),
                 "fricrom_hz": ff.tolist(), "scipy_hz": fs.tolist(),
                 "reduced_matrices": compare_reduced(os.path.join(tmp, "fricrom.h5"),
                                                     os.path.join(tmp, "scipy.npz"), fr["boundary_dofs"], sc)}
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    fsum, ssum, ratio = summarise(fr_runs, sp_runs)
    # Other processes on the machine distort the timings (2 cores: a second job halves them or worse).
    busy = []
    for side, runs in (("fricrom", fr_runs), ("SciPy", sp_runs)):
        for k, r in enumerate(runs):
            other = r.get("other_processes_cpu_s")
            if other is not None and other > max(0.25, 0.1 * r["process_wall_s"]):
                busy.append(f"{side} run {k + 1}: other processes used {other:.1f} CPU-s during its "
                            f"{r['process_wall_s']:.1f} s")
    for r in sp_runs:  # long per-DOF lists are not useful in the result file
        r.pop("boundary_dof_node", None)
        r.pop("boundary_dof_component", None)
    result = {
        "benchmark": "reduce_vs_scipy",
        "model": {"prefix": prefix, "files": files, "boundary_sets": sets, "full_dofs": fr["full_dofs"],
                  "boundary_dofs": fr["boundary_dofs"], "boundary_nodes": fr.get("boundary_nodes"),
                  "interior_dofs": sc["interior_dofs"], "modes": fr["modes"],
                  "stored_entries_full": sc["stored_entries"]},
        "repeat": a.repeat,
        "threads": a.threads,
        "load": {"loadavg_before": load_before, "loadavg_after": load_after,
                 "contention_warnings": busy},
        "notes": [
            "times in seconds; summaries are the best (minimum) over the repetitions",
            "fricrom wall_s: whole command (reading, boundary selection, reduction, HDF5 output); "
            "SciPy total_s: reading (+ full CSC, node sets), reduction, .npz output",
            "fricrom factors K_ii with CHOLMOD (supernodal Cholesky); SciPy has no sparse Cholesky, "
            "so SuperLU (scipy.sparse.linalg.splu) is used, reused by eigsh through OPinv",
            "eigen: ARPACK shift-invert sigma=0 on both sides, ncv = max(2k+1, 20); SciPy tol = "
            f"{a.eigen_tol!r} (0: machine precision), fricrom: its built-in eigen_tolerance",
            "fricrom ran from a private copy of the executable (see machine.fricrom_sha256)",
            "peak RSS: process_peak_rss_mb from wait4 (kernel, per child); peak_rss_mb self-reported",
            "both processes started with the model files in the page cache",
        ],
        "fricrom": {"summary": fsum, "runs": fr_runs},
        "scipy": {"summary": ssum, "runs": sp_runs},
        "ratio_scipy_over_fricrom": ratio,
        "cross_check": cross,
        "machine": fricrom_info,
    }
    print_table(result)
    for w in busy:
        print(f"  WARNING (machine busy, timings unreliable): {w}")
    write_json_atomic(out_path, result)
    print(f"\n  wrote {out_path}")
    red = cross.get("reduced_matrices") or {}
    if red.get("boundary_order_identical") is False:
        d = red.get("first_boundary_order_difference", {})
        sys.stderr.write(f"{PROG}: error: the boundary DOF order of fricrom's OUT.h5 differs from "
                         f"SciPy's (set by set, node by node, components ascending): first at "
                         f"index {d.get('index')}: fricrom (node, component) {d.get('fricrom')}, "
                         f"SciPy {d.get('scipy')}\n")
        return 6
    if not cross["frequencies_agree"]:
        sys.stderr.write(f"{PROG}: error: fixed-interface frequencies differ by {cross['max_rel_freq_diff']:.3e} "
                         f"(> {a.tolerance:.0e}) at mode {worst + 1}: fricrom {ff[worst]!r} Hz, SciPy "
                         f"{fs[worst]!r} Hz\n")
        return 5
    return 0


if __name__ == "__main__":
    sys.exit(main())
