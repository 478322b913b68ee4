// Hill stability (stability.h): the quadratic eigenvalue problem of the linearised balance in
// companion form, and the imaginary-part criterion for the physical exponents.
#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "fricrom/condensed_system.h"
#include "fricrom/stability.h"

namespace fricrom {

bool HillOptions::IsValid(std::string* error) const {
  if (!(growth_tolerance >= 0.0) || !std::isfinite(growth_tolerance)) {
    *error = "HillOptions.growth_tolerance must be finite and >= 0";
    return false;
  }
  if (!(modal_cutoff_factor >= 1.0) || !std::isfinite(modal_cutoff_factor)) {
    *error = "HillOptions.modal_cutoff_factor must be finite and >= 1";
    return false;
  }
  return true;
}

std::string HillResult::BriefReport() const {
  std::ostringstream os;
  os << (stable ? "stable" : "unstable") << ": largest Floquet exponent real part " << max_real
     << " 1/s (" << exponents.size() << " exponents)";
  if (!message.empty()) os << "; " << message;
  return os.str();
}

namespace {

// The companion form's dimension 2n(2H+1) beyond which the dense, nonsymmetric eigen-solve
// (O(N³)) is not attempted for a bound's report: the lumped benchmark's is 60 at H = 1.
constexpr int kLargestHillProblem = 3000;

// Kronecker product of the (2H+1)-coefficient operator `op` with the n x n matrix `a`, in the
// harmonic-major layout (coefficient blocks of n).
Eigen::MatrixXd Kron(const Eigen::MatrixXd& op, const Eigen::MatrixXd& a) {
  const Eigen::Index c = op.rows(), n = a.rows();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(c * n, c * n);
  for (Eigen::Index i = 0; i < c; ++i) {
    for (Eigen::Index j = 0; j < c; ++j) {
      if (op(i, j) != 0.0) out.block(i * n, j * n, n, n) = op(i, j) * a;
    }
  }
  return out;
}

// ∇ on the coefficients [q0, a1, b1, …]: d/dt of a cos hωt + b sin hωt has cosine hω b and sine
// −hω a.
Eigen::MatrixXd Derivative(int harmonics, double omega) {
  const int c = 2 * harmonics + 1;
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(c, c);
  for (int h = 1; h <= harmonics; ++h) {
    d(2 * h - 1, 2 * h) = h * omega;
    d(2 * h, 2 * h - 1) = -h * omega;
  }
  return d;
}

}  // namespace

void NoteSwitchingContacts(const std::vector<ContactRegime>& regimes, HillResult* r) {
  r->switching_contacts = 0;
  for (ContactRegime g : regimes) {
    r->switching_contacts +=
        g == ContactRegime::kStickSlip || g == ContactRegime::kStickSlipLiftOff ? 1 : 0;
  }
  if (r->switching_contacts > 0) {
    r->message += "; approximate: " + std::to_string(r->switching_contacts) +
                  " contact(s) switch between stick and slip (a sampled non-smooth law), time "
                  "integration from the solution decides (frf --time-check, verify)";
  }
}

HillResult HillStability(const Eigen::MatrixXd& jacobian, const Eigen::MatrixXd& mass,
                         const Eigen::MatrixXd& damping, int harmonics, double omega,
                         const HillOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  const Eigen::Index n = mass.rows(), c = 2 * harmonics + 1, size = n * c;
  if (harmonics < 1 || !(omega > 0.0) || mass.cols() != n || damping.rows() != n ||
      damping.cols() != n || jacobian.rows() != size || jacobian.cols() != size) {
    throw std::invalid_argument(
        "HillStability: expected an (n(2H+1))^2 Jacobian, n x n M and C, H >= 1 and omega > 0");
  }
  const Eigen::LLT<Eigen::MatrixXd> m_llt(mass);
  if (m_llt.info() != Eigen::Success) {
    throw std::invalid_argument(
        "HillStability: the mass matrix is not positive definite (massless directions have no "
        "Floquet exponent)");
  }
  const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(c, c);
  const Eigen::MatrixXd d1 = Kron(2.0 * Derivative(harmonics, omega), mass) + Kron(id, damping);
  // Companion form of (J + λΔ1 + λ²Δ2) p = 0 with Δ2 = I ⊗ M inverted blockwise:
  // [p; λp]' = [[0, I], [−Δ2⁻¹J, −Δ2⁻¹Δ1]].
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * size, 2 * size);
  a.topRightCorner(size, size).setIdentity();
  for (Eigen::Index k = 0; k < c; ++k) {
    a.block(size + k * n, 0, n, size) = -m_llt.solve(jacobian.middleRows(k * n, n));
    a.block(size + k * n, size, n, size) = -m_llt.solve(d1.middleRows(k * n, n));
  }
  Eigen::EigenSolver<Eigen::MatrixXd> solver(a, true);
  if (solver.info() != Eigen::Success) {
    throw std::runtime_error("HillStability: the eigenvalue solver did not converge");
  }
  const Eigen::VectorXcd lambda = solver.eigenvalues();
  // Each exponent appears once per harmonic shift i h ω. Written in e^{ikωt}, k = −H..H, the
  // periodic part of a copy shifted by i h ω has its weight shifted by h harmonics: the physical
  // copy is the one whose weight is centred on k = 0 (Lazarus & Thomas' symmetry criterion; it
  // keeps the right copies where H is too small for one within ±ω/2 to exist, where the
  // smallest-|Im λ| rule fails). c_{±h} = (a_h ∓ i b_h)/2 from the cosine/sine blocks.
  std::vector<double> centre(static_cast<size_t>(lambda.size()));
  const std::complex<double> i_unit(0.0, 1.0);
  for (Eigen::Index e = 0; e < lambda.size(); ++e) {
    const Eigen::VectorXcd p = solver.eigenvectors().col(e).head(size);
    double mean = 0.0, total = p.head(n).squaredNorm();
    for (int h = 1; h <= harmonics; ++h) {
      const Eigen::VectorXcd a = p.segment((2 * h - 1) * n, n), b = p.segment(2 * h * n, n);
      const double plus = (0.5 * (a - i_unit * b)).squaredNorm();
      const double minus = (0.5 * (a + i_unit * b)).squaredNorm();
      mean += h * (plus - minus);
      total += plus + minus;
    }
    centre[static_cast<size_t>(e)] = total > 0 ? std::abs(mean) / total : 0.0;
  }
  std::vector<Eigen::Index> order(static_cast<size_t>(lambda.size()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index i, Eigen::Index j) {
    const double ci = centre[static_cast<size_t>(i)], cj = centre[static_cast<size_t>(j)];
    if (std::abs(ci - cj) > 1e-9) return ci < cj;
    return std::abs(lambda[i].imag()) < std::abs(lambda[j].imag());
  });
  order.resize(static_cast<size_t>(2 * n));
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index i, Eigen::Index j) {
    return lambda[i].real() > lambda[j].real();
  });
  HillResult r;
  r.exponents.resize(2 * n);
  for (Eigen::Index i = 0; i < 2 * n; ++i) r.exponents[i] = lambda[order[static_cast<size_t>(i)]];
  r.max_real = r.exponents[0].real();
  if (!std::isfinite(r.max_real)) {
    r.stable = false;
    r.message = "a Floquet exponent is not finite";
    return r;
  }
  r.stable = r.max_real <= options.growth_tolerance * omega;
  r.message = r.stable ? "every Floquet exponent decays"
                       : "a Floquet exponent grows: perturbations leave the solution";
  return r;
}

HillResult HillStability(const HbmSystem& system, const Eigen::VectorXd& x, double omega,
                         const Eigen::VectorXd& alpha, const HillOptions& options) {
  if (HasCyclicContacts(system.model())) {
    // A sector's Floquet exponents would judge only perturbations of its own nodal diameters.
    throw std::domain_error(
        "a cyclic sector's Floquet exponents would judge its own nodal diameters only");
  }
  // A contact stuck over the whole period holds a perturbation with its stick springs in every
  // harmonic, the static one included. The balance's AFT says otherwise for it: it prescribes the
  // static tangential force by α (∂R/∂q̂0 lacks kt), and where the AFT's first pass slipped
  // before the contact settled into stick, its Jacobian carries that transient's dependence on the
  // harmonics (measured on the lumped benchmark at 270 Hz: a spurious growing exponent). Those
  // contacts are therefore taken out of the AFT and put back as linear springs.
  const Model& model = system.model();
  const std::vector<ContactRegime> regimes = system.ContactRegimes(x, omega, alpha);
  const Eigen::VectorXd per_contact = model.ContactAlpha(alpha);
  Model rest = model, stuck = model;
  rest.contacts.clear();
  rest.alpha_group.clear();
  stuck.contacts.clear();
  std::vector<double> rest_alpha;
  for (size_t k = 0; k < regimes.size(); ++k) {
    if (regimes[k] == ContactRegime::kFullStick) {
      stuck.contacts.push_back(model.contacts[k]);
    } else {
      rest.contacts.push_back(model.contacts[k]);
      rest_alpha.push_back(per_contact[static_cast<Eigen::Index>(k)]);
    }
  }
  HbmEvaluation e;
  HbmRequest request;
  request.jacobian = true;
  if (stuck.contacts.empty()) {
    system.Evaluate(x, omega, alpha, request, &e);
  } else {
    const HbmSystem without(rest, system.options());
    without.Evaluate(x, omega,
                     Eigen::Map<const Eigen::VectorXd>(
                         rest_alpha.data(), static_cast<Eigen::Index>(rest_alpha.size())),
                     request, &e);
    const Eigen::MatrixXd springs = ContactStickStiffness(stuck);
    const Eigen::Index n = system.num_dofs();
    for (int c = 0; c < system.num_coefficients(); ++c)
      e.jacobian.block(c * n, c * n, n, n) += springs;
  }
  HillResult r =
      HillStability(e.jacobian, model.mass, model.damping, system.harmonics(), omega, options);
  NoteSwitchingContacts(regimes, &r);
  return r;
}

HillResult SolutionStability::At(const Eigen::VectorXd& x, double omega,
                                 const Eigen::VectorXd& alpha, const HillOptions& options) {
  if (const auto* condensed = dynamic_cast<const CondensedSystem*>(&system_)) {
    if (!condensed_) condensed_ = std::make_unique<CondensedHill>(*condensed);
    return condensed_->At(x, omega, alpha, options);
  }
  return HillStabilityOf(system_, x, omega, alpha, options);
}

HillResult HillStabilityOf(const HarmonicBalance& system, const Eigen::VectorXd& x, double omega,
                           const Eigen::VectorXd& alpha, const HillOptions& options) {
  if (const auto* condensed = dynamic_cast<const CondensedSystem*>(&system)) {
    return HillStability(*condensed, x, omega, alpha, options);
  }
  const auto* full = dynamic_cast<const HbmSystem*>(&system);
  if (!full) {
    throw std::domain_error("Hill stability is computed for the full and the condensed balance");
  }
  if (2 * full->num_unknowns() > kLargestHillProblem) {
    throw std::domain_error("the dense Hill eigenproblem (" +
                            std::to_string(2 * full->num_unknowns()) +
                            " unknowns) is too large to solve here: use the condensed balance");
  }
  return HillStability(*full, x, omega, alpha, options);
}

void AssessBoundStability(const HarmonicBalance& system, double omega, BoundsResult* b,
                          const HillOptions& options) {
  SolutionStability stability(system);
  AssessBoundStability(&stability, omega, b, options);
}

void AssessBoundStability(SolutionStability* stability, double omega, BoundsResult* b,
                          const HillOptions& options) {
  for (BoundSolution* s : {&b->min, &b->max}) {
    s->stability = {};
    if (!s->IsUsable()) {
      s->stability.note = "no solution";
      continue;
    }
    try {
      const HillResult r = stability->At(s->x, omega, s->alpha, options);
      s->stability.computed = true;
      s->stability.stable = r.stable;
      s->stability.max_floquet_real = r.max_real;
      s->stability.note = r.message;
    } catch (const std::domain_error& e) {
      s->stability.note = std::string("not computed: ") + e.what();
    }
  }
}

}  // namespace fricrom
