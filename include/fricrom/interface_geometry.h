// Geometry of node-to-node contact interfaces between FE bodies: the element faces lying in a node
// set, nodal areas and normals of those faces, node pairs of two facing sets (after rigid
// placements of the bodies) and local contact frames. Every function throws
// std::invalid_argument naming the nodes, elements or sets involved; none prints.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"

namespace fricrom {

// A rigid placement x' = rotation * x + translation (rotation orthonormal, det +1).
struct RigidTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d Apply(const Eigen::Vector3d& x) const { return rotation * x + translation; }
  // From an axis (any length > 0) and an angle [rad] about it through `centre`, then `translation`.
  static RigidTransform FromAxisAngle(const Eigen::Vector3d& axis, double angle_rad,
                                      const Eigen::Vector3d& centre,
                                      const Eigen::Vector3d& translation);
  bool IsValid(std::string* error) const;  // orthonormal to 1e-9, det +1, finite
};

// One face of a solid element lying in a node set: 3 corner nodes then (for quadratic faces) the
// 3 mid-side nodes (mid-side k between corners k and k+1 mod 3), ordered so that the right-hand
// normal points OUT of the element.
struct SurfaceFace {
  int64_t element = 0;
  std::vector<int64_t> nodes;  // 3 (linear) or 6 (quadratic)
};

// Faces of the model's solid elements (C3D4, C3D10; others -> std::invalid_argument naming the
// element type) whose nodes all belong to `set`. Throws if the set is unknown or has no face.
// A face shared by two elements of the set is interior and left out. Order: element order, then
// the element's faces opposite corners 4, 3, 1, 2.
std::vector<SurfaceFace> FacesOnSet(const FeModel& model, const std::string& set);

enum class NodalAreaScheme {
  // Each quadratic triangle split into its 4 sub-triangles by the mid-side nodes, each
  // sub-triangle's (true, curved-geometry) area shared equally by its 3 nodes: on a flat face
  // corner A/12, mid-side A/4. Every node gets a positive area. Default.
  // (Each sub-triangle's area is integrated over its part of the isoparametric face, so the
  // areas sum to total_area; piecewise_flat_area is the flat sub-triangles' sum, equal on flat
  // faces with mid-side nodes at mid-edge.) Linear triangles: A/3 per node.
  kSubdivision,
  // Consistent nodal forces of a uniform pressure (quadratic shape functions integrated,
  // flat tri6: corner 0, mid-side A/3; linear tri3: A/3 each).
  kConsistent,
};

struct NodalFaceData {
  std::vector<int64_t> nodes;           // every node of the faces, ascending id
  std::vector<double> area;             // per node [m^2]; sums to the faces' area
  std::vector<Eigen::Vector3d> normal;  // per node, area-weighted outward unit normal
  double total_area = 0.0;              // area of the faces (curved, by quadrature) [m^2]
  // Area of the faces' flat sub-triangles (4 per quadratic face, the face itself if linear)
  // [m^2]: a check on total_area, equal to it on flat faces with straight edges.
  double piecewise_flat_area = 0.0;
};
// Nodal normals do not depend on `scheme`: each node's normal is the sum of the vector areas
// (outward normal x area) of the flat sub-triangles it belongs to, normalised, so corner nodes
// get one under kConsistent as well. Throws if a face's node is unknown or a face degenerate.
NodalFaceData FaceNodalData(const FeModel& model, const std::vector<SurfaceFace>& faces,
                            NodalAreaScheme scheme = NodalAreaScheme::kSubdivision);

struct NodePair {
  int64_t node_a = 0, node_b = 0;
  double distance = 0.0;  // |x_a' - x_b'| after the placements [m]
};
// Pairs every node of `nodes_a` (coordinates from model_a placed by place_a) with the node of
// `nodes_b` (model_b, place_b) within `tolerance` [m]. One-to-one: throws std::invalid_argument
// listing (up to 10) unmatched nodes of either side with their placed coordinates and the nearest
// candidate distance, or a node matching two. Order of the result: nodes_a order. O(n log n)
// (sort or a hash grid), fine for 10^5 nodes.
std::vector<NodePair> PairNodesByCoordinates(const FeModel& model_a,
                                             const std::vector<int64_t>& nodes_a,
                                             const RigidTransform& place_a, const FeModel& model_b,
                                             const std::vector<int64_t>& nodes_b,
                                             const RigidTransform& place_b, double tolerance);

// Local contact frame: unit normal n, tangent t1 = the projection of `preferred_tangent` onto
// the plane normal to n (normalised), t2 = n x t1. If preferred_tangent is (nearly, < 1e-6)
// parallel to n or zero, t1 is the projection of the global axis least aligned with n.
struct ContactFrame {
  Eigen::Vector3d normal, tangent1, tangent2;
};
ContactFrame MakeContactFrame(const Eigen::Vector3d& normal,
                              const Eigen::Vector3d& preferred_tangent);

}  // namespace fricrom
