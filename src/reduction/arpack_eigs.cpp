#include "arpack_eigs.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

// arpack-ng's ISO C binding (libarpack, 32-bit integers); declared here rather than through
// <arpack/arpack.h>, which also declares C99 _Complex routines that ISO C++ rejects.
extern "C" {
void dsaupd_c(int* ido, const char* bmat, int n, const char* which, int nev, double tol,
              double* resid, int ncv, double* v, int ldv, int* iparam, int* ipntr, double* workd,
              double* workl, int lworkl, int* info);
void dseupd_c(int rvec, const char* howmny, const int* select, double* d, double* z, int ldz,
              double sigma, const char* bmat, int n, const char* which, int nev, double tol,
              double* resid, int ncv, double* v, int ldv, int* iparam, int* ipntr, double* workd,
              double* workl, int lworkl, int* info);
}

namespace fricrom::reduction_detail {

EigsResult LowestEigs(CholeskyTransformOp& op, int nev, double tol, int max_iterations) {
  EigsResult out;
  const int n = op.rows();
  if (nev < 1 || nev > n - 2) {
    out.message = "ARPACK needs 1 <= nev <= n - 2";
    return out;
  }
  // ARPACK replaces tol <= 0 by machine precision only inside its first call; the value is passed
  // by value on every call, so later convergence tests would use 0 (about twice the solves).
  if (!(tol > 0)) tol = std::numeric_limits<double>::epsilon();
  const int ncv = std::min(n, std::max(2 * nev + 1, 20));
  const int lworkl = ncv * (ncv + 8);
  std::vector<double> resid(static_cast<size_t>(n)), v(static_cast<size_t>(n) * ncv),
      workd(3 * static_cast<size_t>(n)), workl(static_cast<size_t>(lworkl));
  std::mt19937 gen(12345u);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  for (double& r : resid) r = dist(gen);

  int iparam[11] = {0};
  int ipntr[14] = {0};
  iparam[0] = 1;  // exact shifts
  iparam[2] = max_iterations;
  iparam[6] = 1;  // standard problem C y = nu y
  int ido = 0;
  int info = 1;  // use resid as the start vector
  const char* bmat = "I";
  const char* which = "LM";
  while (true) {
    dsaupd_c(&ido, bmat, n, which, nev, tol, resid.data(), ncv, v.data(), n, iparam, ipntr,
             workd.data(), workl.data(), lworkl, &info);
    double* x = workd.data() + ipntr[0] - 1;  // ARPACK pointers are 1-based
    double* y = workd.data() + ipntr[1] - 1;
    if (ido == -1 || ido == 1) {
      op.perform_op(x, y);
    } else {
      break;
    }
  }
  out.restarts = iparam[2];
  if (info == 1) {
    out.message = "ARPACK dsaupd reached the maximum of " + std::to_string(max_iterations) +
                  " restarts with " + std::to_string(iparam[4]) + " of " + std::to_string(nev) +
                  " Ritz values converged";
    return out;
  }
  if (info != 0) {
    out.message = "ARPACK dsaupd failed with info = " + std::to_string(info);
    return out;
  }
  std::vector<int> select(static_cast<size_t>(ncv), 0);
  std::vector<double> d(static_cast<size_t>(nev)), z(static_cast<size_t>(n) * nev);
  int ierr = 0;
  dseupd_c(1, "A", select.data(), d.data(), z.data(), n, op.shift(), bmat, n, which, nev, tol,
           resid.data(), ncv, v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl,
           &ierr);
  if (ierr != 0) {
    out.message = "ARPACK dseupd failed with info = " + std::to_string(ierr);
    return out;
  }
  const int nconv = iparam[4];
  if (nconv < nev) {
    out.message =
        "ARPACK converged " + std::to_string(nconv) + " of " + std::to_string(nev) + " eigenpairs";
    return out;
  }
  // d holds nu (dseupd returns the operator's eigenvalues in mode 1): largest nu = lowest lambda.
  std::vector<int> order(static_cast<size_t>(nev));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return d[a] > d[b]; });
  const double nu_max = d[order[0]];
  int finite = 0;
  while (nu_max > 0 && finite < nev && d[order[finite]] > 1e-13 * nu_max) ++finite;
  out.infinite = nev - finite;
  Eigen::MatrixXd y(n, finite);
  out.lambda.resize(finite);
  for (int j = 0; j < finite; ++j) {
    const double nu = d[order[j]];
    out.lambda(j) = op.shift() + 1.0 / nu;
    y.col(j) = Eigen::Map<const Eigen::VectorXd>(z.data() + static_cast<size_t>(n) * order[j], n) /
               std::sqrt(nu);  // phi^T M phi = nu y^T y: unit modal mass
  }
  out.vectors = op.ToModes(y);
  out.converged = true;
  return out;
}

}  // namespace fricrom::reduction_detail
