#include "fricrom/formulation.h"

namespace fricrom {

std::string ToString(BalanceKind kind) {
  return kind == BalanceKind::kCondensed ? "condensed" : "full";
}

bool FromString(const std::string& name, BalanceKind* kind) {
  if (name == "full") {
    *kind = BalanceKind::kFull;
    return true;
  }
  if (name == "condensed") {
    *kind = BalanceKind::kCondensed;
    return true;
  }
  return false;
}

std::string ToString(ReceptanceMethod method) {
  return method == ReceptanceMethod::kModal ? "modal" : "dense";
}

bool FromString(const std::string& name, ReceptanceMethod* method) {
  if (name == "dense" || name == "modal") {
    *method = name == "modal" ? ReceptanceMethod::kModal : ReceptanceMethod::kDense;
    return true;
  }
  return false;
}

}  // namespace fricrom
