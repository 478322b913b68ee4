#include "fricrom/balance.h"

#include <stdexcept>
#include <string>

#include "fricrom/alpha_groups.h"
#include "fricrom/condensed_system.h"
#include "fricrom/hbm_system.h"

namespace fricrom {

std::unique_ptr<HarmonicBalance> HarmonicBalance::WithFewerHarmonics(int) const { return nullptr; }

std::vector<ContactRegime> HarmonicBalance::ContactRegimes(const Eigen::VectorXd& x, double omega,
                                                           const Eigen::VectorXd& alpha) const {
  std::vector<ContactRegime> out;
  for (const ContactHistory& h : ContactHistories(x, omega, alpha)) out.push_back(h.regime);
  return out;
}

std::unique_ptr<JacobianOperator> HarmonicBalance::Linearize(
    const Eigen::VectorXd& /*x*/, double /*omega*/, const Eigen::VectorXd& /*alpha*/) const {
  return nullptr;
}

Eigen::VectorXd HarmonicBalance::FromDofCoefficients(
    const Eigen::VectorXd& dof_coefficients) const {
  if (dof_coefficients.size() != num_unknowns()) {
    throw std::invalid_argument("FromDofCoefficients: expected " + std::to_string(num_unknowns()) +
                                " coefficients, got " + std::to_string(dof_coefficients.size()));
  }
  return dof_coefficients;
}

Eigen::VectorXd HarmonicBalance::ToDofCoefficients(const Eigen::VectorXd& x, double /*omega*/,
                                                   const Eigen::VectorXd& /*alpha*/) const {
  if (x.size() != num_unknowns()) {
    throw std::invalid_argument("ToDofCoefficients: expected " + std::to_string(num_unknowns()) +
                                " unknowns, got " + std::to_string(x.size()));
  }
  return x;
}

JacobianPattern HarmonicBalance::StructuralPattern() const {
  const int nx = num_unknowns(), n = nx + num_alpha();
  JacobianPattern p;
  p.rows.reserve(static_cast<size_t>(nx) * static_cast<size_t>(n));
  p.cols.reserve(p.rows.capacity());
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < n; ++j) {
      p.rows.push_back(i);
      p.cols.push_back(j);
    }
  }
  return p;
}

const HarmonicBalance* HarmonicBalance::FirstHarmonicBalance() const {
  if (!first_harmonic_tried_ && harmonics() > 1) {
    first_harmonic_tried_ = true;
    first_harmonic_ = WithFewerHarmonics(1);
  }
  return first_harmonic_.get();
}

Eigen::VectorXd HarmonicBalance::EmbedLowerHarmonics(const Eigen::VectorXd& x_low,
                                                     int low_harmonics) const {
  const int nh = 2 * harmonics() + 1, nl = 2 * low_harmonics + 1;
  const int block = num_unknowns() / nh;
  if (low_harmonics < 0 || low_harmonics > harmonics() || x_low.size() != block * nl) {
    throw std::invalid_argument("EmbedLowerHarmonics: x_low has " + std::to_string(x_low.size()) +
                                " entries, expected " + std::to_string(block) + " x " +
                                std::to_string(nl) + " coefficients");
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(num_unknowns());
  x.head(x_low.size()) = x_low;
  return x;
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
