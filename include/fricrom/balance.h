// The choice of harmonic-balance formulation for a model: the full balance over every DOF
// (HbmSystem, the lumped default) or the balance condensed onto the contact DOFs
// (CondensedSystem, the default of FE assemblies). Both give the same solutions; the condensed
// one has 2 unknowns per contact and harmonic instead of one per DOF.
#pragma once

#include <memory>
#include <string>

#include "fricrom/formulation.h"
#include "fricrom/harmonic_balance.h"
#include "fricrom/model.h"

namespace fricrom {

// The balance of `kind` (fricrom/formulation.h) for the model. Throws std::invalid_argument on
// invalid options or an inconsistent model.
std::unique_ptr<HarmonicBalance> MakeBalance(Model model, const HbmOptions& options,
                                             BalanceKind kind);

}  // namespace fricrom
