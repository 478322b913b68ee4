// AlphaLevel's maps and AlphaLevelBalance: a harmonic balance seen through a level's parameters.
#include "fricrom/alpha_levels.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace fricrom {
namespace {

// An entry of P c counts as unsaturated up to this beyond ±1 (round-off of the product).
constexpr double kEdge = 1e-12;

}  // namespace

bool AlphaLevel::IsIdentity() const {
  return map.rows() == map.cols() &&
         map.isApprox(Eigen::MatrixXd::Identity(map.rows(), map.cols()), 0.0);
}

Eigen::VectorXd AlphaLevel::FineAlpha(const Eigen::VectorXd& c) const {
  if (c.size() != map.cols()) {
    throw std::invalid_argument("alpha level '" + name + "': " + std::to_string(c.size()) +
                                " parameters given, the level has " + std::to_string(map.cols()));
  }
  return (map * c).cwiseMax(-1.0).cwiseMin(1.0);
}

bool AlphaLevel::Lift(const Eigen::VectorXd& alpha, Eigen::VectorXd* c) const {
  if (alpha.size() != map.rows()) return false;
  if (IsIdentity()) {
    *c = alpha;
    return true;
  }
  *c = map.colPivHouseholderQr().solve(alpha).cwiseMax(-1.0).cwiseMin(1.0);
  return (FineAlpha(*c) - alpha).lpNorm<Eigen::Infinity>() <= 1e-10;
}

std::vector<Eigen::VectorXd> StructuredAlphaPatterns(const std::vector<AlphaLevel>& levels) {
  std::vector<Eigen::VectorXd> out;
  const auto add = [&out](const Eigen::VectorXd& a) {
    for (const Eigen::VectorXd& b : out) {
      if (b == a) return;
    }
    out.push_back(a);
  };
  for (size_t l = 0; l + 1 < levels.size(); ++l) {
    const AlphaLevel& level = levels[l];
    const int n = level.num_parameters();
    // A gradient shape: a column that is not constant over its contacts (a face's s1, s2).
    std::vector<int> gradients;
    for (int j = 0; j < n; ++j) {
      if (level.map.col(j).minCoeff() < 0.0) gradients.push_back(j);
    }
    if (gradients.empty()) {
      for (double s : {1.0, -1.0}) add(level.FineAlpha(Eigen::VectorXd::Constant(n, s)));
      for (int j = 0; j < n; ++j) {
        for (double s : {1.0, -1.0}) {
          Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
          c[j] = s;
          add(level.FineAlpha(c));
          c.setConstant(s);
          c[j] = -s;
          add(level.FineAlpha(c));
        }
      }
      continue;
    }
    for (int j : gradients) {
      for (double s : {1.0, -1.0}) {
        Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
        c[j] = s;
        add(level.FineAlpha(c));
      }
    }
    // Each face's first and second gradient together over every face, both signs.
    for (int which = 0; which < 2; ++which) {
      for (double s : {1.0, -1.0}) {
        Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
        int k = 0;
        for (int j = 0; j < n; ++j) {
          if (level.map.col(j).minCoeff() >= 0.0) {
            k = 0;
            continue;
          }
          if (k++ == which) c[j] = s;
        }
        add(level.FineAlpha(c));
      }
    }
  }
  return out;
}

AlphaLevelBalance::AlphaLevelBalance(const HarmonicBalance& inner, AlphaLevel level)
    : inner_(&inner), level_(std::move(level)) {
  if (level_.map.rows() != inner_->num_alpha() || level_.map.cols() < 1) {
    throw std::invalid_argument("AlphaLevelBalance: level '" + level_.name + "' maps to " +
                                std::to_string(level_.map.rows()) + " alpha, the balance has " +
                                std::to_string(inner_->num_alpha()));
  }
}

AlphaLevelBalance::AlphaLevelBalance(std::unique_ptr<HarmonicBalance> owned, AlphaLevel level)
    : AlphaLevelBalance(*owned, std::move(level)) {
  owned_ = std::move(owned);
}

Eigen::VectorXd AlphaLevelBalance::Fine(const Eigen::VectorXd& c) const {
  return level_.FineAlpha(c);
}

Eigen::MatrixXd AlphaLevelBalance::ChainColumns(const Eigen::MatrixXd& per_fine,
                                                const Eigen::VectorXd& c) const {
  const Eigen::VectorXd pc = level_.map * c;
  Eigen::MatrixXd dp = level_.map;
  for (int a = 0; a < pc.size(); ++a) {
    if (std::abs(pc[a]) > 1.0 + kEdge) dp.row(a).setZero();  // saturated: α does not move
  }
  return per_fine * dp;
}

void AlphaLevelBalance::Evaluate(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& c,
                                 const HbmRequest& request, HbmEvaluation* out) const {
  inner_->Evaluate(x, omega, Fine(c), request, out);
  if (request.alpha_jacobian) out->alpha_jacobian = ChainColumns(out->alpha_jacobian, c);
}

double AlphaLevelBalance::LossFactor(const Eigen::VectorXd& x, double omega,
                                     const Eigen::VectorXd& c, const HbmEvaluation& e,
                                     Eigen::VectorXd* grad_x, Eigen::VectorXd* grad_c) const {
  // The inner balance reads ∂R/∂α per fine α from `e`: re-evaluate it at the fine α.
  const Eigen::VectorXd a = Fine(c);
  if (!grad_c) return inner_->LossFactor(x, omega, a, e, grad_x, nullptr);
  HbmEvaluation inner_e;
  inner_->Evaluate(x, omega, a, HbmRequest{true, true, false}, &inner_e);
  Eigen::VectorXd g;
  const double eta = inner_->LossFactor(x, omega, a, inner_e, grad_x, &g);
  *grad_c = ChainColumns(g.transpose(), c).transpose();
  return eta;
}

std::unique_ptr<HarmonicBalance> AlphaLevelBalance::WithFewerHarmonics(int harmonics) const {
  std::unique_ptr<HarmonicBalance> inner = inner_->WithFewerHarmonics(harmonics);
  if (!inner) return nullptr;
  return std::make_unique<AlphaLevelBalance>(std::move(inner), level_);
}

}  // namespace fricrom
