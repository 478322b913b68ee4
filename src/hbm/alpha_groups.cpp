#include "fricrom/alpha_groups.h"

#include <set>
#include <stdexcept>
#include <string>

namespace fricrom {

AlphaGroupedBalance::AlphaGroupedBalance(std::unique_ptr<HarmonicBalance> inner,
                                         std::vector<int> group_of_contact)
    : inner_(std::move(inner)), group_(std::move(group_of_contact)) {
  if (!inner_) throw std::invalid_argument("AlphaGroupedBalance: no balance given");
  if (static_cast<int>(group_.size()) != inner_->num_contacts()) {
    throw std::invalid_argument("AlphaGroupedBalance: " + std::to_string(group_.size()) +
                                " group indices for " + std::to_string(inner_->num_contacts()) +
                                " contacts");
  }
  for (int g : group_) {
    if (g < 0) throw std::invalid_argument("AlphaGroupedBalance: negative group index");
    num_groups_ = std::max(num_groups_, g + 1);
  }
  std::vector<int> size(num_groups_, 0);
  for (int g : group_) ++size[g];
  for (int g = 0; g < num_groups_; ++g) {
    if (size[g] == 0) {
      throw std::invalid_argument("AlphaGroupedBalance: group " + std::to_string(g) +
                                  " has no contact");
    }
  }
}

Eigen::VectorXd AlphaGroupedBalance::Expand(const Eigen::VectorXd& alpha) const {
  if (alpha.size() != num_groups_) {
    throw std::invalid_argument("AlphaGroupedBalance: alpha has " + std::to_string(alpha.size()) +
                                " entries, expected one per group (" + std::to_string(num_groups_) +
                                ")");
  }
  Eigen::VectorXd out(group_.size());
  for (size_t c = 0; c < group_.size(); ++c) out[c] = alpha[group_[c]];
  return out;
}

Eigen::MatrixXd AlphaGroupedBalance::SumColumns(const Eigen::MatrixXd& per_contact) const {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(per_contact.rows(), num_groups_);
  for (size_t c = 0; c < group_.size(); ++c) out.col(group_[c]) += per_contact.col(c);
  return out;
}

void AlphaGroupedBalance::Evaluate(const Eigen::VectorXd& x, double omega,
                                   const Eigen::VectorXd& alpha, const HbmRequest& request,
                                   HbmEvaluation* out) const {
  inner_->Evaluate(x, omega, Expand(alpha), request, out);
  if (request.alpha_jacobian) out->alpha_jacobian = SumColumns(out->alpha_jacobian);
}

double AlphaGroupedBalance::LossFactor(const Eigen::VectorXd& x, double omega,
                                       const Eigen::VectorXd& alpha, const HbmEvaluation& e,
                                       Eigen::VectorXd* grad_x, Eigen::VectorXd* grad_alpha) const {
  // The inner balance reads ∂R/∂α per contact from `e`: re-evaluate it at the expanded α.
  const Eigen::VectorXd a = Expand(alpha);
  if (!grad_alpha) return inner_->LossFactor(x, omega, a, e, grad_x, nullptr);
  HbmEvaluation inner_e;
  inner_->Evaluate(x, omega, a, HbmRequest{true, true, false}, &inner_e);
  Eigen::VectorXd g;
  const double eta = inner_->LossFactor(x, omega, a, inner_e, grad_x, &g);
  *grad_alpha = SumColumns(g.transpose()).transpose();
  return eta;
}

std::unique_ptr<HarmonicBalance> AlphaGroupedBalance::WithFewerHarmonics(int harmonics) const {
  std::unique_ptr<HarmonicBalance> inner = inner_->WithFewerHarmonics(harmonics);
  if (!inner) return nullptr;
  return std::make_unique<AlphaGroupedBalance>(std::move(inner), group_);
}

JacobianPattern AlphaGroupedBalance::StructuralPattern() const {
  // x columns as the inner balance's; a group's α column is the union of its contacts' columns.
  const JacobianPattern inner = inner_->StructuralPattern();
  const int nx = num_unknowns();
  JacobianPattern p;
  std::set<std::pair<int, int>> alpha_entries;  // (column, row), column-major like the inner
  for (int k = 0; k < inner.nnz(); ++k) {
    const int r = inner.rows[static_cast<size_t>(k)], c = inner.cols[static_cast<size_t>(k)];
    if (c < nx) {
      p.rows.push_back(r);
      p.cols.push_back(c);
    } else {
      alpha_entries.emplace(nx + group_[static_cast<size_t>(c - nx)], r);
    }
  }
  for (const auto& [c, r] : alpha_entries) {
    p.rows.push_back(r);
    p.cols.push_back(c);
  }
  return p;
}

}  // namespace fricrom
