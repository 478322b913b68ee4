// Private to src/reduction: the fixed-interface modes of a Craig-Bampton reduction, lowest first,
// by count or up to a cutoff (ARPACK shift-invert, Sylvester count at the cutoff, dense fallback).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <string>

#include "cholmod_factor.h"
#include "fricrom/reduction.h"

namespace fricrom::reduction_detail {

// Interior size up to which a request for a large share of the spectrum (or one ARPACK cannot
// deliver) is finished by the dense generalized eigensolver (a few minutes at this size).
inline constexpr int kDenseFallbackMax = 6000;

struct InteriorModes {
  // kSuccess, kFactorizationFailed or kEigenNotConverged; message says why (or notes a fallback).
  CraigBamptonStatus status = CraigBamptonStatus::kSuccess;
  std::string message;
  Eigen::VectorXd lambda;  // kept modes, ascending, all finite
  Eigen::MatrixXd phi;     // their vectors (M-orthonormal up to rounding)
  bool dense = false;
  int batches = 0;              // ARPACK runs
  int restarts = 0;             // ARPACK iterations, summed
  int applications = 0;         // shift-invert solves, summed
  int count_below_cutoff = -1;  // Sylvester count at the cutoff (-1: not needed)
  double factor_s = 0.0;        // factorisations made here (shifted factor, LDL^T count)
};

// Modes of K_ii phi = lambda M_ii phi (M_ii positive semi-definite: infinite eigenvalues are never
// returned). kfac: a factor of K_ii, used when options.shift == 0 (may be unused otherwise).
InteriorModes ComputeInteriorModes(const Eigen::SparseMatrix<double>& kii,
                                   const Eigen::SparseMatrix<double>& mii, CholmodFactor* kfac,
                                   const CraigBamptonOptions& options);

}  // namespace fricrom::reduction_detail
