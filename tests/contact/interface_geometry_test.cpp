// Contact-interface geometry (interface_geometry.h): faces of a hand-built C3D10 element against
// closed forms (areas, A/12 and A/4 vs 0 and A/3 nodal shares, outward normals, both element
// orientations, a curved face against a fine Riemann sum), the committed coarse blade and damper
// meshes (contact strip areas, normals, node pairing and its errors), rigid placements and frames.
#include "fricrom/interface_geometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "io/io_test_util.h"
#include "test_models.h"

namespace fricrom {
namespace {

using Vec3 = Eigen::Vector3d;
using Ids = std::vector<int64_t>;
using testing::ScratchDir;

// Message of the std::invalid_argument `f` throws ("" and a test failure if none).
template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "no std::invalid_argument";
  return "";
}

// ---- One C3D10 element --------------------------------------------------------------------------

constexpr double kA = 0.02, kB = 0.03, kC = 0.01;  // tetrahedron legs along x, y, z [m]
const std::array<Vec3, 4> kCorners = {Vec3(0, 0, 0), Vec3(kA, 0, 0), Vec3(0, kB, 0),
                                      Vec3(0, 0, kC)};
// C3D10 mid-side edges (1-based corners), Abaqus order: 5 (1-2), 6 (2-3), 7 (3-1), 8 (1-4),
// 9 (2-4), 10 (3-4).
constexpr int kEdges[6][2] = {{1, 2}, {2, 3}, {3, 1}, {1, 4}, {2, 4}, {3, 4}};

// A deck with one C3D10 element whose corners are the points kCorners[order[k]] (node ids 1-4 =
// kCorners 0-3, mid-side ids 5-10 per kEdges of the geometric corners) and an NSET FACE of
// `face_nodes`. `order` = {0,1,2,3} is positively oriented, {0,2,1,3} inverted.
std::string Tet10Deck(const std::array<int, 4>& order, const Ids& face_nodes,
                      const Vec3& lift_node5 = Vec3::Zero()) {
  std::string deck = "*NODE\n";
  char line[160];
  for (int i = 0; i < 4; ++i) {
    const Vec3& x = kCorners[i];
    std::snprintf(line, sizeof line, "%d, %.17g, %.17g, %.17g\n", i + 1, x[0], x[1], x[2]);
    deck += line;
  }
  for (int e = 0; e < 6; ++e) {
    Vec3 x = 0.5 * (kCorners[kEdges[e][0] - 1] + kCorners[kEdges[e][1] - 1]);
    if (e == 0) x += lift_node5;
    std::snprintf(line, sizeof line, "%d, %.17g, %.17g, %.17g\n", e + 5, x[0], x[1], x[2]);
    deck += line;
  }
  // Element connectivity: corners in `order`, then the mid-side node of each element edge.
  const auto mid = [](int a, int b) {  // 1-based geometric corners -> mid-side node id
    for (int e = 0; e < 6; ++e) {
      if ((kEdges[e][0] == a && kEdges[e][1] == b) || (kEdges[e][0] == b && kEdges[e][1] == a)) {
        return e + 5;
      }
    }
    return -1;
  };
  std::array<int, 4> c;
  for (int k = 0; k < 4; ++k) c[k] = order[k] + 1;
  deck += "*ELEMENT, TYPE=C3D10, ELSET=E\n1";
  for (int k = 0; k < 4; ++k) deck += ", " + std::to_string(c[k]);
  constexpr int kLocalEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  for (const auto& [i, j] : kLocalEdges) deck += ", " + std::to_string(mid(c[i], c[j]));
  deck += "\n*NSET, NSET=FACE\n";
  for (size_t k = 0; k < face_nodes.size(); ++k) {
    deck += (k ? ", " : "") + std::to_string(face_nodes[k]);
  }
  return deck + "\n";
}

FeModel ReadText(const std::string& text) {
  ScratchDir dir;
  FeModel model;
  ReadInpNodesAndSets(dir.Write("tet.inp", text), model);
  return model;
}

Vec3 At(const FeModel& m, int64_t id) { return m.FindNode(id)->xyz; }

// Checks a face's node layout: mid-side k halfway between corners k and k+1, and the right-hand
// normal of the corners along `outward`.
void ExpectFaceLayout(const FeModel& m, const SurfaceFace& f, const Vec3& outward) {
  ASSERT_EQ(f.nodes.size(), 6u);
  for (int k = 0; k < 3; ++k) {
    const Vec3 half = 0.5 * (At(m, f.nodes[k]) + At(m, f.nodes[(k + 1) % 3]));
    EXPECT_LT((At(m, f.nodes[3 + k]) - half).norm(), 1e-15) << "mid-side " << k;
  }
  const Vec3 n =
      (At(m, f.nodes[1]) - At(m, f.nodes[0])).cross(At(m, f.nodes[2]) - At(m, f.nodes[0]));
  EXPECT_NEAR(n.normalized().dot(outward), 1.0, 1e-12);
}

struct FaceCase {
  const char* name;
  Ids nodes;     // the face's 6 node ids (corners, mid-sides)
  Ids corners;   // its corner ids
  Vec3 outward;  // unit outward normal
  double area;
};

std::vector<FaceCase> FaceCases() {
  const Vec3 slant = Vec3(kB * kC, kA * kC, kA * kB);
  return {
      {"z=0 face 1-2-3", {1, 2, 3, 5, 6, 7}, {1, 2, 3}, Vec3(0, 0, -1), kA * kB / 2},
      {"y=0 face 1-2-4", {1, 2, 4, 5, 8, 9}, {1, 2, 4}, Vec3(0, -1, 0), kA * kC / 2},
      {"slanted face 2-3-4", {2, 3, 4, 6, 9, 10}, {2, 3, 4}, slant.normalized(), slant.norm() / 2}};
}

TEST(InterfaceGeometry, SingleTet10FaceAreasAndNormals) {
  for (const std::array<int, 4> order : {std::array{0, 1, 2, 3}, std::array{0, 2, 1, 3}}) {
    for (const FaceCase& fc : FaceCases()) {
      SCOPED_TRACE(std::string(fc.name) + (order[1] == 1 ? ", positive element" : ", inverted"));
      const FeModel m = ReadText(Tet10Deck(order, fc.nodes));
      ASSERT_EQ(m.elements.size(), 1u);
      const std::vector<SurfaceFace> faces = FacesOnSet(m, "face");
      ASSERT_EQ(faces.size(), 1u);
      EXPECT_EQ(faces[0].element, 1);
      ExpectFaceLayout(m, faces[0], fc.outward);
      // The outward normal points away from the corner opposite the face.
      const Vec3 centroid = 0.25 * (At(m, 1) + At(m, 2) + At(m, 3) + At(m, 4));
      EXPECT_GT(fc.outward.dot(At(m, fc.corners[0]) - centroid), 0);

      const NodalFaceData sub = FaceNodalData(m, faces);
      const NodalFaceData con = FaceNodalData(m, faces, NodalAreaScheme::kConsistent);
      Ids sorted = fc.nodes;
      std::sort(sorted.begin(), sorted.end());
      EXPECT_EQ(sub.nodes, sorted);
      EXPECT_NEAR(sub.total_area, fc.area, 1e-15 * fc.area);
      EXPECT_NEAR(sub.piecewise_flat_area, fc.area, 1e-15 * fc.area);
      EXPECT_NEAR(con.total_area, fc.area, 1e-15 * fc.area);
      for (size_t i = 0; i < sub.nodes.size(); ++i) {
        const bool corner = std::count(fc.corners.begin(), fc.corners.end(), sub.nodes[i]) > 0;
        EXPECT_NEAR(sub.area[i], fc.area / (corner ? 12 : 4), 1e-14 * fc.area) << sub.nodes[i];
        EXPECT_NEAR(con.area[i], corner ? 0.0 : fc.area / 3, 1e-14 * fc.area) << sub.nodes[i];
        EXPECT_NEAR(sub.normal[i].dot(fc.outward), 1.0, 1e-14) << sub.nodes[i];
        EXPECT_LT((con.normal[i] - sub.normal[i]).norm(), 1e-15);  // normals scheme-independent
      }
    }
  }
}

TEST(InterfaceGeometry, Tet4FaceHasThirdsAndTet10FaceNeedsItsMidSideNodes) {
  const FeModel m = ReadText(
      "*NODE\n1, 0, 0, 0\n2, 0.02, 0, 0\n3, 0, 0.03, 0\n4, 0, 0, 0.01\n"
      "*ELEMENT, TYPE=C3D4\n7, 1, 2, 3, 4\n*NSET, NSET=F\n1, 2, 3\n");
  const std::vector<SurfaceFace> faces = FacesOnSet(m, "F");
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_EQ(faces[0].nodes, (Ids{1, 3, 2}));  // (1, 2, 3) would point into the element
  const NodalFaceData d = FaceNodalData(m, faces);
  for (const double a : d.area) EXPECT_NEAR(a, kA * kB / 6, 1e-18);
  // A C3D10 set with the corners but not the mid-side nodes holds no face.
  const FeModel m10 = ReadText(Tet10Deck({0, 1, 2, 3}, {1, 2, 3, 5, 6}));
  EXPECT_NE(ErrorOf([&] { FacesOnSet(m10, "FACE"); }).find("no C3D4/C3D10 element face"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { FacesOnSet(m10, "NOPE"); }).find("no node set NOPE"), std::string::npos);
}

// Node 5 (mid-side of 1-2, on the z = 0 face) lifted by h: the face z = h·4·ξ(1-ξ-η) over the
// flat triangle is curved; its area, from a fine midpoint sum of sqrt(1 + |grad z|^2), is what
// total_area and the sum of the kSubdivision areas give, while the flat sub-triangles are smaller.
TEST(InterfaceGeometry, CurvedTet10FaceAreaByQuadrature) {
  const double h = 0.004;
  const FeModel m = ReadText(Tet10Deck({0, 1, 2, 3}, {1, 2, 3, 5, 6, 7}, Vec3(0, 0, -h)));
  const std::vector<SurfaceFace> faces = FacesOnSet(m, "FACE");
  ASSERT_EQ(faces.size(), 1u);
  const NodalFaceData d = FaceNodalData(m, faces);
  const NodalFaceData c = FaceNodalData(m, faces, NodalAreaScheme::kConsistent);
  // z(x, y) = -h·4·(x/a)·(1 - x/a - y/b) on the triangle x/a + y/b <= 1.
  const int n = 1000;
  double reference = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; i + j < n; ++j) {  // midpoints of the squares inside; the diagonal halves:
      const double xi = (i + 0.5) / n, eta = (j + 0.5) / n;
      const double w = i + j == n - 1 ? 0.5 : 1.0;  // half squares on the hypotenuse
      const double dz_dxi = -4 * h * (1 - 2 * xi - eta), dz_deta = 4 * h * xi;
      const double gx = dz_dxi / kA, gy = dz_deta / kB;
      reference += w * std::sqrt(1 + gx * gx + gy * gy) * kA * kB / (double(n) * n);
    }
  }
  EXPECT_NEAR(d.total_area, reference, 2e-5 * reference);
  EXPECT_GT(d.total_area, kA * kB / 2 * (1 + 1e-3));  // really curved
  double sum_sub = 0, sum_con = 0;
  for (size_t i = 0; i < d.nodes.size(); ++i) sum_sub += d.area[i], sum_con += c.area[i];
  EXPECT_NEAR(sum_sub, d.total_area, 1e-14 * d.total_area);
  EXPECT_NEAR(sum_con, d.total_area, 1e-14 * d.total_area);
  EXPECT_LT(d.piecewise_flat_area, d.total_area * (1 - 1e-4));
  for (const Vec3& nrm : d.normal) EXPECT_LT(nrm.z(), -0.9);  // still outward (-z)
}

TEST(InterfaceGeometry, UnsupportedElementTypeInSetIsNamed) {
  FeModel m;
  m.nodes.resize(20);
  for (int i = 0; i < 20; ++i) m.nodes[i] = FeNode{i + 1, Vec3(i % 2, (i / 2) % 2, i / 4), 0, 0};
  FeElement e{3, "C3D20", {}};
  for (int i = 1; i <= 20; ++i) e.nodes.push_back(i);
  m.elements.push_back(e);
  m.node_sets.push_back({"TOP", {1, 2, 3, 4, 9, 10, 11, 12}});
  const std::string msg = ErrorOf([&] { FacesOnSet(m, "top"); });
  EXPECT_NE(msg.find("element 3 of type C3D20"), std::string::npos) << msg;
  EXPECT_NE(msg.find("TOP"), std::string::npos) << msg;
}

// ---- The committed coarse meshes -------------------------------------------------------------

using testing::kMeshes;

const FeModel& Blade() {
  static const FeModel m = [] {
    FeModel model;
    ReadInpNodesAndSets(kMeshes + "blade_sector/coarse/blade_sector_mesh.inp", model);
    return model;
  }();
  return m;
}
const FeModel& Damper() {
  static const FeModel m = [] {
    FeModel model;
    ReadInpNodesAndSets(kMeshes + "damper/coarse/damper_mesh.inp", model);
    return model;
  }();
  return m;
}

const double kStripArea = 0.03 * 0.0025 * std::sqrt(2.0);  // 1.06066e-4 m^2

TEST(InterfaceGeometry, CoarseMeshContactStripsAreasAndNormals) {
  const double r = 1 / std::sqrt(2.0);
  const std::vector<std::tuple<const FeModel*, std::string, Vec3>> cases = {
      {&Blade(), "CONTACT_LEFT", Vec3(0, -r, -r)},
      {&Blade(), "CONTACT_RIGHT", Vec3(0, r, -r)},
      {&Damper(), "CONTACT_LEFT", Vec3(0, -r, r)},
      {&Damper(), "CONTACT_RIGHT", Vec3(0, r, r)}};
  for (const auto& [model, set, normal] : cases) {
    SCOPED_TRACE(model->source + " " + set);
    const std::vector<SurfaceFace> faces = FacesOnSet(*model, set);
    EXPECT_EQ(faces.size(), 8u);  // 4 x 1 quads, two triangles each
    const NodalFaceData sub = FaceNodalData(*model, faces);
    const NodalFaceData con = FaceNodalData(*model, faces, NodalAreaScheme::kConsistent);
    Ids members = model->FindNodeSet(set)->nodes;
    std::sort(members.begin(), members.end());
    ASSERT_EQ(sub.nodes, members);  // 27 nodes, every one on a face
    EXPECT_EQ(sub.nodes.size(), 27u);
    EXPECT_NEAR(sub.total_area, kStripArea, 1e-9 * kStripArea);
    EXPECT_NEAR(sub.piecewise_flat_area, sub.total_area, 1e-6 * kStripArea);
    double sum_sub = 0, sum_con = 0;
    int zero_con = 0;
    for (size_t i = 0; i < sub.nodes.size(); ++i) {
      sum_sub += sub.area[i];
      sum_con += con.area[i];
      EXPECT_GT(sub.area[i], kStripArea / 200) << sub.nodes[i];  // every node has stiffness
      zero_con += std::abs(con.area[i]) < 1e-12 * kStripArea;
      EXPECT_LT((sub.normal[i] - normal).norm(), 1e-9) << sub.nodes[i];
    }
    EXPECT_NEAR(sum_sub, kStripArea, 1e-9 * kStripArea);
    EXPECT_NEAR(sum_con, kStripArea, 1e-9 * kStripArea);
    EXPECT_EQ(zero_con, 10);  // the 5 x 2 corner nodes of the triangles
  }
}

TEST(InterfaceGeometry, PerAreaStiffnessSumsToStiffnessTimesArea) {
  const double k_area = 2.5e13;  // N/m^3
  for (const FeModel* m : {&Blade(), &Damper()}) {
    for (const NodalAreaScheme scheme :
         {NodalAreaScheme::kSubdivision, NodalAreaScheme::kConsistent}) {
      const NodalFaceData d = FaceNodalData(*m, FacesOnSet(*m, "CONTACT_RIGHT"), scheme);
      double k_sum = 0;
      for (const double a : d.area) k_sum += k_area * a;
      EXPECT_NEAR(k_sum, k_area * d.total_area, 1e-12 * k_area * d.total_area);
      EXPECT_NEAR(k_sum, k_area * kStripArea, 1e-9 * k_area * kStripArea);
    }
  }
}

Ids SetNodes(const FeModel& m, const std::string& set) { return m.FindNodeSet(set)->nodes; }

TEST(InterfaceGeometry, PairsDamperWithBladeContactNodes) {
  const RigidTransform identity;
  const std::vector<NodePair> left =
      PairNodesByCoordinates(Damper(), SetNodes(Damper(), "CONTACT_LEFT"), identity, Blade(),
                             SetNodes(Blade(), "CONTACT_RIGHT"), identity, 1e-6);
  ASSERT_EQ(left.size(), 27u);
  std::map<int64_t, int> used_b;
  for (size_t i = 0; i < left.size(); ++i) {
    EXPECT_EQ(left[i].node_a, SetNodes(Damper(), "CONTACT_LEFT")[i]);  // nodes_a order
    EXPECT_LE(left[i].distance, 1e-12);
    EXPECT_LE((At(Damper(), left[i].node_a) - At(Blade(), left[i].node_b)).norm(), 1e-12);
    ++used_b[left[i].node_b];
  }
  EXPECT_EQ(used_b.size(), 27u);  // one-to-one

  RigidTransform next_sector;  // the next blade: this one shifted by the pitch
  next_sector.translation = Vec3(0, 0.033, 0);
  const std::vector<NodePair> right =
      PairNodesByCoordinates(Damper(), SetNodes(Damper(), "CONTACT_RIGHT"), identity, Blade(),
                             SetNodes(Blade(), "CONTACT_LEFT"), next_sector, 1e-6);
  ASSERT_EQ(right.size(), 27u);
  for (const NodePair& p : right) {
    EXPECT_LE(p.distance, 1e-12);
    EXPECT_NEAR(At(Damper(), p.node_a).y() - At(Blade(), p.node_b).y(), 0.033, 1e-12);
  }
}

TEST(InterfaceGeometry, PairingErrorsNameTheNodes) {
  const RigidTransform identity;
  const Ids damper_right = SetNodes(Damper(), "CONTACT_RIGHT");
  const Ids blade_left = SetNodes(Blade(), "CONTACT_LEFT");
  // Without the pitch shift nothing meets: the damper's right face is 0.033 m from the blade's.
  std::string msg = ErrorOf([&] {
    PairNodesByCoordinates(Damper(), damper_right, identity, Blade(), blade_left, identity, 1e-6);
  });
  EXPECT_NE(msg.find("27 of 27 nodes of side a and 27 of 27 nodes of side b have no partner"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("side a node " + std::to_string(damper_right[0]) + " at ("), std::string::npos)
      << msg;
  EXPECT_NE(msg.find("at 0.033 m"), std::string::npos) << msg;         // nearest candidate distance
  EXPECT_NE(msg.find("17 more of side a"), std::string::npos) << msg;  // 10 listed

  // A tolerance wider than the node spacing (0.00375 m along x): two candidates.
  RigidTransform shift;
  shift.translation = Vec3(0, 0.033, 0);
  msg = ErrorOf([&] {
    PairNodesByCoordinates(Damper(), damper_right, identity, Blade(), blade_left, shift, 0.005);
  });
  EXPECT_NE(msg.find("matches two"), std::string::npos) << msg;

  // One node of side b too many: the blade's EXCITATION node 11 is named as unmatched.
  Ids blade_plus = SetNodes(Blade(), "CONTACT_RIGHT");
  blade_plus.push_back(11);
  msg = ErrorOf([&] {
    PairNodesByCoordinates(Damper(), SetNodes(Damper(), "CONTACT_LEFT"), identity, Blade(),
                           blade_plus, identity, 1e-6);
  });
  EXPECT_NE(msg.find("0 of 27 nodes of side a and 1 of 28 nodes of side b"), std::string::npos)
      << msg;
  EXPECT_NE(msg.find("side b node 11 at (-0.0114906666, -0.00964181415, 0.069)"), std::string::npos)
      << msg;

  // Unknown node, node listed twice, bad tolerance, bad placement.
  EXPECT_NE(ErrorOf([&] {
              PairNodesByCoordinates(Damper(), {1, 999999}, identity, Blade(), {1}, identity, 1e-6);
            }).find("node 999999 is not in the model"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              PairNodesByCoordinates(Damper(), {1, 1}, identity, Blade(), {1}, identity, 1e-6);
            }).find("node 1 is listed twice"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              PairNodesByCoordinates(Damper(), {1}, identity, Blade(), {1}, identity, 0.0);
            }).find("tolerance must be > 0"),
            std::string::npos);
  RigidTransform mirror;
  mirror.rotation(2, 2) = -1;
  EXPECT_NE(ErrorOf([&] {
              PairNodesByCoordinates(Damper(), {1}, identity, Blade(), {1}, mirror, 1e-6);
            }).find("invalid placement"),
            std::string::npos);
}

// 10^5 nodes of a jittered grid; side b holds the same points with other ids, in another order,
// stored rotated and shifted, and placed back by the inverse transform: every node finds its twin.
TEST(InterfaceGeometry, PairsOneHundredThousandNodesThroughRotation) {
  const int n = 100'000;
  const RigidTransform stored =
      RigidTransform::FromAxisAngle(Vec3(1, 2, 3), 0.7, Vec3(0.1, 0, 0), Vec3(0.5, -0.2, 0.3));
  RigidTransform back;
  back.rotation = stored.rotation.transpose();
  back.translation = -back.rotation * stored.translation;
  FeModel a, b;
  Ids ids_a, ids_b;
  for (int i = 0; i < n; ++i) {
    const Vec3 x =
        1e-3 * Vec3(i % 50, (i / 50) % 40, i / 2000) + 1e-5 * Vec3(std::sin(i), std::cos(i), 0);
    a.nodes.push_back(FeNode{i + 1, x, 0, 0});
    ids_a.push_back(i + 1);
    const int64_t twin = 1'000'000 + 7 * int64_t{(i * 7919) % n};  // 7919 prime: a permutation
    b.nodes.push_back(FeNode{twin, stored.Apply(x), 0, 0});
    ids_b.push_back(twin);
  }
  std::reverse(ids_b.begin(), ids_b.end());
  const std::vector<NodePair> pairs =
      PairNodesByCoordinates(a, ids_a, RigidTransform(), b, ids_b, back, 1e-4);
  ASSERT_EQ(pairs.size(), size_t{n});
  for (int i = 0; i < n; ++i) {
    ASSERT_EQ(pairs[i].node_a, i + 1);
    ASSERT_EQ(pairs[i].node_b, 1'000'000 + 7 * int64_t{(i * 7919) % n}) << i;
    ASSERT_LT(pairs[i].distance, 1e-15);
  }
}

// ---- Placements and frames -------------------------------------------------------------------

TEST(InterfaceGeometry, RigidTransformRotatesAboutCentre) {
  const RigidTransform t = RigidTransform::FromAxisAngle(Vec3(0, 0, 3), std::acos(-1.0) / 2,
                                                         Vec3(1, 2, 0), Vec3(0, 0, 1));
  // (2, 2, 5) is (1, 0, 5) from the centre; turned 90 deg about z: (0, 1, 5); + centre + shift.
  EXPECT_LT((t.Apply(Vec3(2, 2, 5)) - Vec3(1, 3, 6)).norm(), 1e-15);
  EXPECT_LT((t.Apply(Vec3(1, 2, 0)) - Vec3(1, 2, 1)).norm(), 1e-15);  // the centre stays
  std::string error = "unset";
  EXPECT_TRUE(t.IsValid(&error));
  EXPECT_EQ(error, "");

  RigidTransform scaled;
  scaled.rotation *= 1.001;
  EXPECT_FALSE(scaled.IsValid(&error));
  EXPECT_NE(error.find("not orthonormal"), std::string::npos) << error;
  RigidTransform mirror;
  mirror.rotation(0, 0) = -1;
  EXPECT_FALSE(mirror.IsValid(&error));
  EXPECT_NE(error.find("reflection"), std::string::npos) << error;
  RigidTransform nan;
  nan.translation.x() = std::nan("");
  EXPECT_FALSE(nan.IsValid(nullptr));
  EXPECT_NE(ErrorOf([] {
              RigidTransform::FromAxisAngle(Vec3::Zero(), 1, Vec3::Zero(), Vec3::Zero());
            }).find("no direction"),
            std::string::npos);
}

void ExpectRightHandedOrthonormal(const ContactFrame& f) {
  Eigen::Matrix3d m;
  m << f.normal, f.tangent1, f.tangent2;
  EXPECT_LT((m.transpose() * m - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_NEAR(m.determinant(), 1.0, 1e-14);
}

TEST(InterfaceGeometry, ContactFrameFollowsPreferredTangent) {
  const ContactFrame f = MakeContactFrame(Vec3(0, 0, 2), Vec3(1, 1, 1));
  ExpectRightHandedOrthonormal(f);
  EXPECT_LT((f.normal - Vec3(0, 0, 1)).norm(), 1e-15);
  EXPECT_LT((f.tangent1 - Vec3(1, 1, 0).normalized()).norm(), 1e-15);
  EXPECT_LT((f.tangent2 - Vec3(-1, 1, 0).normalized()).norm(), 1e-15);

  // Blade CONTACT_RIGHT normal, a tangent with a part along n: t1 = x, t2 = n x x.
  const Vec3 n = Vec3(0, 1, -1).normalized();
  const ContactFrame g = MakeContactFrame(n, Vec3(1, 0.3, -0.3));
  ExpectRightHandedOrthonormal(g);
  EXPECT_LT((g.tangent1 - Vec3(1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((g.tangent2 - Vec3(0, -1, -1).normalized()).norm(), 1e-15);
}

TEST(InterfaceGeometry, ContactFrameFallsBackWhenTangentParallelOrZero) {
  const Vec3 n = Vec3(0.1, 0.9, 0.3).normalized();  // least aligned with the x axis
  for (const Vec3& pref : {Vec3(n * 5), Vec3(n * 5 + Vec3(1e-8, 0, 0)), Vec3(Vec3::Zero())}) {
    const ContactFrame f = MakeContactFrame(n, pref);
    ExpectRightHandedOrthonormal(f);
    const Vec3 expected = (Vec3::UnitX() - n.x() * n).normalized();
    EXPECT_LT((f.tangent1 - expected).norm(), 1e-12) << pref.transpose();
  }
  // Just above the threshold the preferred direction still counts.
  const Vec3 pref = n + 1e-4 * Vec3(0, 0.3, -0.9).normalized();
  const ContactFrame f = MakeContactFrame(n, pref);
  EXPECT_LT((f.tangent1 - Vec3(0, 0.3, -0.9).normalized()).norm(), 1e-6);
  EXPECT_NE(ErrorOf([] { MakeContactFrame(Vec3::Zero(), Vec3::UnitX()); }).find("no direction"),
            std::string::npos);
}

}  // namespace
}  // namespace fricrom
