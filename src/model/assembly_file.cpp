// FE assembly case files (schema fricrom-assembly-1, docs/case-files.md): bodies given by their
// exported matrices (any format `fricrom info` reads, with a DOF map), node-to-node contacts with
// given frames, nodal loads and a response DOF. Builds the same Model the lumped schema builds,
// with DOF names "body.node.component", solved by default through the condensed balance.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "case_reader.h"
#include "fricrom/fe_model.h"

namespace fricrom::detail {
namespace {

namespace fs = std::filesystem;

const char* kComponents[] = {"s", "x", "y", "z", "rx", "ry", "rz"};

struct FeBody {
  std::string name;
  bool blade = true;
  int offset = 0;                                // first DOF in the assembled model
  std::vector<DofId> dofs;                       // the body's DOF map
  std::map<std::pair<int64_t, int>, int> index;  // (node, component) -> assembled DOF
};

// One matrix file of a body: exactly one square real matrix, with a DOF map.
FeMatrix ReadBodyMatrix(const Reader& rd, const toml::table& t, const std::string& where,
                        const std::string& key, const fs::path& base, const std::string& dof_map) {
  const fs::path file = base / rd.String(t, where, key);
  FeModel fe;
  try {
    fe = dof_map.empty() ? ReadFe(file.string())
                         : ReadMatrixMarket(file.string(), (base / dof_map).string());
  } catch (const FeReadError& e) {
    rd.Fail(where + "." + key, e.what(), t.get(key));
  }
  if (fe.matrices.size() != 1) {
    rd.Fail(where + "." + key,
            file.string() + " holds " + std::to_string(fe.matrices.size()) +
                " matrices; a body matrix file must hold exactly one",
            t.get(key));
  }
  FeMatrix m = std::move(fe.matrices[0]);
  if (m.rows != m.cols || m.is_complex) {
    rd.Fail(where + "." + key, file.string() + ": expected a square real matrix", t.get(key));
  }
  if (m.row_dofs.empty()) {
    rd.Fail(
        where + "." + key,
        file.string() + " has no DOF map (give dof_map = \"file.csv\" with node,component rows)",
        t.get(key));
  }
  return m;
}

void Place(const Eigen::SparseMatrix<double>& s, int offset, Eigen::MatrixXd* dense) {
  for (int k = 0; k < s.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(s, k); it; ++it) {
      (*dense)(offset + it.row(), offset + it.col()) += it.value();
    }
  }
}

// Reads the [[bodies]] and assembles block-diagonal K, M, C.
std::vector<FeBody> ReadBodies(const Reader& rd, const toml::table& root, const fs::path& base,
                               Model* m, toml::array* resolved) {
  const toml::array& arr = rd.Array(root, "", "bodies");
  std::vector<FeBody> bodies;
  std::vector<std::vector<FeMatrix>> mats;
  int n = 0;
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "bodies[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, arr, i, where);
    rd.CheckKeys(t, where, {"name", "role", "stiffness", "mass", "damping", "dof_map"});
    FeBody b;
    b.name = rd.String(t, where, "name");
    for (const FeBody& o : bodies) {
      if (o.name == b.name) rd.Fail(where + ".name", "duplicate body name", t.get("name"));
    }
    const std::string role = rd.StringOr(t, where, "role", "blade");
    if (role != "blade" && role != "damper") {
      rd.Fail(where + ".role", "expected \"blade\" or \"damper\", got '" + role + "'",
              t.get("role"));
    }
    b.blade = role == "blade";
    const std::string dof_map = rd.StringOr(t, where, "dof_map", "");
    std::vector<FeMatrix> km;
    for (const char* key : {"stiffness", "mass", "damping"}) {
      if (std::string(key) == "damping" && !t.get("damping")) break;
      km.push_back(ReadBodyMatrix(rd, t, where, key, base, dof_map));
      if (km.back().row_dofs != km[0].row_dofs) {
        rd.Fail(where + "." + key, "its DOF map differs from the stiffness matrix's", t.get(key));
      }
    }
    b.dofs = km[0].row_dofs;
    b.offset = n;
    for (size_t d = 0; d < b.dofs.size(); ++d) {
      const DofId& id = b.dofs[d];
      if (id.component < 0 || id.component > 6) {
        rd.Fail(where + ".dof_map", "component " + std::to_string(id.component) + " not in 0..6");
      }
      if (!b.index.emplace(std::make_pair(id.node, id.component), n + static_cast<int>(d)).second) {
        rd.Fail(where + ".dof_map", "node " + std::to_string(id.node) + " component " +
                                        std::to_string(id.component) + " appears twice");
      }
      m->dof_names.push_back(b.name + "." + std::to_string(id.node) + "." +
                             kComponents[id.component]);
      if (b.blade) m->free_dofs.push_back(n + static_cast<int>(d));
    }
    n += static_cast<int>(b.dofs.size());
    toml::table rb{{"name", b.name}, {"role", role}, {"dofs", static_cast<int64_t>(b.dofs.size())}};
    for (const char* key : {"stiffness", "mass", "damping", "dof_map"}) {
      if (t.get(key)) rb.insert(key, rd.String(t, where, key));
    }
    resolved->push_back(std::move(rb));
    bodies.push_back(std::move(b));
    mats.push_back(std::move(km));
  }
  m->stiffness.setZero(n, n);
  m->mass.setZero(n, n);
  m->damping.setZero(n, n);
  for (size_t i = 0; i < bodies.size(); ++i) {
    Place(mats[i][0].real, bodies[i].offset, &m->stiffness);
    Place(mats[i][1].real, bodies[i].offset, &m->mass);
    if (mats[i].size() > 2) Place(mats[i][2].real, bodies[i].offset, &m->damping);
  }
  return bodies;
}

// {body = "...", node = N} -> the body; node checked to exist.
const FeBody& NodeRef(const Reader& rd, const std::vector<FeBody>& bodies, const toml::table& t,
                      const std::string& where, int64_t* node) {
  const std::string body = rd.String(t, where, "body");
  const double nv = rd.Number(t, where, "node");
  if (nv != std::floor(nv)) rd.Fail(where + ".node", "expected an integer node id", t.get("node"));
  *node = static_cast<int64_t>(nv);
  for (const FeBody& b : bodies) {
    if (b.name != body) continue;
    for (const DofId& d : b.dofs) {
      if (d.node == *node) return b;
    }
    rd.Fail(where + ".node", "body '" + body + "' has no node " + std::to_string(*node),
            t.get("node"));
  }
  rd.Fail(where + ".body", "no body named '" + body + "'", t.get("body"));
}

int DofOf(const FeBody& b, int64_t node, int component) {
  const auto it = b.index.find({node, component});
  return it == b.index.end() ? -1 : it->second;
}

Eigen::VectorXd Vector3(const Reader& rd, const toml::table& t, const std::string& where,
                        const std::string& key) {
  const toml::array& a = rd.Array(t, where, key);
  if (a.size() != 3) rd.Fail(where + "." + key, "expected 3 components [x, y, z]", t.get(key));
  Eigen::VectorXd v(3);
  for (int i = 0; i < 3; ++i) v[i] = rd.Number(a[i], where + "." + key);
  return v;
}

void ReadContacts(const Reader& rd, const toml::table& root, const std::vector<FeBody>& bodies,
                  Case* cs, toml::array* resolved) {
  const toml::array& arr = rd.Array(root, "", "contacts");
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "contacts[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, arr, i, where);
    rd.CheckKeys(t, where,
                 {"name", "a", "b", "normal", "tangent", "kn", "kt", "mu", "normal_preload"});
    Contact c;
    c.name = rd.String(t, where, "name");
    int64_t na = 0, nb = 0;
    for (const char* side : {"a", "b"}) {
      const toml::node& sn = rd.Require(t, where, side);
      if (!sn.is_table()) rd.Fail(where + "." + side, "expected {body = \"...\", node = N}", &sn);
      rd.CheckKeys(*sn.as_table(), where + "." + side, {"body", "node"});
    }
    const FeBody& ba = NodeRef(rd, bodies, *t["a"].as_table(), where + ".a", &na);
    const FeBody& bb = NodeRef(rd, bodies, *t["b"].as_table(), where + ".b", &nb);
    c.normal = Vector3(rd, t, where, "normal");
    c.tangent = Vector3(rd, t, where, "tangent");
    for (int d = 0; d < 3; ++d) {
      c.dofs_a.push_back(DofOf(ba, na, d + 1));
      c.dofs_b.push_back(DofOf(bb, nb, d + 1));
      const bool used = c.normal[d] != 0.0 || c.tangent[d] != 0.0;
      if (used && (c.dofs_a.back() < 0 || c.dofs_b.back() < 0)) {
        rd.Fail(where,
                std::string("the frame has a ") + kComponents[d + 1] +
                    " component but a node of the pair has no " + kComponents[d + 1] + " DOF",
                &t);
      }
    }
    c.kn = rd.NonNegative(t, where, "kn");
    c.kt = rd.Positive(t, where, "kt");
    c.mu = rd.NonNegative(t, where, "mu");
    c.normal_preload = rd.NonNegative(t, where, "normal_preload", 0.0);
    resolved->push_back(toml::table{{"name", c.name}, {"kn", c.kn}, {"kt", c.kt}, {"mu", c.mu}});
    cs->contact_names.push_back(c.name);
    cs->model.contacts.push_back(std::move(c));
  }
}

int DofRef(const Reader& rd, const std::vector<FeBody>& bodies, const toml::table& t,
           const std::string& where) {
  int64_t node = 0;
  const FeBody& b = NodeRef(rd, bodies, t, where, &node);
  const double cv = rd.Number(t, where, "component");
  const int dof = cv == std::floor(cv) ? DofOf(b, node, static_cast<int>(cv)) : -1;
  if (dof < 0) {
    rd.Fail(where + ".component",
            "node " + std::to_string(node) + " of '" + b.name +
                "' has no DOF with this component (1..6 = x..rz)",
            t.get("component"));
  }
  return dof;
}

void ReadLoadsAndResponse(const Reader& rd, const toml::table& root,
                          const std::vector<FeBody>& bodies, Model* m) {
  const int n = m->num_dofs();
  const toml::array& arr = rd.Array(root, "", "loads");
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "loads[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, arr, i, where);
    rd.CheckKeys(t, where, {"body", "node", "component", "harmonic", "cos", "sin"});
    const int dof = DofRef(rd, bodies, t, where);
    const double hv = rd.Number(t, where, "harmonic");
    if (hv < 0 || hv != std::floor(hv))
      rd.Fail(where + ".harmonic", "expected an integer >= 0", t.get("harmonic"));
    const int h = static_cast<int>(hv);
    const double sv = rd.NumberOr(t, where, "sin", 0.0);
    if (h == 0 && sv != 0.0)
      rd.Fail(where + ".sin", "a static load has no sine part", t.get("sin"));
    HarmonicLoad* target = nullptr;
    for (HarmonicLoad& l : m->loads) target = l.harmonic == h ? &l : target;
    if (!target) {
      m->loads.push_back(HarmonicLoad{h, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)});
      target = &m->loads.back();
    }
    target->cos[dof] += rd.Number(t, where, "cos");
    target->sin[dof] += sv;
  }
  const toml::node& rn = rd.Require(root, "", "response");
  if (!rn.is_table()) rd.Fail("response", "expected {body, node, component}", &rn);
  rd.CheckKeys(*rn.as_table(), "response", {"body", "node", "component"});
  m->response_dof = DofRef(rd, bodies, *rn.as_table(), "response");
}

}  // namespace

Case ParseAssembly(const toml::table& root, const std::string& source_name,
                   const std::vector<ParameterOverride>& overrides) {
  Reader rd(source_name);
  rd.CheckKeys(root, "",
               {"schema", "name", "description", "units", "parameters", "bodies", "contacts",
                "loads", "response", "analysis"});
  Case cs;
  cs.source = source_name;
  const std::string units = rd.String(root, "", "units");
  if (units != "SI")
    rd.Fail("units", "only \"SI\" is supported, got \"" + units + "\"", root.get("units"));
  cs.name = rd.String(root, "", "name");
  cs.description = rd.StringOr(root, "", "description", "");
  toml::table resolved{{"schema", "fricrom-assembly-1"}, {"units", "SI"}, {"name", cs.name}};
  ParseParameters(rd, root, overrides, &cs, &resolved);
  const fs::path base = fs::path(source_name).parent_path();
  toml::array rbodies, rcontacts;
  const std::vector<FeBody> bodies = ReadBodies(rd, root, base, &cs.model, &rbodies);
  ReadContacts(rd, root, bodies, &cs, &rcontacts);
  ReadLoadsAndResponse(rd, root, bodies, &cs.model);
  resolved.insert("bodies", std::move(rbodies));
  resolved.insert("contacts", std::move(rcontacts));
  ParseAnalysis(rd, root, rd.Array(root, "", "loads"), cs.model.contacts.size(),
                BalanceKind::kCondensed, &cs.analysis, &resolved);
  FinishCase(resolved, &cs);
  return cs;
}

}  // namespace fricrom::detail
