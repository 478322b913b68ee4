// The pieces of an FE assembly case file (schema fricrom-assembly-1) shared by its readers:
// bodies (assembly_bodies.cpp), node-to-node interfaces (assembly_interfaces.cpp) and the
// top level with contacts, loads and the response (assembly_file.cpp).
#pragma once

#include <Eigen/Dense>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "case_reader.h"
#include "fricrom/fe_model.h"
#include "fricrom/interface_geometry.h"

namespace fricrom::detail {

inline const char* kComponentNames[] = {"s", "x", "y", "z", "rx", "ry", "rz"};

struct AssemblyBody {
  std::string name;
  bool blade = true;
  int offset = 0;                                // first DOF in the assembled model
  std::vector<DofId> dofs;                       // the body's DOFs in row order
  std::map<std::pair<int64_t, int>, int> index;  // (node, component) -> assembled DOF
  RigidTransform place;                          // body frame -> assembly frame
  FeModel mesh;  // nodes (body frame), node sets and, when a mesh deck is known, elements
  // Loads of unit accelerations along the assembly's x, y, z (columns), in the body's rows
  // [N per m/s²]; empty when the body's files cannot give them.
  Eigen::MatrixXd unit_acceleration_loads;

  int Dof(int64_t node, int component) const {
    const auto it = index.find({node, component});
    return it == index.end() ? -1 : it->second;
  }
  bool HasNode(int64_t node) const;
  Eigen::Vector3d PlacedXyz(int64_t node) const;  // throws CaseError-free: caller checks HasNode
  const NodeSet* Set(const std::string& name) const { return mesh.FindNodeSet(name); }
};

// [[bodies]]: reads every body, assembles block-diagonal K, M, C into `model` (dof names
// "body.node.component", modal coordinates "body.q<k>"), records the resolved entries.
std::vector<AssemblyBody> ReadAssemblyBodies(const Reader& rd, const toml::table& root,
                                             const std::filesystem::path& base, Model* model,
                                             toml::array* resolved);

// The body named `name` (error at `where` otherwise).
const AssemblyBody& BodyNamed(const Reader& rd, const std::vector<AssemblyBody>& bodies,
                              const std::string& name, const std::string& where,
                              const toml::node* node);

// [cyclic] of a sector of a bladed disk: where the next sector lies (this one rotated by 2π/N
// about the axis through the origin) and its phase per harmonic under the engine order.
struct CyclicFrame {
  RigidTransform next;  // this sector's frame -> the next sector's placement
  double phase = 0.0;   // [rad] 2π·EO/N
};

// [[interfaces]]: contacts between node sets, appended to cs->model.contacts (with α groups).
// A side b with sector = "next" is the next sector's copy of the set (needs `cyclic`).
void ReadInterfaces(const Reader& rd, const toml::table& root,
                    const std::vector<AssemblyBody>& bodies, const CyclicFrame* cyclic, Case* cs,
                    toml::array* resolved);

Eigen::Vector3d Vector3(const Reader& rd, const toml::table& t, const std::string& where,
                        const std::string& key);

}  // namespace fricrom::detail
