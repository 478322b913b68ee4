// Invariants every case the case-file readers accept must satisfy (both fuzz targets of case
// files: case_fuzz.cpp for fricrom-case-1, assembly_fuzz.cpp for fricrom-assembly-1); a broken
// one aborts, which libFuzzer reports as a finding.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "fricrom/case_file.h"

namespace fricrom_fuzz {

inline void Check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "invariant broken: %s\n", what);
    std::abort();
  }
}

// Finite matrices, loads and contact laws, the response DOF in range, loads within H, AFT samples
// that resolve H, one default α in [-1, 1] per α, and at least one harmonic load.
inline void CheckCase(const fricrom::Case& c) {
  const fricrom::Model& m = c.model;
  Check(m.num_dofs() > 0, "a case has DOFs");
  Check(m.mass.allFinite() && m.stiffness.allFinite() && m.damping.allFinite(), "finite matrices");
  Check(m.response_dof >= 0 && m.response_dof < m.num_dofs(), "response DOF in range");
  for (const fricrom::Contact& k : m.contacts) {
    Check(std::isfinite(k.kn) && std::isfinite(k.kt) && std::isfinite(k.mu) &&
              std::isfinite(k.normal_preload),
          "finite contact law");
  }
  bool harmonic = false;
  for (const fricrom::HarmonicLoad& l : m.loads) {
    Check(l.cos.allFinite() && l.sin.allFinite(), "finite loads");
    Check(l.harmonic >= 0 && l.harmonic <= c.analysis.harmonics, "load harmonic within H");
    harmonic = harmonic || (l.harmonic >= 1 && (l.cos.norm() > 0 || l.sin.norm() > 0));
  }
  Check(harmonic, "a harmonic load");
  Check(c.analysis.harmonics >= 1 && c.analysis.samples_per_period > 2 * c.analysis.harmonics,
        "AFT samples resolve H");
  Check(static_cast<int>(c.analysis.alpha.size()) == m.num_alpha(), "one default alpha per alpha");
  for (double a : c.analysis.alpha) Check(std::abs(a) <= 1.0, "default alpha in [-1, 1]");
}

}  // namespace fricrom_fuzz
