// Local coordinate systems of FE models resolved to the basic frame (basic_frame.h).
#include "fricrom/basic_frame.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace fricrom {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// Direction cosines below this are round-off of a turn that does not mix two directions.
constexpr double kNoMixing = 1e-12;
// Deeper reference chains than this are taken for a loop (real decks chain two or three).
constexpr int kMaxDepth = 64;

// Cartesian coordinates, in the system's own rectangular frame, of coordinates `p` of a system of
// type `type`.
Eigen::Vector3d Cartesian(char type, const Eigen::Vector3d& p) {
  if (type == 'C') return {p[0] * std::cos(p[1] * kDeg), p[0] * std::sin(p[1] * kDeg), p[2]};
  if (type == 'S') {
    const double t = p[1] * kDeg, f = p[2] * kDeg;
    return {p[0] * std::sin(t) * std::cos(f), p[0] * std::sin(t) * std::sin(f), p[0] * std::cos(t)};
  }
  return p;
}

std::string SystemName(const CoordinateSystem& s) {
  return std::string(s.by_grids ? "CORD1" : "CORD2") + s.type + " " + std::to_string(s.id);
}

}  // namespace

BasicFrame::BasicFrame(const FeModel& model) : source_(model.source) {
  for (const CoordinateSystem& s : model.systems) cards_[s.id] = s;
  for (const auto& [id, card] : cards_) systems_[id] = Resolve(id, 0);
}

BasicFrame::Resolved BasicFrame::Resolve(int id, int depth) const {
  Resolved r;
  if (id == 0) return r;
  const auto it = cards_.find(id);
  if (it == cards_.end()) {
    r.error = "coordinate system " + std::to_string(id) + " is not defined in " + source_;
    return r;
  }
  const CoordinateSystem& s = it->second;
  if (s.by_grids) {
    r.error = SystemName(s) + " of " + source_ +
              " is defined by grid points, which fricrom does not read: write it as a CORD2" +
              s.type + " card (origin, a point on z, a point in the x-z plane)";
    return r;
  }
  if (depth > kMaxDepth) {
    r.error = "coordinate system " + std::to_string(id) + " of " + source_ +
              " refers to itself through its reference systems (RID)";
    return r;
  }
  const Resolved ref = Resolve(s.reference, depth + 1);
  if (!ref.error.empty()) {
    r.error = SystemName(s) + ": " + ref.error;
    return r;
  }
  const auto to_basic = [&](const Eigen::Vector3d& p) {
    return (ref.origin + ref.axes.transpose() * Cartesian(ref.type, p)).eval();
  };
  const Eigen::Vector3d a = to_basic(s.a), b = to_basic(s.b), c = to_basic(s.c);
  const Eigen::Vector3d z = b - a, xz = c - a;
  if (!(z.norm() > 0) || !(z.cross(xz).norm() > 1e-12 * z.norm() * xz.norm())) {
    r.error = SystemName(s) + " of " + source_ +
              " is degenerate in the basic frame (expected B != A and C off the line A-B)";
    return r;
  }
  const Eigen::Vector3d ez = z.normalized();
  const Eigen::Vector3d ey = ez.cross(xz).normalized();
  r.type = s.type;
  r.origin = a;
  r.axes.row(0) = ey.cross(ez).transpose();
  r.axes.row(1) = ey.transpose();
  r.axes.row(2) = ez.transpose();
  return r;
}

const BasicFrame::Resolved& BasicFrame::Get(int id) const {
  static const Resolved kBasic;
  if (id == 0) return kBasic;
  const auto it = systems_.find(id);
  if (it == systems_.end()) {
    throw std::invalid_argument("coordinate system " + std::to_string(id) + " is not defined in " +
                                source_);
  }
  if (!it->second.error.empty()) throw std::invalid_argument(it->second.error);
  return it->second;
}

Eigen::Vector3d BasicFrame::ToBasic(int id, const Eigen::Vector3d& p) const {
  const Resolved& s = Get(id);
  return s.origin + s.axes.transpose() * Cartesian(s.type, p);
}

Eigen::Matrix3d BasicFrame::Axes(int id, const Eigen::Vector3d& at) const {
  const Resolved& s = Get(id);
  if (s.type == 'R') return s.axes;
  // Directions in the system's rectangular frame at the point (on the axis: those of angle 0).
  const Eigen::Vector3d q = s.axes * (at - s.origin);
  const double f = std::atan2(q[1], q[0]);
  Eigen::Matrix3d local;
  if (s.type == 'C') {
    local << std::cos(f), std::sin(f), 0.0, -std::sin(f), std::cos(f), 0.0, 0.0, 0.0, 1.0;
  } else {
    const double t = std::atan2(std::hypot(q[0], q[1]), q[2]);
    local << std::sin(t) * std::cos(f), std::sin(t) * std::sin(f), std::cos(t),
        std::cos(t) * std::cos(f), std::cos(t) * std::sin(f), -std::sin(t), -std::sin(f),
        std::cos(f), 0.0;
  }
  return local * s.axes;
}

namespace {

// u_local = T u_basic over the DOFs `dofs`: identity except the triples of turned nodes.
Eigen::SparseMatrix<double> Turn(const std::vector<DofId>& dofs,
                                 const std::map<int64_t, Eigen::Matrix3d>& turn,
                                 const std::string& what) {
  std::map<std::pair<int64_t, int>, int> index;
  for (size_t i = 0; i < dofs.size(); ++i) index[{dofs[i].node, dofs[i].component}] = int(i);
  std::vector<Eigen::Triplet<double>> t;
  for (size_t i = 0; i < dofs.size(); ++i) {
    const DofId& d = dofs[i];
    const auto it = d.component >= 1 ? turn.find(d.node) : turn.end();
    if (it == turn.end()) {
      t.emplace_back(int(i), int(i), 1.0);
      continue;
    }
    const int base = d.component <= 3 ? 1 : 4;
    for (int k = 0; k < 3; ++k) {
      // A direction the local one does not mix in is not needed (a 2D model turned about z).
      const double v = it->second(d.component - base, k);
      if (std::abs(v) <= kNoMixing) continue;
      const auto j = index.find({d.node, base + k});
      if (j == index.end()) {
        throw std::invalid_argument(
            what + ": node " + std::to_string(d.node) + " has a displacement system (CD) and " +
            "component " + std::to_string(d.component) + " but not " + std::to_string(base + k) +
            ": turning it to the basic frame needs all three of its directions");
      }
      t.emplace_back(int(i), j->second, v);
    }
  }
  Eigen::SparseMatrix<double> m(Eigen::Index(dofs.size()), Eigen::Index(dofs.size()));
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

bool Touches(const std::vector<DofId>& dofs, const std::map<int64_t, Eigen::Matrix3d>& turn) {
  for (const DofId& d : dofs) {
    if (d.component >= 1 && turn.count(d.node)) return true;
  }
  return false;
}

void TurnMatrix(const std::map<int64_t, Eigen::Matrix3d>& turn, const std::string& source,
                FeMatrix* m) {
  if (!Touches(m->row_dofs, turn) && !Touches(m->col_dofs, turn)) return;
  const std::string what = "matrix " + m->name + " of " + source;
  if (m->coordinate) {
    throw std::invalid_argument(what + " is held in coordinate form: it cannot be turned to the " +
                                "basic frame (its nodes have displacement systems, CD)");
  }
  const Eigen::SparseMatrix<double> tr = Turn(m->row_dofs, turn, what);
  const Eigen::SparseMatrix<double> tc = Turn(m->col_dofs, turn, what);
  m->real = Eigen::SparseMatrix<double>(tr.transpose() * m->real * tc);
  if (m->is_complex) m->imag = Eigen::SparseMatrix<double>(tr.transpose() * m->imag * tc);
  m->real.prune(0.0);
}

}  // namespace

void ExpressInBasic(FeModel* model, const std::vector<FeModel*>& others) {
  std::vector<FeModel*> all = {model};
  all.insert(all.end(), others.begin(), others.end());
  bool local = false;
  for (const FeModel* m : all) {
    for (const FeNode& n : m->nodes) local = local || n.position_system || n.displacement_system;
  }
  if (!local) return;
  // One geometry: the systems and nodes of every file (the first file's where ids repeat).
  FeModel geometry;
  std::map<int64_t, std::pair<FeNode, std::string>> nodes;
  for (const FeModel* m : all) {
    if (!m->source.empty()) geometry.source += (geometry.source.empty() ? "" : ", ") + m->source;
    geometry.systems.insert(geometry.systems.end(), m->systems.begin(), m->systems.end());
    for (const FeNode& n : m->nodes) nodes.emplace(n.id, std::make_pair(n, m->source));
  }
  const BasicFrame frame(geometry);
  std::map<int64_t, Eigen::Vector3d> position;
  std::map<int64_t, Eigen::Matrix3d> turn;
  for (const auto& [id, entry] : nodes) {
    const FeNode& n = entry.first;
    const std::string grid = "GRID " + std::to_string(id) + " of " + entry.second + ": ";
    try {
      position[id] = frame.ToBasic(n.position_system, n.xyz);
      if (n.displacement_system > 0) turn[id] = frame.Axes(n.displacement_system, position[id]);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(grid + e.what());
    }
    if (n.displacement_system < 0) {
      throw std::invalid_argument(grid + "CD = " + std::to_string(n.displacement_system) +
                                  " (a fluid grid) is not a structural node fricrom can use");
    }
  }
  for (FeModel* m : all) {
    for (FeMatrix& a : m->matrices) TurnMatrix(turn, m->source, &a);
    for (FeNode& n : m->nodes) {
      n.xyz = position.at(n.id);
      n.position_system = n.displacement_system = 0;
    }
  }
}

}  // namespace fricrom
