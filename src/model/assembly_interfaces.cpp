// [[interfaces]] of an FE assembly: node-to-node friction contacts between a node set of one body
// and a node set of another. Nodes are paired by their placed coordinates (within a tolerance;
// unmatched nodes are an error that lists them); each pair becomes one contact of the paper's 1D
// law (normal from the faces' geometry or given, tangent along the projected slip direction), with
// kn, kt per pair given or from a stiffness per unit area times the nodal area of the faces
// (docs/contact-interfaces.md). α: one per pair (the physical non-uniqueness) or one per interface.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "assembly_parts.h"

namespace fricrom::detail {

namespace {

struct Side {
  const AssemblyBody* body = nullptr;
  std::string set;
  std::vector<int64_t> nodes;
  bool next_sector = false;  // the next sector's copy of the set (cyclic symmetry)
  RigidTransform place;      // body frame -> this sector's frame (the next sector's placement)
};

Side SideOf(const Reader& rd, const toml::table& iface, const std::string& where, const char* key,
            const std::vector<AssemblyBody>& bodies, const CyclicFrame* cyclic) {
  const std::string w = where + "." + key;
  const toml::node& sn = rd.Require(iface, where, key);
  if (!sn.is_table()) rd.Fail(w, "expected {body = \"...\", set = \"NODE_SET\"}", &sn);
  const toml::table& t = *sn.as_table();
  const bool side_b = std::string(key) == "b";
  if (side_b) {
    rd.CheckKeys(t, w, {"body", "set", "sector"});
  } else {
    rd.CheckKeys(t, w, {"body", "set"});
  }
  Side s;
  s.body = &BodyNamed(rd, bodies, rd.String(t, w, "body"), w + ".body", t.get("body"));
  s.set = rd.String(t, w, "set");
  s.place = s.body->place;
  if (side_b && t.get("sector")) {
    const std::string sector = rd.String(t, w, "sector");
    if (sector != "next" && sector != "this") {
      rd.Fail(w + ".sector", "expected \"this\" or \"next\" (the next sector of a cyclic model)",
              t.get("sector"));
    }
    s.next_sector = sector == "next";
    if (s.next_sector && !cyclic) {
      rd.Fail(w + ".sector", "sector = \"next\" needs a [cyclic] section (sectors, axis)",
              t.get("sector"));
    }
    if (s.next_sector) {
      // The next sector's copy: this sector's placement, then the sector rotation.
      s.place.rotation = cyclic->next.rotation * s.body->place.rotation;
      s.place.translation = cyclic->next.Apply(s.body->place.translation);
    }
  }
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
    (*normal)[fd.nodes[i]] = s.place.rotation * fd.normal[i];
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
  // Beyond this a pair's stiffness (times an area of 1e-4 m² at most a few orders less) overflows
  // the products of the stick stiffness, as a body matrix would (assembly_bodies.cpp).
  constexpr double kLargest = 1e150;
  for (const char* key : {"kn", "kt"}) {
    const std::string k = std::string(key) + (area ? "_per_area" : "");
    const double v = std::string(key) == "kn" ? s.kn : s.kt;
    if (v > kLargest) {
      std::ostringstream m;
      m << "a contact stiffness of " << v << " is not representable (at most 1e150)";
      rd.Fail(where + "." + k, m.str(), t.get(k));
    }
  }
  return s;
}

// One [[interfaces]] entry as read: both sides paired node to node, their face data, the
// contact law and the α grouping.
struct Interface {
  std::string name;
  Side a, b;
  std::vector<NodePair> pairs;
  std::map<int64_t, double> area_a, area_b;
  std::map<int64_t, Eigen::Vector3d> normal_a, normal_b;
  bool faces_a = false, faces_b = false;
  PairStiffness k;
  bool given_normal = false;
  Eigen::Vector3d fixed_normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d slip = Eigen::Vector3d::UnitX();
  double mu = 0, preload = 0;
  int directions = 1;
  std::string alpha;
  double phase = 0.0;  // cyclic: the next sector's delay per harmonic [rad]
};

// The node pairs (equal sets, matched by placed coordinates) and the faces' areas and normals.
void ReadGeometry(const Reader& rd, const toml::table& t, const std::string& where,
                  const std::vector<AssemblyBody>& bodies, const CyclicFrame* cyclic,
                  Interface* f) {
  f->a = SideOf(rd, t, where, "a", bodies, cyclic);
  f->b = SideOf(rd, t, where, "b", bodies, cyclic);
  if (f->b.next_sector) f->phase = cyclic->phase;
  const Side &a = f->a, &b = f->b;
  const double tol = rd.NumberOr(t, where, "tolerance", 1e-6);
  if (!(tol > 0)) rd.Fail(where + ".tolerance", "expected a value > 0 [m]", t.get("tolerance"));
  try {
    f->pairs =
        PairNodesByCoordinates(a.body->mesh, a.nodes, a.place, b.body->mesh, b.nodes, b.place, tol);
  } catch (const std::invalid_argument& e) {
    rd.Fail(where,
            std::string(e.what()) +
                (b.next_sector ? " (side b: the next sector's copy, rotated by 2π/N about the "
                                 "[cyclic] axis)"
                               : ""),
            &t);
  }
  if (f->pairs.size() != b.nodes.size()) {
    rd.Fail(where,
            "set '" + b.set + "' of '" + b.body->name + "' has " + std::to_string(b.nodes.size()) +
                " nodes, '" + a.set + "' of '" + a.body->name + "' " +
                std::to_string(a.nodes.size()) + ": node-to-node pairing needs equal sets",
            &t);
  }
  const std::string scheme_name = rd.StringOr(t, where, "area_scheme", "subdivision");
  if (scheme_name != "subdivision" && scheme_name != "consistent") {
    rd.Fail(where + ".area_scheme", "expected \"subdivision\" or \"consistent\"",
            t.get("area_scheme"));
  }
  const NodalAreaScheme scheme =
      scheme_name == "consistent" ? NodalAreaScheme::kConsistent : NodalAreaScheme::kSubdivision;
  // Faces give nodal areas (stiffness per area) and normals. An interface with kn/kt per pair and
  // a normal needs neither: on beams, shells or superelements it pairs its nodes without them.
  const bool needs_faces = t.get("kn_per_area") || t.get("kt_per_area") || !t.get("normal");
  try {
    f->faces_a = FaceData(a, scheme, &f->area_a, &f->normal_a);
    f->faces_b = FaceData(b, scheme, &f->area_b, &f->normal_b);
  } catch (const std::invalid_argument& e) {
    if (needs_faces) rd.Fail(where, e.what(), &t);
    f->faces_a = f->faces_b = false;
    f->area_a.clear();
    f->area_b.clear();
    f->normal_a.clear();
    f->normal_b.clear();
  }
}

// Stiffness, normal, slip direction, friction, preload, tangential directions and α grouping.
void ReadLaw(const Reader& rd, const toml::table& t, const std::string& where, Interface* f) {
  f->k = ReadStiffness(rd, t, where);
  const bool faces = f->faces_a || f->faces_b;
  if (f->k.per_area && !faces) {
    rd.Fail(where,
            "stiffness per area needs the faces of one side: give its body a mesh deck "
            "(mesh = \"deck.inp\" with the elements)",
            &t);
  }
  f->given_normal = t.get("normal") != nullptr;
  if (!f->given_normal && !faces) {
    rd.Fail(where,
            "no face geometry to take the normal from: give normal = [x, y, z] (from A "
            "into B) or a mesh deck for one body",
            &t);
  }
  if (f->given_normal) {
    f->fixed_normal = Vector3(rd, t, where, "normal");
    if (!(f->fixed_normal.norm() > 0)) rd.Fail(where + ".normal", "expected a non-zero vector");
    f->fixed_normal.normalize();
  }
  if (t.get("slip_direction")) {
    f->slip = Vector3(rd, t, where, "slip_direction");
    if (!(f->slip.norm() > 0)) {
      rd.Fail(where + ".slip_direction", "expected a non-zero vector", t.get("slip_direction"));
    }
  }
  f->mu = rd.NonNegative(t, where, "mu");
  f->preload = rd.NonNegative(t, where, "normal_preload", 0.0);
  const double nd = rd.NumberOr(t, where, "tangential_directions", 1.0);
  if (nd != 1.0 && nd != 2.0) {
    rd.Fail(where + ".tangential_directions",
            "expected 1 (the slip direction) or 2 (slip direction and normal x slip direction)",
            t.get("tangential_directions"));
  }
  f->directions = static_cast<int>(nd);
  f->alpha = rd.StringOr(t, where, "alpha", "pair");
  if (f->alpha != "pair" && f->alpha != "interface") {
    rd.Fail(where + ".alpha", "expected \"pair\" (one α per node pair) or \"interface\"",
            t.get("alpha"));
  }
}

void PushContact(const Interface& f, const NodePair& p, Contact c, Case* cs) {
  cs->contact_names.push_back(c.name);
  cs->model.contacts.push_back(std::move(c));
  const int nc = static_cast<int>(cs->model.contacts.size());
  cs->contact_positions.conservativeResize(3, nc);
  cs->contact_positions.col(nc - 1) = f.a.body->PlacedXyz(p.node_a);
  cs->contact_interface.push_back(static_cast<int>(cs->interface_names.size()));
}

// Rᵀ d for the sector rotation R: the next sector's motion along d, read on this sector's copy.
Eigen::VectorXd BackFromNextSector(const Interface& f, const Eigen::Vector3d& d) {
  const Eigen::Matrix3d r = f.b.place.rotation * f.b.body->place.rotation.transpose();
  Eigen::VectorXd out(3);
  for (int i = 0; i < 3; ++i) out[i] = r.col(i).dot(d);
  return out;
}

// One contact per node pair (two with two tangential directions); returns the faces' area.
double AddContacts(const Interface& f, Case* cs) {
  double area_sum = 0;
  for (const NodePair& p : f.pairs) {
    Contact c;
    c.name = f.name + "." + std::to_string(p.node_a);
    // Normal from A into B: A's outward normal, else minus B's.
    Eigen::Vector3d n = f.fixed_normal;
    if (!f.given_normal)
      n = f.faces_a ? f.normal_a.at(p.node_a) : Eigen::Vector3d(-f.normal_b.at(p.node_b));
    const ContactFrame frame = MakeContactFrame(n, f.slip);
    c.normal = frame.normal;
    c.tangent = frame.tangent1;
    const double area =
        f.faces_a ? f.area_a.at(p.node_a) : (f.faces_b ? f.area_b.at(p.node_b) : 1.0);
    area_sum += area;
    if (f.b.next_sector) {
      // Side B's DOFs are this sector's copy of the node: the next sector's motion along a
      // direction d is (Rᵀd) of them, one sector later in the travelling wave.
      c.normal_b = BackFromNextSector(f, frame.normal);
      c.tangent_b = BackFromNextSector(f, frame.tangent1);
      c.phase_b = f.phase;
    }
    c.kn = f.k.per_area ? f.k.kn * area : f.k.kn;
    c.kt = f.k.per_area ? f.k.kt * area : f.k.kt;
    c.mu = f.mu;
    c.normal_preload = f.preload;
    for (int d = 1; d <= 3; ++d) {
      c.dofs_a.push_back(f.a.body->Dof(p.node_a, d));
      c.dofs_b.push_back(f.b.body->Dof(p.node_b, d));
    }
    if (f.directions == 2) {
      // Two 1D laws sharing the pair's normal gap, each limited by μ × the pair's whole normal
      // load: halves of kn and the preload with 2μ give both (normal force summed, T_i ≤ μN).
      Contact c2 = c;
      c.name += ".t1";
      c2.name += ".t2";
      c2.tangent = frame.tangent2;
      if (f.b.next_sector) c2.tangent_b = BackFromNextSector(f, frame.tangent2);
      for (Contact* d : {&c, &c2}) {
        d->kn *= 0.5;
        d->normal_preload *= 0.5;
        d->mu *= 2.0;
      }
      PushContact(f, p, std::move(c), cs);
      c = std::move(c2);
    }
    PushContact(f, p, std::move(c), cs);
  }
  return area_sum;
}

// α groups: per contact, or per interface and direction.
void AddAlphaGroups(const Interface& f, std::vector<int>* groups, Case* cs) {
  const int next = groups->empty() ? 0 : groups->back() + 1;
  const int next_interface = cs->alpha_interface.empty() ? 0 : cs->alpha_interface.back() + 1;
  const bool per_interface = f.alpha == "interface";
  for (size_t p = 0; p < f.pairs.size(); ++p) {
    for (int d = 0; d < f.directions; ++d) {
      groups->push_back(per_interface ? next + d : next + static_cast<int>(p) * f.directions + d);
      if (!per_interface || p == 0) cs->alpha_interface.push_back(next_interface + d);
    }
  }
}

}  // namespace

void ReadInterfaces(const Reader& rd, const toml::table& root,
                    const std::vector<AssemblyBody>& bodies, const CyclicFrame* cyclic, Case* cs,
                    toml::array* resolved) {
  if (!root.get("interfaces")) return;
  const toml::array& arr = rd.Array(root, "", "interfaces");
  // α groups: the contacts read before (explicit [[contacts]]) have one α each.
  std::vector<int> groups;
  for (size_t c = 0; c < cs->model.contacts.size(); ++c) groups.push_back(static_cast<int>(c));
  bool grouped = false;
  std::vector<std::string> paired;  // the interfaces' sets, "body/set | body/set"
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "interfaces[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, arr, i, where);
    rd.CheckKeys(
        t, where,
        {"name", "a", "b", "tolerance", "kn", "kt", "kn_per_area", "kt_per_area", "mu", "normal",
         "slip_direction", "tangential_directions", "alpha", "area_scheme", "normal_preload"});
    Interface f;
    f.name = rd.String(t, where, "name");
    for (const std::string& other : cs->interface_names) {
      if (other == f.name) rd.Fail(where + ".name", "duplicate interface name", t.get("name"));
    }
    ReadGeometry(rd, t, where, bodies, cyclic, &f);
    // A set paired with itself has no relative displacement; the same two sets paired twice
    // would put every contact in twice (doubled stiffness and friction).
    const auto side = [](const Side& s) {
      return s.body->name + "/" + s.set + (s.next_sector ? " (next sector)" : "");
    };
    if (side(f.a) == side(f.b)) {
      rd.Fail(where, "side a and side b are the same set ('" + side(f.a) + "')", &t);
    }
    const std::string key = std::min(side(f.a), side(f.b)) + " | " + std::max(side(f.a), side(f.b));
    for (size_t j = 0; j < paired.size(); ++j) {
      if (paired[j] == key) {
        rd.Fail(where,
                "pairs the same sets as interfaces[" + std::to_string(j) + "] ('" + key +
                    "'): its contacts would act twice",
                &t);
      }
    }
    paired.push_back(key);
    ReadLaw(rd, t, where, &f);
    const int first = static_cast<int>(cs->model.contacts.size());
    const double area_sum = AddContacts(f, cs);
    cs->interface_names.push_back(f.name);
    AddAlphaGroups(f, &groups, cs);
    grouped = grouped || (f.alpha == "interface" && f.pairs.size() > 1);
    toml::table r{{"name", f.name},
                  {"pairs", static_cast<int64_t>(f.pairs.size())},
                  {"alpha", f.alpha},
                  {"mu", f.mu},
                  {"tangential_directions", static_cast<int64_t>(f.directions)},
                  {"first_contact", static_cast<int64_t>(first)}};
    if (f.b.next_sector) r.insert("b_sector", "next");
    if (f.faces_a || f.faces_b) r.insert("face_area_m2", area_sum);
    resolved->push_back(std::move(r));
  }
  if (grouped) cs->model.alpha_group = std::move(groups);
}

}  // namespace fricrom::detail
