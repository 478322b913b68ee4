// [[interfaces]] of an FE assembly: node-to-node friction contacts between a node set of one body
// and a node set of another. Nodes are paired by their placed coordinates (within a tolerance;
// unmatched nodes are an error that lists them); each pair becomes one contact of the paper's 1D
// law (normal from the faces' geometry or given, tangent along the projected slip direction), with
// kn, kt per pair given or from a stiffness per unit area times the nodal area of the faces
// (docs/contact-interfaces.md). α: one per pair (the physical non-uniqueness) or one per interface.
#include <cmath>

#include "assembly_parts.h"

namespace fricrom::detail {

namespace {

struct Side {
  const AssemblyBody* body = nullptr;
  std::string set;
  std::vector<int64_t> nodes;
};

Side SideOf(const Reader& rd, const toml::table& iface, const std::string& where, const char* key,
            const std::vector<AssemblyBody>& bodies) {
  const std::string w = where + "." + key;
  const toml::node& sn = rd.Require(iface, where, key);
  if (!sn.is_table()) rd.Fail(w, "expected {body = \"...\", set = \"NODE_SET\"}", &sn);
  const toml::table& t = *sn.as_table();
  rd.CheckKeys(t, w, {"body", "set"});
  Side s;
  s.body = &BodyNamed(rd, bodies, rd.String(t, w, "body"), w + ".body", t.get("body"));
  s.set = rd.String(t, w, "set");
  const NodeSet* ns = s.body->Set(s.set);
  if (!ns) {
    std::string names;
    for (const NodeSet& n : s.body->mesh.node_sets) names += (names.empty() ? "" : ", ") + n.name;
    rd.Fail(w + ".set",
            "body '" + s.body->name + "' has no node set '" + s.set +
                "' (it has: " + (names.empty() ? "none" : names) + ")",
            t.get("set"));
  }
  s.nodes = ns->nodes;
  for (int64_t n : s.nodes) {
    if (!s.body->HasNode(n)) {
      rd.Fail(w + ".set",
              "node " + std::to_string(n) + " of set '" + s.set + "' has no coordinates in body '" +
                  s.body->name + "'",
              t.get("set"));
    }
    for (int c = 1; c <= 3; ++c) {
      if (s.body->Dof(n, c) < 0) {
        rd.Fail(w + ".set",
                "node " + std::to_string(n) + " of set '" + s.set + "' has no " +
                    kComponentNames[c] + " DOF in body '" + s.body->name +
                    "' (keep the set's nodes as boundary DOFs 1,2,3)",
                t.get("set"));
      }
    }
  }
  return s;
}

// Areas and outward normals (in the assembly frame) of a side's nodes, when its body has faces.
bool FaceData(const Side& s, NodalAreaScheme scheme, std::map<int64_t, double>* area,
              std::map<int64_t, Eigen::Vector3d>* normal) {
  if (s.body->mesh.elements.empty()) return false;
  const NodalFaceData fd = FaceNodalData(s.body->mesh, FacesOnSet(s.body->mesh, s.set), scheme);
  for (size_t i = 0; i < fd.nodes.size(); ++i) {
    (*area)[fd.nodes[i]] = fd.area[i];
    (*normal)[fd.nodes[i]] = s.body->place.rotation * fd.normal[i];
  }
  return true;
}

struct PairStiffness {
  bool per_area = false;
  double kn = 0, kt = 0;  // [N/m] per pair, or [N/m³] per area
};

PairStiffness ReadStiffness(const Reader& rd, const toml::table& t, const std::string& where) {
  const bool pair = t.get("kn") || t.get("kt");
  const bool area = t.get("kn_per_area") || t.get("kt_per_area");
  if (pair == area) {
    rd.Fail(where, "give either kn and kt [N/m per pair] or kn_per_area and kt_per_area [N/m³]",
            &t);
  }
  PairStiffness s;
  s.per_area = area;
  s.kn = rd.NonNegative(t, where, area ? "kn_per_area" : "kn");
  s.kt = rd.Positive(t, where, area ? "kt_per_area" : "kt");
  return s;
}

}  // namespace

void ReadInterfaces(const Reader& rd, const toml::table& root,
                    const std::vector<AssemblyBody>& bodies, Case* cs, toml::array* resolved) {
  if (!root.get("interfaces")) return;
  const toml::array& arr = rd.Array(root, "", "interfaces");
  // α groups: the contacts read before (explicit [[contacts]]) have one α each.
  std::vector<int> groups;
  for (size_t c = 0; c < cs->model.contacts.size(); ++c) groups.push_back(static_cast<int>(c));
  bool grouped = false;
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "interfaces[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, arr, i, where);
    rd.CheckKeys(
        t, where,
        {"name", "a", "b", "tolerance", "kn", "kt", "kn_per_area", "kt_per_area", "mu", "normal",
         "slip_direction", "tangential_directions", "alpha", "area_scheme", "normal_preload"});
    const std::string name = rd.String(t, where, "name");
    const Side a = SideOf(rd, t, where, "a", bodies), b = SideOf(rd, t, where, "b", bodies);
    const double tol = rd.NumberOr(t, where, "tolerance", 1e-6);
    if (!(tol > 0)) rd.Fail(where + ".tolerance", "expected a value > 0 [m]", t.get("tolerance"));
    std::vector<NodePair> pairs;
    try {
      pairs = PairNodesByCoordinates(a.body->mesh, a.nodes, a.body->place, b.body->mesh, b.nodes,
                                     b.body->place, tol);
    } catch (const std::invalid_argument& e) {
      rd.Fail(where, e.what(), &t);
    }
    if (pairs.size() != b.nodes.size()) {
      rd.Fail(where,
              "set '" + b.set + "' of '" + b.body->name + "' has " +
                  std::to_string(b.nodes.size()) + " nodes, '" + a.set + "' of '" + a.body->name +
                  "' " + std::to_string(a.nodes.size()) + ": node-to-node pairing needs equal sets",
              &t);
    }
    const std::string scheme_name = rd.StringOr(t, where, "area_scheme", "subdivision");
    if (scheme_name != "subdivision" && scheme_name != "consistent") {
      rd.Fail(where + ".area_scheme", "expected \"subdivision\" or \"consistent\"",
              t.get("area_scheme"));
    }
    const NodalAreaScheme scheme =
        scheme_name == "consistent" ? NodalAreaScheme::kConsistent : NodalAreaScheme::kSubdivision;
    std::map<int64_t, double> area_a, area_b;
    std::map<int64_t, Eigen::Vector3d> normal_a, normal_b;
    bool faces_a = false, faces_b = false;
    try {
      faces_a = FaceData(a, scheme, &area_a, &normal_a);
      faces_b = FaceData(b, scheme, &area_b, &normal_b);
    } catch (const std::invalid_argument& e) {
      rd.Fail(where, e.what(), &t);
    }
    const PairStiffness k = ReadStiffness(rd, t, where);
    if (k.per_area && !faces_a && !faces_b) {
      rd.Fail(where,
              "stiffness per area needs the faces of one side: give its body a mesh deck "
              "(mesh = \"deck.inp\" with the elements)",
              &t);
    }
    const bool given_normal = t.get("normal") != nullptr;
    if (!given_normal && !faces_a && !faces_b) {
      rd.Fail(where,
              "no face geometry to take the normal from: give normal = [x, y, z] (from A "
              "into B) or a mesh deck for one body",
              &t);
    }
    Eigen::Vector3d fixed_normal = Eigen::Vector3d::Zero();
    if (given_normal) {
      fixed_normal = Vector3(rd, t, where, "normal");
      if (!(fixed_normal.norm() > 0)) rd.Fail(where + ".normal", "expected a non-zero vector");
      fixed_normal.normalize();
    }
    const Eigen::Vector3d slip = t.get("slip_direction") ? Vector3(rd, t, where, "slip_direction")
                                                         : Eigen::Vector3d::UnitX();
    const double mu = rd.NonNegative(t, where, "mu");
    const double preload = rd.NonNegative(t, where, "normal_preload", 0.0);
    const double nd = rd.NumberOr(t, where, "tangential_directions", 1.0);
    if (nd != 1.0 && nd != 2.0) {
      rd.Fail(where + ".tangential_directions",
              "expected 1 (the slip direction) or 2 (slip direction and normal x slip direction)",
              t.get("tangential_directions"));
    }
    const int directions = static_cast<int>(nd);
    const std::string alpha = rd.StringOr(t, where, "alpha", "pair");
    if (alpha != "pair" && alpha != "interface") {
      rd.Fail(where + ".alpha", "expected \"pair\" (one α per node pair) or \"interface\"",
              t.get("alpha"));
    }
    double area_sum = 0;
    const int first = static_cast<int>(cs->model.contacts.size());
    for (const NodePair& p : pairs) {
      Contact c;
      c.name = name + "." + std::to_string(p.node_a);
      // Normal from A into B: A's outward normal, else minus B's.
      Eigen::Vector3d n = fixed_normal;
      if (!given_normal)
        n = faces_a ? normal_a.at(p.node_a) : Eigen::Vector3d(-normal_b.at(p.node_b));
      const ContactFrame frame = MakeContactFrame(n, slip);
      c.normal = frame.normal;
      c.tangent = frame.tangent1;
      const double area = faces_a ? area_a.at(p.node_a) : (faces_b ? area_b.at(p.node_b) : 1.0);
      area_sum += area;
      c.kn = k.per_area ? k.kn * area : k.kn;
      c.kt = k.per_area ? k.kt * area : k.kt;
      c.mu = mu;
      c.normal_preload = preload;
      for (int d = 1; d <= 3; ++d) {
        c.dofs_a.push_back(a.body->Dof(p.node_a, d));
        c.dofs_b.push_back(b.body->Dof(p.node_b, d));
      }
      if (directions == 2) {
        // Two 1D laws sharing the pair's normal gap, each limited by μ × the pair's whole normal
        // load: halves of kn and the preload with 2μ give both (normal force summed, T_i ≤ μN).
        Contact c2 = c;
        c.name += ".t1";
        c2.name += ".t2";
        c2.tangent = frame.tangent2;
        for (Contact* d : {&c, &c2}) {
          d->kn *= 0.5;
          d->normal_preload *= 0.5;
          d->mu *= 2.0;
        }
        cs->contact_names.push_back(c.name);
        cs->model.contacts.push_back(std::move(c));
        c = std::move(c2);
      }
      cs->contact_names.push_back(c.name);
      cs->model.contacts.push_back(std::move(c));
      const int nc = static_cast<int>(cs->model.contacts.size());
      cs->contact_positions.conservativeResize(3, nc);
      for (int k = static_cast<int>(cs->contact_interface.size()); k < nc; ++k) {
        cs->contact_positions.col(k) = a.body->PlacedXyz(p.node_a);
        cs->contact_interface.push_back(static_cast<int>(cs->interface_names.size()));
      }
    }
    cs->interface_names.push_back(name);
    // α groups: per contact, or per interface and direction.
    const int next = groups.empty() ? 0 : groups.back() + 1;
    const int next_interface = cs->alpha_interface.empty() ? 0 : cs->alpha_interface.back() + 1;
    for (size_t p = 0; p < pairs.size(); ++p) {
      for (int d = 0; d < directions; ++d) {
        groups.push_back(alpha == "interface" ? next + d
                                              : next + static_cast<int>(p) * directions + d);
        if (alpha != "interface" || p == 0) cs->alpha_interface.push_back(next_interface + d);
      }
    }
    grouped = grouped || (alpha == "interface" && pairs.size() > 1);
    toml::table r{{"name", name},
                  {"pairs", static_cast<int64_t>(pairs.size())},
                  {"alpha", alpha},
                  {"mu", mu},
                  {"tangential_directions", static_cast<int64_t>(directions)},
                  {"first_contact", static_cast<int64_t>(first)}};
    if (faces_a || faces_b) r.insert("face_area_m2", area_sum);
    resolved->push_back(std::move(r));
  }
  if (grouped) cs->model.alpha_group = std::move(groups);
}

}  // namespace fricrom::detail
