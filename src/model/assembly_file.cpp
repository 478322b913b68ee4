// FE assembly case files (schema fricrom-assembly-1, or -2 with [cyclic], docs/case-files.md):
// bodies (assembly_bodies.cpp), node-to-node contacts with given frames, interfaces between node
// sets (assembly_interfaces.cpp), nodal loads on nodes or node sets, body accelerations, and a
// response DOF. Builds the same Model the lumped schema builds, with DOF names
// "body.node.component", solved by default through the condensed balance.
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "assembly_parts.h"
#include "fricrom/fe_model.h"
#include "fricrom/linear.h"

namespace fricrom::detail {
namespace {

// A stiffness pivot below this fraction of the largest is a free motion (round-off of zero).
constexpr double kFreeMotion = 1e-11;

namespace fs = std::filesystem;

// {body = "...", node = N} -> the body; node checked to exist.
const AssemblyBody& NodeRef(const Reader& rd, const std::vector<AssemblyBody>& bodies,
                            const toml::table& t, const std::string& where, int64_t* node) {
  const AssemblyBody& b =
      BodyNamed(rd, bodies, rd.String(t, where, "body"), where + ".body", t.get("body"));
  const double nv = rd.Number(t, where, "node");
  if (nv != std::floor(nv)) rd.Fail(where + ".node", "expected an integer node id", t.get("node"));
  *node = static_cast<int64_t>(nv);
  for (const DofId& d : b.dofs) {
    if (d.node == *node) return b;
  }
  rd.Fail(where + ".node",
          "body '" + b.name + "' has no node " + std::to_string(*node) + " among its DOFs",
          t.get("node"));
}

void ReadContacts(const Reader& rd, const toml::table& root,
                  const std::vector<AssemblyBody>& bodies, Case* cs, toml::array* resolved) {
  if (!root.get("contacts")) return;
  const toml::array& arr = rd.Array(root, "", "contacts");
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "contacts[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, arr, i, where);
    rd.CheckKeys(t, where,
                 {"name", "a", "b", "normal", "tangent", "kn", "kt", "mu", "normal_preload"});
    Contact c;
    c.name = rd.String(t, where, "name");
    for (const Contact& o : cs->model.contacts) {
      if (o.name == c.name) {
        rd.Fail(where + ".name", "duplicate contact name '" + c.name + "'", t.get("name"));
      }
    }
    int64_t na = 0, nb = 0;
    for (const char* side : {"a", "b"}) {
      const toml::node& sn = rd.Require(t, where, side);
      if (!sn.is_table()) rd.Fail(where + "." + side, "expected {body = \"...\", node = N}", &sn);
      rd.CheckKeys(*sn.as_table(), where + "." + side, {"body", "node"});
    }
    const AssemblyBody& ba = NodeRef(rd, bodies, *t["a"].as_table(), where + ".a", &na);
    const AssemblyBody& bb = NodeRef(rd, bodies, *t["b"].as_table(), where + ".b", &nb);
    // Component by component: g++ 12 (-march=x86-64-v3) warns on a Vector3d -> VectorXd copy.
    const Eigen::Vector3d normal = Vector3(rd, t, where, "normal");
    const Eigen::Vector3d tangent = Vector3(rd, t, where, "tangent");
    for (const auto& [key, v] : {std::pair{"normal", normal}, std::pair{"tangent", tangent}}) {
      if (std::abs(v.norm() - 1.0) > 1e-9) {
        rd.Fail(where + "." + key,
                "expected a unit vector, got one of length " + std::to_string(v.norm()),
                t.get(key));
      }
    }
    if (std::abs(normal.dot(tangent)) > 1e-9) {
      rd.Fail(where + ".tangent", "expected a direction orthogonal to the normal",
              t.get("tangent"));
    }
    c.normal = Eigen::VectorXd{{normal[0], normal[1], normal[2]}};
    c.tangent = Eigen::VectorXd{{tangent[0], tangent[1], tangent[2]}};
    for (int d = 0; d < 3; ++d) {
      c.dofs_a.push_back(ba.Dof(na, d + 1));
      c.dofs_b.push_back(bb.Dof(nb, d + 1));
      const bool used = c.normal[d] != 0.0 || c.tangent[d] != 0.0;
      if (used && (c.dofs_a.back() < 0 || c.dofs_b.back() < 0)) {
        rd.Fail(where,
                std::string("the frame has a ") + kComponentNames[d + 1] +
                    " component but a node of the pair has no " + kComponentNames[d + 1] + " DOF",
                &t);
      }
    }
    c.kn = rd.NonNegative(t, where, "kn");
    c.kt = rd.Positive(t, where, "kt");
    c.mu = rd.NonNegative(t, where, "mu");
    c.normal_preload = rd.NonNegative(t, where, "normal_preload", 0.0);
    resolved->push_back(toml::table{{"name", c.name}, {"kn", c.kn}, {"kt", c.kt}, {"mu", c.mu}});
    cs->contact_names.push_back(c.name);
    cs->alpha_interface.push_back(cs->alpha_interface.empty() ? 0 : cs->alpha_interface.back() + 1);
    cs->model.contacts.push_back(std::move(c));
    // Not on an interface face: no place in a contact-state map.
    cs->contact_positions.conservativeResize(3, cs->contact_positions.cols() + 1);
    cs->contact_positions.col(cs->contact_positions.cols() - 1).setConstant(NAN);
    cs->contact_interface.push_back(-1);
  }
}

int Component(const Reader& rd, const toml::table& t, const std::string& where) {
  const double cv = rd.Number(t, where, "component");
  if (cv != std::floor(cv) || cv < 1 || cv > 6) {
    rd.Fail(where + ".component", "expected 1..6 (x, y, z, rx, ry, rz)", t.get("component"));
  }
  return static_cast<int>(cv);
}

int DofAt(const Reader& rd, const AssemblyBody& b, int64_t node, int component,
          const std::string& where, const toml::table& t) {
  const int dof = b.Dof(node, component);
  if (dof < 0) {
    rd.Fail(where + ".component",
            "node " + std::to_string(node) + " of '" + b.name + "' has no " +
                kComponentNames[component] + " DOF (not a boundary DOF of the body?)",
            &t);
  }
  return dof;
}

HarmonicLoad& LoadAt(Model* m, int h) {
  for (HarmonicLoad& l : m->loads) {
    if (l.harmonic == h) return l;
  }
  const int n = m->num_dofs();
  m->loads.push_back(HarmonicLoad{h, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)});
  return m->loads.back();
}

int Harmonic(const Reader& rd, const toml::table& t, const std::string& where) {
  const double hv = rd.Number(t, where, "harmonic");
  if (hv < 0 || hv != std::floor(hv)) {
    rd.Fail(where + ".harmonic", "expected an integer >= 0", t.get("harmonic"));
  }
  return static_cast<int>(hv);
}

// [[loads]]: a force on a node or on every node of a set, f = cos·cos(hωt) + sin·sin(hωt), or
// f = amplitude·cos(hωt − phase) (phase_deg: e.g. an engine-order lag between blades).
void ReadLoads(const Reader& rd, const toml::table& root, const std::vector<AssemblyBody>& bodies,
               Model* m) {
  const toml::array& arr = rd.Array(root, "", "loads");
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "loads[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, arr, i, where);
    rd.CheckKeys(
        t, where,
        {"body", "node", "set", "component", "harmonic", "cos", "sin", "amplitude", "phase_deg"});
    const AssemblyBody& b =
        BodyNamed(rd, bodies, rd.String(t, where, "body"), where + ".body", t.get("body"));
    const int comp = Component(rd, t, where);
    const int h = Harmonic(rd, t, where);
    double fc = 0, fs = 0;
    if (t.get("amplitude")) {
      if (t.get("cos") || t.get("sin")) {
        rd.Fail(where, "give cos/sin or amplitude/phase_deg, not both", &t);
      }
      const double phase = rd.NumberOr(t, where, "phase_deg", 0.0) * std::numbers::pi / 180.0;
      fc = rd.Number(t, where, "amplitude") * std::cos(phase);
      fs = rd.Number(t, where, "amplitude") * std::sin(phase);
    } else {
      fc = rd.Number(t, where, "cos");
      fs = rd.NumberOr(t, where, "sin", 0.0);
    }
    if (h == 0 && fs != 0.0) rd.Fail(where, "a static load (harmonic 0) has no sine part", &t);
    std::vector<int64_t> nodes;
    if (t.get("node")) {
      int64_t node = 0;
      NodeRef(rd, bodies, t, where, &node);
      nodes = {node};
    } else if (t.get("set")) {
      const std::string set = rd.String(t, where, "set");
      const NodeSet* ns = b.Set(set);
      if (!ns) {
        rd.Fail(where + ".set", "body '" + b.name + "' has no node set '" + set + "'",
                t.get("set"));
      }
      nodes = ns->nodes;
    } else {
      rd.Fail(where, "give node = N or set = \"NODE_SET\" (the force applies to each node)", &t);
    }
    HarmonicLoad& l = LoadAt(m, h);
    for (int64_t node : nodes) {
      const int dof = DofAt(rd, b, node, comp, where, t);
      l.cos[dof] += fc;
      l.sin[dof] += fs;
    }
  }
}

// [[accelerations]]: a body acceleration (e.g. the centrifugal field Ω²R of a damper at radius
// R, taken uniform over the body) applied through the body's mass: f = Tᵀ M g_a.
void ReadAccelerations(const Reader& rd, const toml::table& root,
                       const std::vector<AssemblyBody>& bodies, Model* m, toml::array* resolved) {
  if (!root.get("accelerations")) return;
  const toml::array& arr = rd.Array(root, "", "accelerations");
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "accelerations[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, arr, i, where);
    rd.CheckKeys(t, where, {"body", "acceleration", "harmonic"});
    const AssemblyBody& b =
        BodyNamed(rd, bodies, rd.String(t, where, "body"), where + ".body", t.get("body"));
    if (b.unit_acceleration_loads.size() == 0) {
      rd.Fail(where + ".body",
              "body '" + b.name +
                  "' has no acceleration loads (a reduced.h5 "
                  "from an older fricrom: reduce it again)",
              t.get("body"));
    }
    const Eigen::Vector3d a = Vector3(rd, t, where, "acceleration");
    const int h = t.get("harmonic") ? Harmonic(rd, t, where) : 0;
    const Eigen::VectorXd f = b.unit_acceleration_loads * a;
    LoadAt(m, h).cos.segment(b.offset, f.size()) += f;
    resolved->push_back(toml::table{
        {"body", b.name}, {"acceleration", toml::array{a[0], a[1], a[2]}}, {"harmonic", h}});
  }
}

void ReadResponse(const Reader& rd, const toml::table& root,
                  const std::vector<AssemblyBody>& bodies, Model* m) {
  const toml::node& rn = rd.Require(root, "", "response");
  if (!rn.is_table()) rd.Fail("response", "expected {body, node or set, component}", &rn);
  const toml::table& t = *rn.as_table();
  rd.CheckKeys(t, "response", {"body", "node", "set", "component"});
  const AssemblyBody& b =
      BodyNamed(rd, bodies, rd.String(t, "response", "body"), "response.body", t.get("body"));
  int64_t node = 0;
  if (t.get("set")) {
    const std::string set = rd.String(t, "response", "set");
    const NodeSet* ns = b.Set(set);
    if (!ns)
      rd.Fail("response.set", "body '" + b.name + "' has no node set '" + set + "'", t.get("set"));
    if (ns->nodes.size() != 1) {
      rd.Fail("response.set",
              "set '" + set + "' of body '" + b.name + "' has " + std::to_string(ns->nodes.size()) +
                  " nodes; the response needs a set of exactly one node (or give `node`)",
              t.get("set"));
    }
    node = ns->nodes[0];
  } else {
    NodeRef(rd, bodies, t, "response", &node);
  }
  m->response_dof = DofAt(rd, b, node, Component(rd, t, "response"), "response", t);
}

// Directions of zero stiffness of a symmetric positive semi-definite K: LDLᵀ pivots (with
// pivoting) at round-off of the largest.
int ZeroStiffness(const Eigen::MatrixXd& k) {
  if (k.size() == 0) return 0;
  const Eigen::VectorXd d = Eigen::LDLT<Eigen::MatrixXd>(k).vectorD().cwiseAbs();
  const double largest = d.maxCoeff();
  int zero = 0;
  for (Eigen::Index i = 0; i < d.size(); ++i) zero += !(d[i] > kFreeMotion * largest);
  return zero;
}

// The assembly with every contact stuck must be held: a free motion leaves the static state
// (harmonic 0) undetermined and every solve diverges. An error naming the bodies and the keys.
void CheckHeld(const Reader& rd, const std::vector<AssemblyBody>& bodies, const Model& model) {
  const int free = ZeroStiffness(model.stiffness + ContactStickStiffness(model));
  if (free == 0) return;
  std::string own;
  for (const AssemblyBody& b : bodies) {
    const Eigen::Index n = static_cast<Eigen::Index>(b.dofs.size());
    const int z = ZeroStiffness(model.stiffness.block(b.offset, b.offset, n, n));
    if (z > 0) own += (own.empty() ? "" : ", ") + b.name + " " + std::to_string(z);
  }
  rd.Fail("bodies",
          "with every contact stuck the assembly has " + std::to_string(free) +
              " direction(s) of zero stiffness (free motion: the static state is undetermined)" +
              (own.empty() ? "" : "; the bodies' own: " + own) +
              ". Hold the free bodies: ground_stiffness [N/m] on translations, "
              "ground_rotation_stiffness [N m/rad] on rotations, or boundary conditions in the "
              "exported matrices");
}

// [cyclic] (schema fricrom-assembly-2): the case's bodies are one sector of `sectors`; the next
// sector is this one rotated by 2π/N about `axis` (right hand) through `origin`.
bool ReadCyclic(const Reader& rd, const toml::table& root, const std::string& schema, Case* cs,
                CyclicFrame* frame, toml::table* resolved) {
  const toml::node* node = root.get("cyclic");
  if (!node) return false;
  if (schema != "fricrom-assembly-2") {
    rd.Fail("cyclic", "cyclic symmetry needs schema = \"fricrom-assembly-2\"", node);
  }
  if (!node->is_table()) rd.Fail("cyclic", "expected a table", node);
  const toml::table& t = *node->as_table();
  rd.CheckKeys(t, "cyclic", {"sectors", "engine_order", "axis", "origin"});
  const double n = rd.Number(t, "cyclic", "sectors");
  if (!(n >= 2 && n == std::floor(n) && n <= 10000)) {
    rd.Fail("cyclic.sectors",
            "expected an integer >= 2 (sectors in the disk), got " + Reader::Fmt(n),
            t.get("sectors"));
  }
  const int sectors = static_cast<int>(n);
  const double eo = rd.Number(t, "cyclic", "engine_order");
  if (!(eo >= 0 && eo == std::floor(eo) && eo <= sectors / 2)) {
    rd.Fail("cyclic.engine_order",
            "expected an integer in 0.." + std::to_string(sectors / 2) +
                " (engine orders above N/2 alias to N - EO), got " + Reader::Fmt(eo),
            t.get("engine_order"));
  }
  const Eigen::Vector3d axis = Vector3(rd, t, "cyclic", "axis");
  if (!(axis.norm() > 0)) rd.Fail("cyclic.axis", "expected a non-zero vector", t.get("axis"));
  const Eigen::Vector3d origin =
      t.get("origin") ? Vector3(rd, t, "cyclic", "origin") : Eigen::Vector3d::Zero();
  cs->model.cyclic.sectors = sectors;
  cs->model.cyclic.engine_order = static_cast<int>(eo);
  frame->next = RigidTransform::FromAxisAngle(axis, 2.0 * std::numbers::pi / sectors, origin,
                                              Eigen::Vector3d::Zero());
  frame->phase = cs->model.cyclic.phase();
  const Eigen::Vector3d unit = axis.normalized();
  resolved->insert("cyclic",
                   toml::table{{"sectors", static_cast<int64_t>(sectors)},
                               {"engine_order", static_cast<int64_t>(eo)},
                               {"axis", toml::array{unit.x(), unit.y(), unit.z()}},
                               {"origin", toml::array{origin.x(), origin.y(), origin.z()}},
                               {"phase_rad", frame->phase}});
  return true;
}

}  // namespace

Case ParseAssembly(const toml::table& root, const std::string& source_name,
                   const std::vector<ParameterOverride>& overrides) {
  Reader rd(source_name);
  rd.CheckKeys(root, "",
               {"schema", "name", "description", "units", "parameters", "bodies", "contacts",
                "interfaces", "loads", "accelerations", "response", "analysis", "cyclic"});
  const std::string schema = rd.String(root, "", "schema");
  Case cs;
  cs.source = source_name;
  const std::string units = rd.String(root, "", "units");
  if (units != "SI")
    rd.Fail("units", "only \"SI\" is supported, got \"" + units + "\"", root.get("units"));
  cs.name = rd.String(root, "", "name");
  cs.description = rd.StringOr(root, "", "description", "");
  toml::table resolved{{"schema", schema}, {"units", "SI"}, {"name", cs.name}};
  ParseParameters(rd, root, overrides, &cs, &resolved);
  const std::filesystem::path base = std::filesystem::path(source_name).parent_path();
  toml::array rbodies, rcontacts, rinterfaces, raccel;
  const std::vector<AssemblyBody> bodies = ReadAssemblyBodies(rd, root, base, &cs.model, &rbodies);
  CyclicFrame frame;
  const bool cyclic = ReadCyclic(rd, root, schema, &cs, &frame, &resolved);
  ReadContacts(rd, root, bodies, &cs, &rcontacts);
  ReadInterfaces(rd, root, bodies, cyclic ? &frame : nullptr, &cs, &rinterfaces);
  if (cyclic && !HasCyclicContacts(cs.model)) {
    rd.Fail("cyclic",
            "no interface couples to the next sector: give one side b sector = \"next\" (the "
            "sectors would be uncoupled)");
  }
  if (cs.model.contacts.empty()) rd.Fail("contacts", "the assembly has no contact or interface");
  ReadLoads(rd, root, bodies, &cs.model);
  ReadAccelerations(rd, root, bodies, &cs.model, &raccel);
  ReadResponse(rd, root, bodies, &cs.model);
  CheckHeld(rd, bodies, cs.model);
  resolved.insert("bodies", std::move(rbodies));
  if (!rcontacts.empty()) resolved.insert("contacts", std::move(rcontacts));
  if (!rinterfaces.empty()) resolved.insert("interfaces", std::move(rinterfaces));
  if (!raccel.empty()) resolved.insert("accelerations", std::move(raccel));
  ParseAnalysis(rd, root, rd.Array(root, "", "loads"), cs.model.num_alpha(),
                BalanceKind::kCondensed, &cs.analysis, &resolved);
  const toml::table* analysis = root["analysis"].as_table();
  if (cyclic && cs.analysis.receptance == ReceptanceMethod::kModal && analysis &&
      analysis->get("receptance")) {
    rd.Fail("analysis.receptance",
            "a cyclic sector needs \"dense\": its stuck modes differ per harmonic (nodal "
            "diameter)",
            analysis->get("receptance"));
  }
  if (!analysis || !analysis->get("receptance")) {
    // No route named: the modal one where it is exact and pays (linear.h), else dense.
    cs.analysis.receptance = ChooseReceptance(cs.model);
    resolved["analysis"].as_table()->insert_or_assign("receptance",
                                                      ToString(cs.analysis.receptance));
  }
  FinishCase(resolved, &cs);
  return cs;
}

}  // namespace fricrom::detail
