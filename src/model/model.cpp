#include "fricrom/model.h"

#include <algorithm>
#include <cmath>
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

Eigen::MatrixXd ContactStickStiffness(const Model& model) {
  const int n = model.num_dofs();
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (const Contact& c : model.contacts) {
    const Eigen::MatrixXd local =
        c.kn * c.normal * c.normal.transpose() + c.kt * c.tangent * c.tangent.transpose();
    const int dim = static_cast<int>(c.normal.size());
    for (int i = 0; i < dim; ++i) {
      for (int j = 0; j < dim; ++j) {
        const int ai = c.dofs_a[i], bi = c.dofs_b[i], aj = c.dofs_a[j], bj = c.dofs_b[j];
        if (ai >= 0 && aj >= 0) k(ai, aj) += local(i, j);
        if (bi >= 0 && bj >= 0) k(bi, bj) += local(i, j);
        if (ai >= 0 && bj >= 0) k(ai, bj) -= local(i, j);
        if (bi >= 0 && aj >= 0) k(bi, aj) -= local(i, j);
      }
    }
  }
  return k;
}

}  // namespace fricrom
