// The names of the harmonic-balance formulations a case can ask for (analysis.balance,
// analysis.receptance): plain data of the model's analysis settings, read and written by the
// case files without the solvers that implement them (balance.h, harmonic_balance.h).
#pragma once

#include <string>

namespace fricrom {

// The full balance over every DOF (HbmSystem, the lumped default) or the balance condensed onto
// the contact DOFs (CondensedSystem, the default of FE assemblies).
enum class BalanceKind { kFull, kCondensed };

// How the condensed balance forms the receptance Z_h(ω)⁻¹ of the linear part.
enum class ReceptanceMethod {
  kDense,  // LU of the real block form per harmonic and ω: exact for any damping, O(n³) per ω
  kModal,  // one generalised eigen-decomposition of (K + K_stick, M), then O(n_r² n) per ω; the
           // damping enters through the diagonal of Φᵀ C Φ (exact for proportional damping)
};

std::string ToString(BalanceKind kind);                              // "full" | "condensed"
bool FromString(const std::string& name, BalanceKind* kind);         // false on an unknown name
std::string ToString(ReceptanceMethod method);                       // "dense" | "modal"
bool FromString(const std::string& name, ReceptanceMethod* method);  // false on an unknown name

}  // namespace fricrom
