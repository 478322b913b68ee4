// The α levels of a case (alpha_levels.h): interface, face shapes, pair.
#include <Eigen/Dense>
#include <algorithm>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fricrom/alpha_levels.h"
#include "fricrom/case_file.h"

namespace fricrom {
namespace {

// A face whose second in-plane extent is below this fraction of its first is a line of nodes:
// no second gradient shape.
constexpr double kFlatFace = 1e-3;

// The tangential direction of a contact from its name (".t2": the second of a pair), 0 otherwise.
int DirectionOf(const std::string& name) {
  return name.size() > 3 && name.compare(name.size() - 3, 3, ".t2") == 0 ? 1 : 0;
}

// Per (interface, direction) group the contacts in it; contacts outside interfaces alone.
std::vector<std::vector<int>> InterfaceGroups(const Case& c, std::vector<std::string>* names) {
  const int nc = static_cast<int>(c.model.contacts.size());
  const bool fe = static_cast<int>(c.contact_interface.size()) == nc;
  std::map<std::pair<int, int>, int> index;
  std::vector<std::vector<int>> groups;
  for (int k = 0; k < nc; ++k) {
    const int d = DirectionOf(c.model.contacts[k].name);
    // A contact outside the case's interfaces (given one by one, index −1) is its own interface.
    const int iface = fe ? c.contact_interface[k] : -1;
    const bool named = iface >= 0 && iface < static_cast<int>(c.interface_names.size());
    const std::pair<int, int> key = named ? std::make_pair(iface, d) : std::make_pair(-1 - k, 0);
    auto [it, added] = index.emplace(key, static_cast<int>(groups.size()));
    if (added) {
      groups.emplace_back();
      names->push_back(named ? c.interface_names[iface] + (d ? ".t2" : ".t1")
                             : c.model.contacts[k].name);
    }
    groups[it->second].push_back(k);
  }
  return groups;
}

// The face shapes of one group: columns 1, s1, s2 over its contacts' positions, s along the
// principal in-plane axes of the node cloud, each normalised to [−1, 1].
Eigen::MatrixXd FaceShapes(const Eigen::Matrix3Xd& pos) {
  const int n = static_cast<int>(pos.cols());
  Eigen::MatrixXd shapes = Eigen::MatrixXd::Ones(n, 1);
  if (n < 2) return shapes;
  const Eigen::Vector3d centre = pos.rowwise().mean();
  const Eigen::Matrix3Xd d = pos.colwise() - centre;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(d * d.transpose());
  const Eigen::Vector3d ev = eig.eigenvalues();  // ascending
  for (int axis = 2; axis >= 1; --axis) {
    if (!(ev[axis] > 0.0) || ev[axis] < kFlatFace * kFlatFace * ev[2]) continue;
    Eigen::VectorXd s = d.transpose() * eig.eigenvectors().col(axis);
    const double scale = s.cwiseAbs().maxCoeff();
    if (!(scale > 0.0)) continue;
    shapes.conservativeResize(n, shapes.cols() + 1);
    shapes.col(shapes.cols() - 1) = s / scale;
  }
  return shapes;
}

}  // namespace

std::vector<AlphaLevel> AlphaLevelsOf(const Case& c) {
  const int nc = static_cast<int>(c.model.contacts.size());
  const int na = c.model.num_alpha();
  AlphaLevel pair{"pair", Eigen::MatrixXd::Identity(na, na), {}};
  for (int a = 0; a < na; ++a) {
    pair.labels.push_back(c.model.alpha_group.empty() &&
                                  a < static_cast<int>(c.contact_names.size())
                              ? c.contact_names[a]
                              : "alpha" + std::to_string(a));
  }
  // Interface groups already in the case: its α are what the solvers vary, one level.
  if (!c.model.alpha_group.empty() || na != nc) return {pair};
  std::vector<std::string> names;
  const std::vector<std::vector<int>> groups = InterfaceGroups(c, &names);
  const bool have_positions = static_cast<int>(c.contact_positions.cols()) == nc;
  AlphaLevel interface { "interface", Eigen::MatrixXd::Zero(na, groups.size()), names };
  std::vector<Eigen::MatrixXd> shapes;
  int face_cols = 0;
  for (size_t g = 0; g < groups.size(); ++g) {
    Eigen::Matrix3Xd pos(3, groups[g].size());
    for (size_t k = 0; k < groups[g].size(); ++k) {
      interface.map(groups[g][k], static_cast<Eigen::Index>(g)) = 1.0;
      pos.col(static_cast<Eigen::Index>(k)) =
          have_positions ? Eigen::Vector3d(c.contact_positions.col(groups[g][k]))
                         : Eigen::Vector3d::Zero();
    }
    shapes.push_back(FaceShapes(pos));
    face_cols += static_cast<int>(shapes.back().cols());
  }
  AlphaLevel face{"face", Eigen::MatrixXd::Zero(na, face_cols), {}};
  int col = 0;
  for (size_t g = 0; g < groups.size(); ++g) {
    static const char* kShape[] = {".uniform", ".s1", ".s2"};
    for (int s = 0; s < shapes[g].cols(); ++s, ++col) {
      for (size_t k = 0; k < groups[g].size(); ++k) {
        face.map(groups[g][k], col) = shapes[g](static_cast<Eigen::Index>(k), s);
      }
      face.labels.push_back(names[g] + kShape[s]);
    }
  }
  // A level with the same map as the next finer one is that level (a lumped case: one level).
  std::vector<AlphaLevel> levels;
  const AlphaLevel* all[] = {&interface, &face, &pair};
  for (int i = 0; i < 3; ++i) {
    const bool same_as_next =
        i < 2 && all[i]->map.cols() == all[i + 1]->map.cols() && all[i]->map == all[i + 1]->map;
    if (!same_as_next) levels.push_back(*all[i]);
  }
  return levels;
}

}  // namespace fricrom
