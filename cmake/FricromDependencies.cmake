# Locates every third-party dependency; a missing one stops configure with the Debian package
# that provides it (scripts/setup.sh installs them all).
find_package(PkgConfig REQUIRED)

macro(fricrom_require found what package)
  if(NOT ${found})
    message(FATAL_ERROR "fricrom: ${what} not found. Install the Debian package '${package}' "
                        "(or run: sudo bash scripts/setup.sh).")
  endif()
endmacro()

find_package(Eigen3 3.4 QUIET NO_MODULE)
fricrom_require(Eigen3_FOUND "Eigen3 (>= 3.4)" libeigen3-dev)

pkg_check_modules(FFTW3 QUIET IMPORTED_TARGET fftw3)
fricrom_require(FFTW3_FOUND "FFTW3" libfftw3-dev)

pkg_check_modules(IPOPT QUIET IMPORTED_TARGET ipopt)
fricrom_require(IPOPT_FOUND "Ipopt" coinor-libipopt-dev)

pkg_check_modules(ARPACK QUIET IMPORTED_TARGET arpack)
fricrom_require(ARPACK_FOUND "arpack-ng" libarpack2-dev)

# SuiteSparse 5.x on Debian 12 ships neither a CMake config nor a pkg-config file for CHOLMOD.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig)
if(CHOLMOD_INCLUDE_DIR AND CHOLMOD_LIBRARY AND SUITESPARSECONFIG_LIBRARY)
  set(CHOLMOD_FOUND TRUE)
endif()
fricrom_require(CHOLMOD_FOUND "SuiteSparse CHOLMOD" libsuitesparse-dev)
add_library(fricrom_cholmod INTERFACE)
target_include_directories(fricrom_cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(fricrom_cholmod INTERFACE ${CHOLMOD_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})

set(HDF5_PREFER_PARALLEL FALSE)
find_package(HDF5 QUIET COMPONENTS C)
fricrom_require(HDF5_FOUND "HDF5 (C library)" libhdf5-dev)

find_package(tomlplusplus QUIET)
fricrom_require(tomlplusplus_FOUND "toml++" libtomlplusplus-dev)

find_package(muparser QUIET)
fricrom_require(muparser_FOUND "muParser" libmuparser-dev)

find_package(CLI11 QUIET)
fricrom_require(CLI11_FOUND "CLI11" libcli11-dev)

find_package(nlohmann_json 3 QUIET)
fricrom_require(nlohmann_json_FOUND "nlohmann-json" nlohmann-json3-dev)

# Units of work over ranks under mpirun (src/app/mpi_units.cpp); the library itself has no MPI.
find_package(MPI QUIET COMPONENTS C)
fricrom_require(MPI_C_FOUND "MPI (OpenMPI)" libopenmpi-dev)

if(FRICROM_BUILD_TESTS)
  find_package(GTest QUIET)
  fricrom_require(GTest_FOUND "GoogleTest" libgtest-dev)
endif()
if(FRICROM_BUILD_BENCHMARKS)
  find_package(benchmark QUIET)
  fricrom_require(benchmark_FOUND "Google Benchmark" libbenchmark-dev)
endif()

set(FRICROM_WARNINGS -Wall -Wextra -Wpedantic)
if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  # In a unity build each .cpp is #included, so GCC takes its anonymous-namespace types for a
  # header's and warns where a class of the file uses them; that is only a warning about headers.
  list(APPEND FRICROM_WARNINGS -Wno-subobject-linkage)
endif()
find_package(Threads REQUIRED)  # reading large FE files on two threads
# dgemm, dgetrf, dsygvd for large dense work (src/linear/dense_lapack.cpp); OpenBLAS at run time
pkg_check_modules(BLAS QUIET IMPORTED_TARGET blas)
fricrom_require(BLAS_FOUND "BLAS (blas.pc)" libblas-dev)
pkg_check_modules(LAPACK QUIET IMPORTED_TARGET lapack)
fricrom_require(LAPACK_FOUND "LAPACK (lapack.pc)" liblapack-dev)
