#include "fricrom/balance.h"

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

std::unique_ptr<HarmonicBalance> MakeBalance(Model model, const HbmOptions& options,
                                             BalanceKind kind) {
  if (kind == BalanceKind::kCondensed) {
    return std::make_unique<CondensedSystem>(std::move(model), options);
  }
  return std::make_unique<HbmSystem>(std::move(model), options);
}

}  // namespace fricrom
