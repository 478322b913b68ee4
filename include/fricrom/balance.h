// The choice of harmonic-balance formulation for a model: the full balance over every DOF
// (HbmSystem, the lumped default) or the balance condensed onto the contact DOFs
// (CondensedSystem, the default of FE assemblies). Both give the same solutions; the condensed
// one has 2 unknowns per contact and harmonic instead of one per DOF.
#pragma once

#include <memory>
#include <string>

#include "fricrom/harmonic_balance.h"
#include "fricrom/model.h"

namespace fricrom {

enum class BalanceKind { kFull, kCondensed };
std::string ToString(BalanceKind kind);                              // "full" | "condensed"
bool FromString(const std::string& name, BalanceKind* kind);         // false on an unknown name
std::string ToString(ReceptanceMethod method);                       // "dense" | "modal"
bool FromString(const std::string& name, ReceptanceMethod* method);  // false on an unknown name

// Throws std::invalid_argument on invalid options or an inconsistent model.
std::unique_ptr<HarmonicBalance> MakeBalance(Model model, const HbmOptions& options,
                                             BalanceKind kind);

}  // namespace fricrom
