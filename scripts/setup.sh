#!/usr/bin/env bash
# Installs every build/run dependency of fricrom from Debian's registry.
# Idempotent: re-running only checks that the packages are present.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git bc
  libeigen3-dev            # dense/sparse linear algebra (public headers)
  libsuitesparse-dev       # CHOLMOD (Craig-Bampton factorisation)
  libblas-dev              # dgemm for large dense products (blas.pc; OpenBLAS at run time)
  liblapack-dev            # dgetrf/dsygvd for large dense LU and eigenproblems (lapack.pc)
  libarpack2-dev           # arpack-ng (shift-invert modes)
  libfftw3-dev             # AFT transforms
  coinor-libipopt-dev      # bounds NLP
  libhdf5-dev              # result files
  libgtest-dev libgmock-dev googletest
  libbenchmark-dev
  libcli11-dev             # command line
  libtomlplusplus-dev      # case files
  libmuparser-dev          # parameter expressions in case files
  nlohmann-json3-dev       # --json output
  python3-matplotlib python3-numpy python3-h5py   # figures (system /usr/bin/python3)
  clang libclang-rt-14-dev # libFuzzer smoke run of the FE readers; the ASan + UBSan build
  calculix-ccx             # regenerates the CalculiX fixtures and meshes/ (with gmsh)
  gmsh                     # blade-sector and damper geometry + meshing (scripts/make_meshes.sh)
  libopenblas0-pthread     # optimised BLAS/LAPACK for CHOLMOD (5x faster factor than reference BLAS)
  python3-scipy            # benchmarks/reduce_vs_scipy.py, scripts/geometry_noa.py (Brent search)
  libopenmpi-dev openmpi-bin  # mpirun -np N fricrom sweep: values over MPI ranks
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  SUDO=sudo
else
  SUDO=
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "setup: done"
