#include "fricrom/model.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>

namespace fricrom {

int Model::DofIndex(const std::string& name) const {
  for (int i = 0; i < num_dofs(); ++i) {
    if (dof_names[i] == name) return i;
  }
  return -1;
}

void Model::Validate() const {
  const int n = num_dofs();
  auto fail = [](const std::string& what) { throw std::invalid_argument("Model: " + what); };
  if (n == 0) fail("no degrees of freedom");
  auto square = [&](const Eigen::MatrixXd& m, const char* name) {
    if (m.rows() != n || m.cols() != n) {
      fail(std::string(name) + " is " + std::to_string(m.rows()) + "x" + std::to_string(m.cols()) +
           ", expected " + std::to_string(n) + "x" + std::to_string(n));
    }
    if (!m.allFinite()) fail(std::string(name) + " has non-finite entries");
  };
  square(mass, "mass");
  square(damping, "damping");
  square(stiffness, "stiffness");
  if (response_dof < 0 || response_dof >= n) fail("response_dof out of range");
  for (int d : free_dofs) {
    if (d < 0 || d >= n) fail("free_dofs holds an index out of range");
  }
  for (const Contact& c : contacts) {
    const std::string who = "contact '" + c.name + "': ";
    const auto dim = c.normal.size();
    if (dim == 0 || c.tangent.size() != dim || static_cast<Eigen::Index>(c.dofs_a.size()) != dim ||
        static_cast<Eigen::Index>(c.dofs_b.size()) != dim) {
      fail(who + "normal, tangent, dofs_a and dofs_b must have the same non-zero length");
    }
    if (std::abs(c.normal.norm() - 1.0) > 1e-9 || std::abs(c.tangent.norm() - 1.0) > 1e-9) {
      fail(who + "normal and tangent must be unit vectors");
    }
    if (std::abs(c.normal.dot(c.tangent)) > 1e-9) fail(who + "normal and tangent not orthogonal");
    if (c.normal_b.size() != c.tangent_b.size() ||
        (c.normal_b.size() != 0 && c.normal_b.size() != dim)) {
      fail(who + "normal_b and tangent_b must both be empty or have the length of normal");
    }
    if (c.normal_b.size() != 0 &&
        (std::abs(c.normal_b.norm() - 1.0) > 1e-9 || std::abs(c.tangent_b.norm() - 1.0) > 1e-9 ||
         std::abs(c.normal_b.dot(c.tangent_b)) > 1e-9)) {
      fail(who + "normal_b and tangent_b must be orthogonal unit vectors");
    }
    if (!std::isfinite(c.phase_b)) fail(who + "phase_b must be finite");
    for (size_t i = 0; i < c.dofs_a.size(); ++i) {
      if (c.dofs_a[i] >= n || c.dofs_b[i] >= n) fail(who + "DOF index out of range");
    }
    if (!(c.kn >= 0.0) || !(c.kt > 0.0) || !(c.mu >= 0.0)) {
      fail(who + "needs kn >= 0, kt > 0, mu >= 0");
    }
  }
  if (!alpha_group.empty()) {
    if (alpha_group.size() != contacts.size()) fail("alpha_group needs one entry per contact");
    std::vector<int> members(contacts.size(), 0);
    for (int g : alpha_group) {
      if (g < 0 || g >= static_cast<int>(contacts.size())) fail("alpha_group index out of range");
      ++members[g];
    }
    for (int g = 0; g < num_alpha(); ++g) {
      if (members[g] == 0) fail("alpha group " + std::to_string(g) + " has no contact");
    }
  }
  for (const HarmonicLoad& l : loads) {
    if (l.harmonic < 0) fail("load with negative harmonic");
    if (l.cos.size() != n || l.sin.size() != n) fail("load vectors must have one entry per DOF");
  }
}

int Model::num_alpha() const {
  if (alpha_group.empty()) return static_cast<int>(contacts.size());
  return *std::max_element(alpha_group.begin(), alpha_group.end()) + 1;
}

int Model::num_contact_pairs() const {
  std::set<std::pair<std::vector<int>, std::vector<int>>> pairs;
  for (const Contact& c : contacts) pairs.emplace(c.dofs_a, c.dofs_b);
  return static_cast<int>(pairs.size());
}

Eigen::VectorXd Model::ContactAlpha(const Eigen::VectorXd& alpha) const {
  if (alpha.size() != num_alpha()) {
    throw std::invalid_argument("Model: alpha has " + std::to_string(alpha.size()) +
                                " entries, expected " + std::to_string(num_alpha()));
  }
  if (alpha_group.empty()) return alpha;
  Eigen::VectorXd out(alpha_group.size());
  for (size_t c = 0; c < alpha_group.size(); ++c) out[c] = alpha[alpha_group[c]];
  return out;
}

void CyclicSymmetry::Validate() const {
  if (sectors < 2) {
    throw std::invalid_argument("cyclic symmetry needs at least 2 sectors, got " +
                                std::to_string(sectors));
  }
  if (engine_order < 0 || engine_order > sectors / 2) {
    throw std::invalid_argument("engine order must lie in 0.." + std::to_string(sectors / 2) +
                                " for " + std::to_string(sectors) + " sectors, got " +
                                std::to_string(engine_order));
  }
}

double CyclicSymmetry::phase() const {
  return sectors > 0 ? 2.0 * std::numbers::pi * engine_order / sectors : 0.0;
}

bool HasCyclicContacts(const Model& model) {
  return std::any_of(model.contacts.begin(), model.contacts.end(),
                     [](const Contact& c) { return c.cyclic(); });
}

void RequireNoCyclicContacts(const Model& model, const std::string& who) {
  if (HasCyclicContacts(model)) {
    throw std::invalid_argument(who +
                                " does not handle cyclic-symmetry contacts (a sector's "
                                "contacts with the next sector); use the full harmonic balance "
                                "or the explicit ring (ExpandCyclicRing)");
  }
}

namespace {

// One relative-displacement row of a contact in harmonic h's real block form: its cos row
// (which = 0) or sin row (which = 1) over [q_cos; q_sin] (2n), or over q (n) for h = 0, as
// (index, coefficient) terms.
std::vector<std::pair<int, double>> StickRow(const Contact& c, bool normal, int h, int n,
                                             int which) {
  const Eigen::VectorXd& da = normal ? c.normal : c.tangent;
  const Eigen::VectorXd& db = normal ? c.NormalB() : c.TangentB();
  const double th = h * c.phase_b, co = std::cos(th), si = std::sin(th);
  std::vector<std::pair<int, double>> row;
  for (int i = 0; i < da.size(); ++i) {
    const int a = c.dofs_a[static_cast<size_t>(i)], b = c.dofs_b[static_cast<size_t>(i)];
    if (a >= 0) row.emplace_back(a + which * n, da[i]);
    if (b < 0) continue;
    if (h == 0) {
      row.emplace_back(b, -db[i]);
    } else if (which == 0) {  // cos row of the delayed side B: c·q_cos − s·q_sin
      row.emplace_back(b, -db[i] * co);
      row.emplace_back(b + n, db[i] * si);
    } else {  // sin row: s·q_cos + c·q_sin
      row.emplace_back(b, -db[i] * si);
      row.emplace_back(b + n, -db[i] * co);
    }
  }
  return row;
}

}  // namespace

Eigen::MatrixXd ContactStickStiffness(const Model& model, int harmonic) {
  const int n = model.num_dofs(), size = harmonic == 0 ? n : 2 * n;
  if (harmonic == 0 || !HasCyclicContacts(model)) {
    const Eigen::MatrixXd k0 = ContactStickStiffness(model);
    if (harmonic == 0) return k0;
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(size, size);
    k.topLeftCorner(n, n) = k0;
    k.bottomRightCorner(n, n) = k0;
    return k;
  }
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(size, size);
  for (const Contact& c : model.contacts) {
    for (const bool normal : {true, false}) {
      const double stiffness = normal ? c.kn : c.kt;
      for (int which = 0; which < (harmonic == 0 ? 1 : 2); ++which) {
        const auto row = StickRow(c, normal, harmonic, n, which);
        for (const auto& [i, ci] : row) {
          for (const auto& [j, cj] : row) k(i, j) += stiffness * ci * cj;
        }
      }
    }
  }
  return k;
}

Eigen::MatrixXd ContactStickStiffness(const Model& model) {
  const int n = model.num_dofs();
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (const Contact& c : model.contacts) {
    // Side B's directions differ from A's only on a cyclic contact (the next sector's rotation).
    const Eigen::VectorXd &nb = c.NormalB(), &tb = c.TangentB();
    const Eigen::MatrixXd aa =
        c.kn * c.normal * c.normal.transpose() + c.kt * c.tangent * c.tangent.transpose();
    const Eigen::MatrixXd bb =
        c.cyclic() ? Eigen::MatrixXd(c.kn * nb * nb.transpose() + c.kt * tb * tb.transpose()) : aa;
    const Eigen::MatrixXd ab =
        c.cyclic()
            ? Eigen::MatrixXd(c.kn * c.normal * nb.transpose() + c.kt * c.tangent * tb.transpose())
            : aa;
    const int dim = static_cast<int>(c.normal.size());
    for (int i = 0; i < dim; ++i) {
      for (int j = 0; j < dim; ++j) {
        const int ai = c.dofs_a[i], bi = c.dofs_b[i], aj = c.dofs_a[j], bj = c.dofs_b[j];
        if (ai >= 0 && aj >= 0) k(ai, aj) += aa(i, j);
        if (bi >= 0 && bj >= 0) k(bi, bj) += bb(i, j);
        if (ai >= 0 && bj >= 0) k(ai, bj) -= ab(i, j);
        // ab(j, i) couples B's direction i with A's j; an ordinary contact keeps local(i, j),
        // equal up to the rounding of the outer product, so its matrix stays the same to the bit.
        if (bi >= 0 && aj >= 0) k(bi, aj) -= c.cyclic() ? ab(j, i) : ab(i, j);
      }
    }
  }
  return k;
}

}  // namespace fricrom
