#include "fricrom/balance.h"

#include "fricrom/alpha_groups.h"
#include "fricrom/condensed.h"
#include "fricrom/hbm.h"

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

std::unique_ptr<HarmonicBalance> MakeBalance(Model model, const HbmOptions& options,
                                             BalanceKind kind) {
  std::vector<int> groups = model.alpha_group;
  std::unique_ptr<HarmonicBalance> balance;
  if (kind == BalanceKind::kCondensed) {
    balance = std::make_unique<CondensedSystem>(std::move(model), options);
  } else {
    balance = std::make_unique<HbmSystem>(std::move(model), options);
  }
  if (groups.empty()) return balance;
  return std::make_unique<AlphaGroupedBalance>(std::move(balance), std::move(groups));
}

}  // namespace fricrom
