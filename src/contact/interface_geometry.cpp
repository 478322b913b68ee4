// Contact-interface geometry of FE bodies: faces of C3D4/C3D10 elements on a node set, nodal areas
// and normals (tri3/tri6 isoparametric faces), node pairing by placed coordinates, contact frames.
#include "fricrom/interface_geometry.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace fricrom {

namespace {

using Vec3 = Eigen::Vector3d;

[[noreturn]] void Throw(const std::string& what) { throw std::invalid_argument(what); }

std::string FormatG9(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string Point(const Vec3& x) {
  char buf[96];  // one call: g++ 12 -O3 -march=x86-64-v3 takes "(" + std::string for an overflow
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", x[0], x[1], x[2]);
  return buf;
}

std::string Source(const FeModel& m) { return m.source.empty() ? "" : " (" + m.source + ")"; }

// Node id -> coordinates; FeModel::FindNode is a linear search.
class NodeCoordinates {
 public:
  explicit NodeCoordinates(const FeModel& model) : model_(model) {
    index_.reserve(model.nodes.size());
    for (size_t i = 0; i < model.nodes.size(); ++i) index_.emplace(model.nodes[i].id, i);
  }
  // Throws naming `context` when the node is unknown or has non-finite coordinates.
  const Vec3& At(int64_t id, const std::string& context) const {
    const auto it = index_.find(id);
    if (it == index_.end())
      Throw(context + ": node " + std::to_string(id) + " is not in the model" + Source(model_));
    const Vec3& x = model_.nodes[it->second].xyz;
    if (!x.allFinite())
      Throw(context + ": node " + std::to_string(id) + " has non-finite coordinates");
    return x;
  }

 private:
  const FeModel& model_;
  std::unordered_map<int64_t, size_t> index_;
};

// ---- Faces of tetrahedra -------------------------------------------------------------------

// Corners of each face (0-based) and the corner opposite it.
struct TetFace {
  std::array<int, 3> corner;
  int opposite;
};
constexpr std::array<TetFace, 4> kTetFaces = {
    {{{0, 1, 2}, 3}, {{0, 1, 3}, 2}, {{1, 2, 3}, 0}, {{0, 2, 3}, 1}}};

// C3D10 local index of the mid-side node of edge (i, j): 4 (0-1), 5 (1-2), 6 (2-0), 7 (0-3),
// 8 (1-3), 9 (2-3).
int MidSide(int i, int j) {
  if (i > j) std::swap(i, j);
  if (j == 3) return 7 + i;
  return i == 0 ? (j == 1 ? 4 : 6) : 5;
}

// The face of element `e` with corners `f.corner`, ordered so its right-hand normal points away
// from the opposite corner.
SurfaceFace OrientedFace(const FeElement& e, const TetFace& f, bool quadratic,
                         const NodeCoordinates& xyz) {
  std::array<int, 3> c = f.corner;
  const std::string ctx = "FacesOnSet: element " + std::to_string(e.id);
  const Vec3& x0 = xyz.At(e.nodes[c[0]], ctx);
  const Vec3 n = (xyz.At(e.nodes[c[1]], ctx) - x0).cross(xyz.At(e.nodes[c[2]], ctx) - x0);
  const double side = n.dot(xyz.At(e.nodes[f.opposite], ctx) - x0);
  if (!(side != 0.0)) Throw(ctx + " (" + e.type + ") is degenerate (zero volume)");
  if (side > 0) std::swap(c[1], c[2]);  // the normal pointed into the element
  SurfaceFace face{e.id, {e.nodes[c[0]], e.nodes[c[1]], e.nodes[c[2]]}};
  if (quadratic) {
    for (int k = 0; k < 3; ++k) face.nodes.push_back(e.nodes[MidSide(c[k], c[(k + 1) % 3])]);
  }
  return face;
}

std::array<int64_t, 3> SortedCorners(const SurfaceFace& f) {
  std::array<int64_t, 3> k = {f.nodes[0], f.nodes[1], f.nodes[2]};
  std::sort(k.begin(), k.end());
  return k;
}

// ---- Isoparametric triangles -----------------------------------------------------------------

// Shape functions and their derivatives at (xi, eta) of a tri3 (n = 3) or tri6 (n = 6) with the
// node order of SurfaceFace; area coordinates L = (1 - xi - eta, xi, eta).
void Shape(int n, double xi, double eta, double* N, double* dxi, double* deta) {
  const double L[3] = {1 - xi - eta, xi, eta};
  const double dL_dxi[3] = {-1, 1, 0}, dL_deta[3] = {-1, 0, 1};
  for (int i = 0; i < 3; ++i) {
    const double f = n == 3 ? 1.0 : 4 * L[i] - 1;  // d(L(2L-1))/dL = 4L-1
    N[i] = n == 3 ? L[i] : L[i] * (2 * L[i] - 1);
    dxi[i] = f * dL_dxi[i];
    deta[i] = f * dL_deta[i];
  }
  for (int k = 0; n == 6 && k < 3; ++k) {
    const int i = k, j = (k + 1) % 3;
    N[3 + k] = 4 * L[i] * L[j];
    dxi[3 + k] = 4 * (dL_dxi[i] * L[j] + L[i] * dL_dxi[j]);
    deta[3 + k] = 4 * (dL_deta[i] * L[j] + L[i] * dL_deta[j]);
  }
}

// 7-point rule of degree 5 on the triangle (Dunavant): area coordinates and weights summing to 1.
struct TriRule {
  std::array<std::array<double, 3>, 7> L;
  std::array<double, 7> w;
};
const TriRule& Rule7() {
  static const TriRule rule = [] {
    const double s = std::sqrt(15.0);
    const double a1 = (6 - s) / 21, b1 = 1 - 2 * a1, w1 = (155 - s) / 1200;
    const double a2 = (6 + s) / 21, b2 = 1 - 2 * a2, w2 = (155 + s) / 1200;
    TriRule r;
    r.L = {{{1.0 / 3, 1.0 / 3, 1.0 / 3},
            {a1, a1, b1},
            {a1, b1, a1},
            {b1, a1, a1},
            {a2, a2, b2},
            {a2, b2, a2},
            {b2, a2, a2}}};
    r.w = {9.0 / 40, w1, w1, w1, w2, w2, w2};
    return r;
  }();
  return rule;
}

// Parametric (xi, eta) of the face's local nodes; sub-triangles of a tri6 (corner 0, 1, 2, centre)
// as local nodes, counter-clockwise in (xi, eta) like the face.
constexpr double kNodeXi[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
constexpr int kSubTriangles[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};

// Integrals over the part of the face given by parametric triangle `sub` (local nodes): its area
// and the integrals of the shape functions times the area element (added to `shape_integral`).
double IntegrateSub(const Eigen::Matrix<double, 3, Eigen::Dynamic>& X, const int sub[3],
                    double* shape_integral) {
  const int n = static_cast<int>(X.cols());
  const TriRule& rule = Rule7();
  const double* p[3] = {kNodeXi[sub[0]], kNodeXi[sub[1]], kNodeXi[sub[2]]};
  const double jac = std::abs((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
                              (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]));  // d(xi,eta)/d(s,t)
  double area = 0;
  for (size_t q = 0; q < rule.w.size(); ++q) {
    const auto& L = rule.L[q];
    const double xi = L[0] * p[0][0] + L[1] * p[1][0] + L[2] * p[2][0];
    const double eta = L[0] * p[0][1] + L[1] * p[1][1] + L[2] * p[2][1];
    double N[6], dxi[6], deta[6];
    Shape(n, xi, eta, N, dxi, deta);
    Vec3 gxi = Vec3::Zero(), geta = Vec3::Zero();
    for (int i = 0; i < n; ++i) {
      gxi += dxi[i] * X.col(i);
      geta += deta[i] * X.col(i);
    }
    const double dA = 0.5 * rule.w[q] * jac * gxi.cross(geta).norm();  // reference area 1/2
    area += dA;
    for (int i = 0; i < n; ++i) shape_integral[i] += N[i] * dA;
  }
  return area;
}

struct FaceIntegrals {
  double area = 0, flat_area = 0;
  double subdivision[6] = {}, consistent[6] = {};
  Vec3 vector_area[6];  // flat sub-triangles' outward vector areas shared to their nodes
};

FaceIntegrals IntegrateFace(const Eigen::Matrix<double, 3, Eigen::Dynamic>& X) {
  FaceIntegrals f;
  const int n = static_cast<int>(X.cols());
  for (Vec3& v : f.vector_area) v.setZero();
  const int tri3[1][3] = {{0, 1, 2}};
  const int num_sub = n == 6 ? 4 : 1;
  for (int s = 0; s < num_sub; ++s) {
    const int* sub = n == 6 ? kSubTriangles[s] : tri3[0];
    const double a = IntegrateSub(X, sub, f.consistent);
    const Vec3 va = 0.5 * (X.col(sub[1]) - X.col(sub[0])).cross(X.col(sub[2]) - X.col(sub[0]));
    f.area += a;
    f.flat_area += va.norm();
    for (int k = 0; k < 3; ++k) {
      f.subdivision[sub[k]] += a / 3;
      f.vector_area[sub[k]] += va / 3;
    }
  }
  return f;
}

// ---- Pairing ---------------------------------------------------------------------------------

struct Placed {
  int64_t id;
  Vec3 x;
};

std::vector<Placed> PlaceNodes(const FeModel& model, const std::vector<int64_t>& ids,
                               const RigidTransform& place, const std::string& side) {
  const std::string ctx = "PairNodesByCoordinates, " + side;
  std::string error;
  if (!place.IsValid(&error)) Throw(ctx + ": invalid placement: " + error);
  const NodeCoordinates xyz(model);
  std::unordered_set<int64_t> seen;
  std::vector<Placed> out;
  out.reserve(ids.size());
  for (const int64_t id : ids) {
    if (!seen.insert(id).second) Throw(ctx + ": node " + std::to_string(id) + " is listed twice");
    out.push_back({id, place.Apply(xyz.At(id, ctx))});
  }
  if (out.empty()) Throw(ctx + ": no nodes given");
  return out;
}

using CellKey = std::array<int64_t, 3>;

// Uniform grid over the points of side b, cells at least `tolerance` wide (so a partner lies in
// the 27 cells around a point) and at most 1e9 per axis (keys stay in range for any tolerance).
class PointGrid {
 public:
  PointGrid(const std::vector<Placed>& a, const std::vector<Placed>& b, double tolerance) {
    Vec3 lo = b.front().x, hi = b.front().x;
    for (const auto* side : {&a, &b}) {
      for (const Placed& p : *side) {
        lo = lo.cwiseMin(p.x);
        hi = hi.cwiseMax(p.x);
      }
    }
    origin_ = lo;
    cell_ = std::max(tolerance, 1e-9 * (hi - lo).maxCoeff());
    keys_.reserve(b.size());
    for (size_t i = 0; i < b.size(); ++i) keys_.emplace_back(Key(b[i].x), i);
    std::sort(keys_.begin(), keys_.end());
  }
  // Calls f(index of b) for every point of b in the cells around x.
  template <typename F>
  void ForNear(const Vec3& x, F&& f) const {
    const CellKey k = Key(x);
    for (int64_t dx = -1; dx <= 1; ++dx) {
      for (int64_t dy = -1; dy <= 1; ++dy) {
        for (int64_t dz = -1; dz <= 1; ++dz) {
          const CellKey c = {k[0] + dx, k[1] + dy, k[2] + dz};
          auto it = std::lower_bound(keys_.begin(), keys_.end(), std::make_pair(c, size_t{0}));
          for (; it != keys_.end() && it->first == c; ++it) f(it->second);
        }
      }
    }
  }

 private:
  CellKey Key(const Vec3& x) const {
    CellKey k;
    for (int d = 0; d < 3; ++d)
      k[d] = static_cast<int64_t>(std::floor((x[d] - origin_[d]) / cell_));
    return k;
  }
  Vec3 origin_;
  double cell_ = 1;
  std::vector<std::pair<CellKey, size_t>> keys_;
};

// "node 5 at (x, y, z), nearest node of side b: 7 at 0.033 m" (brute force: only for the few
// nodes an error message lists).
std::string DescribeUnmatched(const Placed& p, const std::vector<Placed>& other,
                              const std::string& other_side) {
  size_t best = 0;
  double d = std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < other.size(); ++j) {
    const double dj = (other[j].x - p.x).norm();
    if (dj < d) d = dj, best = j;
  }
  return "node " + std::to_string(p.id) + " at " + Point(p.x) + ", nearest node of " + other_side +
         ": " + std::to_string(other[best].id) + " at " + FormatG9(d) + " m";
}

constexpr size_t kMaxListed = 10;

[[noreturn]] void ThrowUnmatched(const std::vector<Placed>& a, const std::vector<Placed>& b,
                                 const std::vector<size_t>& lost_a,
                                 const std::vector<size_t>& lost_b, double tolerance) {
  std::string msg = "PairNodesByCoordinates: " + std::to_string(lost_a.size()) + " of " +
                    std::to_string(a.size()) + " nodes of side a and " +
                    std::to_string(lost_b.size()) + " of " + std::to_string(b.size()) +
                    " nodes of side b have no partner within the tolerance " + FormatG9(tolerance) +
                    " m (coordinates after the placements):";
  for (size_t k = 0; k < lost_a.size() && k < kMaxListed; ++k) {
    msg += "\n  side a " + DescribeUnmatched(a[lost_a[k]], b, "side b");
  }
  if (lost_a.size() > kMaxListed)
    msg += "\n  ... (" + std::to_string(lost_a.size() - kMaxListed) + " more of side a)";
  for (size_t k = 0; k < lost_b.size() && k < kMaxListed; ++k) {
    msg += "\n  side b " + DescribeUnmatched(b[lost_b[k]], a, "side a");
  }
  if (lost_b.size() > kMaxListed)
    msg += "\n  ... (" + std::to_string(lost_b.size() - kMaxListed) + " more of side b)";
  Throw(msg);
}

}  // namespace

// ---- RigidTransform ----------------------------------------------------------------------------

RigidTransform RigidTransform::FromAxisAngle(const Vec3& axis, double angle_rad, const Vec3& centre,
                                             const Vec3& translation) {
  const double len = axis.norm();
  if (!(len > 0) || !std::isfinite(len)) {
    Throw("RigidTransform::FromAxisAngle: the axis " + Point(axis) + " has no direction");
  }
  if (!std::isfinite(angle_rad) || !centre.allFinite() || !translation.allFinite()) {
    Throw("RigidTransform::FromAxisAngle: non-finite angle, centre or translation");
  }
  RigidTransform t;
  t.rotation = Eigen::AngleAxisd(angle_rad, axis / len).toRotationMatrix();
  t.translation = centre - t.rotation * centre + translation;  // x' = R (x - c) + c + translation
  return t;
}

bool RigidTransform::IsValid(std::string* error) const {
  std::string why;
  if (!rotation.allFinite() || !translation.allFinite()) {
    why = "non-finite rotation or translation";
  } else if (const double off = (rotation.transpose() * rotation - Eigen::Matrix3d::Identity())
                                    .cwiseAbs()
                                    .maxCoeff();
             off > 1e-9) {
    why = "rotation is not orthonormal (|R^T R - I| = " + FormatG9(off) + " > 1e-9)";
  } else if (rotation.determinant() < 0) {
    why = "rotation has determinant -1 (a reflection)";
  }
  if (error) *error = why;
  return why.empty();
}

// ---- Faces -------------------------------------------------------------------------------------

std::vector<SurfaceFace> FacesOnSet(const FeModel& model, const std::string& set) {
  const NodeSet* s = model.FindNodeSet(set);
  if (!s) Throw("FacesOnSet: no node set " + set + " in the model" + Source(model));
  const std::unordered_set<int64_t> members(s->nodes.begin(), s->nodes.end());
  const NodeCoordinates xyz(model);
  const auto in_set = [&](int64_t n) { return members.count(n) > 0; };
  std::vector<SurfaceFace> faces;
  for (const FeElement& e : model.elements) {
    const bool tet4 = e.type == "C3D4", tet10 = e.type == "C3D10";
    if (!tet4 && !tet10) {
      if (std::count_if(e.nodes.begin(), e.nodes.end(), in_set) >= 3) {
        Throw("FacesOnSet: element " + std::to_string(e.id) + " of type " + e.type +
              " has nodes in set " + s->name + "; faces are supported for C3D4 and C3D10 only");
      }
      continue;
    }
    if (e.nodes.size() != (tet4 ? 4u : 10u)) {
      Throw("FacesOnSet: element " + std::to_string(e.id) + " of type " + e.type + " has " +
            std::to_string(e.nodes.size()) + " nodes");
    }
    for (const TetFace& f : kTetFaces) {
      bool on = true;
      for (int k = 0; k < 3 && on; ++k) {
        on = in_set(e.nodes[f.corner[k]]) &&
             (tet4 || in_set(e.nodes[MidSide(f.corner[k], f.corner[(k + 1) % 3])]));
      }
      if (on) faces.push_back(OrientedFace(e, f, tet10, xyz));
    }
  }
  // A face of two elements is inside the body, not on its surface.
  std::map<std::array<int64_t, 3>, int> count;
  for (const SurfaceFace& f : faces) ++count[SortedCorners(f)];
  std::erase_if(faces, [&](const SurfaceFace& f) { return count[SortedCorners(f)] > 1; });
  if (faces.empty()) {
    Throw("FacesOnSet: no C3D4/C3D10 element face has all its nodes in set " + s->name + " (" +
          std::to_string(s->nodes.size()) + " nodes, " + std::to_string(model.elements.size()) +
          " elements in the model" + Source(model) + ")");
  }
  return faces;
}

NodalFaceData FaceNodalData(const FeModel& model, const std::vector<SurfaceFace>& faces,
                            NodalAreaScheme scheme) {
  if (faces.empty()) Throw("FaceNodalData: no faces given");
  const NodeCoordinates xyz(model);
  NodalFaceData out;
  std::unordered_map<int64_t, size_t> slot;
  for (const SurfaceFace& f : faces) {
    for (const int64_t n : f.nodes) slot.emplace(n, 0);
  }
  out.nodes.reserve(slot.size());
  for (const auto& [n, unused] : slot) out.nodes.push_back(n);
  std::sort(out.nodes.begin(), out.nodes.end());
  for (size_t i = 0; i < out.nodes.size(); ++i) slot[out.nodes[i]] = i;
  out.area.assign(out.nodes.size(), 0.0);
  std::vector<Vec3> vector_area(out.nodes.size(), Vec3::Zero());
  for (const SurfaceFace& f : faces) {
    const std::string ctx = "FaceNodalData: face of element " + std::to_string(f.element);
    const int n = static_cast<int>(f.nodes.size());
    if (n != 3 && n != 6) Throw(ctx + " has " + std::to_string(n) + " nodes, expected 3 or 6");
    Eigen::Matrix<double, 3, Eigen::Dynamic> X(3, n);
    for (int i = 0; i < n; ++i) X.col(i) = xyz.At(f.nodes[i], ctx);
    const FaceIntegrals fi = IntegrateFace(X);
    if (!(fi.area > 0)) Throw(ctx + " has zero area (coincident nodes?)");
    out.total_area += fi.area;
    out.piecewise_flat_area += fi.flat_area;
    const double* share = scheme == NodalAreaScheme::kConsistent ? fi.consistent : fi.subdivision;
    for (int i = 0; i < n; ++i) {
      out.area[slot[f.nodes[i]]] += share[i];
      vector_area[slot[f.nodes[i]]] += fi.vector_area[i];
    }
  }
  out.normal.resize(out.nodes.size());
  for (size_t i = 0; i < out.nodes.size(); ++i) {
    const double len = vector_area[i].norm();
    // Opposite faces cancel at a node only on a folded surface (a set around a thin edge).
    if (!(len > 1e-12 * out.total_area)) {
      Throw("FaceNodalData: the faces around node " + std::to_string(out.nodes[i]) +
            " have no net normal (faces of opposite sides of a thin part?)");
    }
    out.normal[i] = vector_area[i] / len;
  }
  return out;
}

// ---- Pairing -----------------------------------------------------------------------------------

std::vector<NodePair> PairNodesByCoordinates(const FeModel& model_a,
                                             const std::vector<int64_t>& nodes_a,
                                             const RigidTransform& place_a, const FeModel& model_b,
                                             const std::vector<int64_t>& nodes_b,
                                             const RigidTransform& place_b, double tolerance) {
  if (!(tolerance > 0) || !std::isfinite(tolerance)) {
    Throw("PairNodesByCoordinates: the tolerance must be > 0 and finite, got " +
          FormatG9(tolerance));
  }
  const std::vector<Placed> a = PlaceNodes(model_a, nodes_a, place_a, "side a" + Source(model_a));
  const std::vector<Placed> b = PlaceNodes(model_b, nodes_b, place_b, "side b" + Source(model_b));
  const PointGrid grid(a, b, tolerance);
  constexpr size_t kNone = std::numeric_limits<size_t>::max();
  std::vector<size_t> partner(a.size(), kNone), taken_by(b.size(), kNone);
  std::vector<size_t> lost_a;
  std::string twice;
  size_t num_twice = 0;
  const auto note_twice = [&](const std::string& line) {
    if (num_twice++ < kMaxListed) twice += "\n  " + line;
  };
  for (size_t i = 0; i < a.size(); ++i) {
    std::vector<size_t> near;
    grid.ForNear(a[i].x, [&](size_t j) {
      if (near.size() < 2 && (b[j].x - a[i].x).norm() <= tolerance) near.push_back(j);
    });
    if (near.empty()) {
      lost_a.push_back(i);
      continue;
    }
    if (near.size() > 1) {
      note_twice("side a node " + std::to_string(a[i].id) + " at " + Point(a[i].x) +
                 " matches two nodes of side b: " + std::to_string(b[near[0]].id) + " and " +
                 std::to_string(b[near[1]].id));
      continue;
    }
    partner[i] = near[0];
    if (taken_by[near[0]] != kNone) {
      note_twice("side b node " + std::to_string(b[near[0]].id) + " at " + Point(b[near[0]].x) +
                 " matches two nodes of side a: " + std::to_string(a[taken_by[near[0]]].id) +
                 " and " + std::to_string(a[i].id));
    }
    taken_by[near[0]] = i;
  }
  if (num_twice > 0) {
    Throw("PairNodesByCoordinates: " + std::to_string(num_twice) +
          " nodes are not one-to-one within the tolerance " + FormatG9(tolerance) +
          " m (a smaller tolerance separates them):" + twice);
  }
  std::vector<size_t> lost_b;
  for (size_t j = 0; j < b.size(); ++j) {
    if (taken_by[j] == kNone) lost_b.push_back(j);
  }
  if (!lost_a.empty() || !lost_b.empty()) ThrowUnmatched(a, b, lost_a, lost_b, tolerance);
  std::vector<NodePair> pairs(a.size());
  for (size_t i = 0; i < a.size(); ++i) {
    pairs[i] = {a[i].id, b[partner[i]].id, (a[i].x - b[partner[i]].x).norm()};
  }
  return pairs;
}

// ---- Frames ------------------------------------------------------------------------------------

ContactFrame MakeContactFrame(const Vec3& normal, const Vec3& preferred_tangent) {
  const double len = normal.norm();
  if (!(len > 0) || !std::isfinite(len)) {
    Throw("MakeContactFrame: the normal " + Point(normal) + " has no direction");
  }
  if (!preferred_tangent.allFinite()) {
    Throw("MakeContactFrame: non-finite preferred tangent " + Point(preferred_tangent));
  }
  ContactFrame f;
  f.normal = normal / len;
  Vec3 t = preferred_tangent - preferred_tangent.dot(f.normal) * f.normal;
  if (!(t.norm() > 1e-6 * preferred_tangent.norm())) {  // zero or (nearly) parallel to n
    Eigen::Index axis = 0;
    f.normal.cwiseAbs().minCoeff(&axis);
    const Vec3 e = Vec3::Unit(axis);
    t = e - e.dot(f.normal) * f.normal;
  }
  f.tangent1 = t.normalized();
  f.tangent2 = f.normal.cross(f.tangent1);
  return f;
}

}  // namespace fricrom
