// Fixed-interface modes of a Craig-Bampton reduction. Count mode: ARPACK for num_modes modes.
// Cutoff mode: a first ARPACK batch of num_modes; if its highest mode is still below the cutoff,
// Sylvester's law of inertia (an LDL^T of K_ii - lambda_cut M_ii) gives the exact number N of
// modes below the cutoff and one more ARPACK run asks for N + 1 (the last one must lie above the
// cutoff: a check of the count). Requests for a large share of the spectrum, and ARPACK runs that
// stop, finish with the dense generalized eigensolver up to kDenseFallbackMax interior DOFs.
#include "interior_modes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "arpack_eigs.h"
#include "dense_modes.h"
#include "fricrom/units.h"

namespace fricrom::reduction_detail {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string FormatG6(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// Keeps the modes up to the cutoff, or the lowest num_modes (noting a clamp).
void Select(const CraigBamptonOptions& o, InteriorModes* out) {
  const int available = static_cast<int>(out->lambda.size());
  int keep = 0;
  if (o.cutoff_hz > 0.0) {
    const double cut = EigenvalueFromHz(o.cutoff_hz);
    while (keep < available && out->lambda(keep) <= cut) ++keep;
  } else {
    keep = std::min(o.num_modes, available);
    if (keep < o.num_modes) {
      out->message += std::string(out->message.empty() ? "" : "; ") + "num_modes clamped to " +
                      std::to_string(keep) + " (finite interior modes available)";
    }
  }
  out->lambda.conservativeResize(keep);
  out->phi.conservativeResize(Eigen::NoChange, keep);
}

// Every finite mode, densely; then the selection.
void DenseAll(const Eigen::SparseMatrix<double>& kii, const Eigen::SparseMatrix<double>& mii,
              const CraigBamptonOptions& o, const std::string& note, InteriorModes* out) {
  std::string err;
  out->dense = true;
  out->message = note;
  if (!DenseLowestModes(kii, mii, o.shift, static_cast<int>(kii.rows()), &out->lambda, &out->phi,
                        &err)) {
    out->status = CraigBamptonStatus::kFactorizationFailed;
    out->message = err;
    return;
  }
  Select(o, out);
}

EigsResult Arpack(CholeskyTransformOp& op, int nev, const CraigBamptonOptions& o,
                  InteriorModes* out) {
  EigsResult r = LowestEigs(op, nev, o.eigen_tolerance, o.max_eigen_iterations);
  ++out->batches;
  out->restarts += r.restarts;
  out->applications = op.applications();
  return r;
}

}  // namespace

InteriorModes ComputeInteriorModes(const Eigen::SparseMatrix<double>& kii,
                                   const Eigen::SparseMatrix<double>& mii, CholmodFactor* kfac,
                                   const CraigBamptonOptions& o) {
  InteriorModes out;
  const int ni = static_cast<int>(kii.rows());
  if (ni == 0) return out;
  const bool by_cutoff = o.cutoff_hz > 0.0;
  const double cut = EigenvalueFromHz(o.cutoff_hz);
  const int first = std::min(o.num_modes, ni);
  // More than a quarter of the spectrum: Lanczos slows down (and stops with dsaupd info 3 when
  // massless DOFs leave fewer finite modes than asked for).
  auto large = [&](int nev) { return nev > ni - 2 || 4 * nev > ni; };
  if (ni <= o.dense_eigen_max_size || first > ni - 2 || (large(first) && ni <= kDenseFallbackMax)) {
    DenseAll(kii, mii, o,
             ni <= o.dense_eigen_max_size ? ""
                                          : "a large share of the interior spectrum asked for, "
                                            "dense eigensolver used",
             &out);
    return out;
  }
  // Finish densely when the interior is small enough, else fail saying why and what to do.
  auto fallback = [&](const std::string& why) {
    if (ni <= kDenseFallbackMax) {
      DenseAll(kii, mii, o, why + "; dense eigensolver used", &out);
    } else {
      out.status = CraigBamptonStatus::kEigenNotConverged;
      out.message =
          why + "; the interior (" + std::to_string(ni) + " DOFs) is beyond the dense limit of " +
          std::to_string(kDenseFallbackMax) +
          (by_cutoff ? ": lower the cutoff or ask for a number of modes" : ": ask for fewer modes");
    }
    return out;
  };
  CholeskyTransformOp op(kii, mii);
  std::string err;
  if (o.shift == 0.0) {
    op.use_factor(kfac);
  } else {
    const auto tf = Clock::now();
    const bool ok = op.set_shift(o.shift, &err);
    out.factor_s += Seconds(tf);
    if (!ok) {
      out.status = CraigBamptonStatus::kFactorizationFailed;
      out.message = "K_ii - shift * M_ii: " + err;
      return out;
    }
  }
  EigsResult r = Arpack(op, first, o, &out);
  if (!r.converged) {
    return fallback(
        "ARPACK: " + r.message +
        " (massless DOFs leave fewer finite modes than DOFs: M_ii may have fewer than " +
        std::to_string(first) + " finite modes)");
  }
  // All finite modes found (ARPACK met massless directions), or the highest is above the cutoff:
  // done. Otherwise count the modes below the cutoff and ask for one more than that.
  const auto got = r.lambda.size();
  if (by_cutoff && r.infinite == 0 && got > 0 && r.lambda(got - 1) <= cut) {
    int count = 0;
    const auto tc = Clock::now();
    const bool counted = CountEigenvaluesBelow(kii, mii, cut, &count, &err) ||
                         CountEigenvaluesBelow(kii, mii, cut * (1 + 1e-9), &count, &err);
    out.factor_s += Seconds(tc);
    if (!counted) return fallback("counting the modes below the cutoff: " + err);
    out.count_below_cutoff = count;
    if (count > first) {
      const std::string share = std::to_string(count) + " of the " + std::to_string(ni) +
                                " interior modes lie below the cutoff " + FormatG6(o.cutoff_hz) +
                                " Hz (Sylvester count)";
      if (large(count + 1)) return fallback(share + ", more than Lanczos delivers efficiently");
      r = Arpack(op, count + 1, o, &out);
      if (!r.converged) return fallback(share + "; ARPACK: " + r.message);
      const auto found = r.lambda.size();
      if (found < static_cast<Eigen::Index>(count) ||
          (found > static_cast<Eigen::Index>(count) && r.lambda(count) <= cut)) {
        return fallback(share + ", but ARPACK found " + std::to_string(found) +
                        " modes and the count disagrees");
      }
    }
  }
  out.lambda = r.lambda;
  out.phi = r.vectors;
  Select(o, &out);
  return out;
}

}  // namespace fricrom::reduction_detail
