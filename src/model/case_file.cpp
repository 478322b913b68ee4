#include "fricrom/case_file.h"

#include <muParser.h>
#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include "case_reader.h"

namespace fricrom {
namespace {

using detail::Reader;
using detail::TableAt;

struct Body {
  std::string name;
  bool damper = false;
  std::vector<std::string> directions;
  std::vector<int> dofs;  // per direction
};

int DirectionIndex(const Body& b, const std::string& dir) {
  for (size_t i = 0; i < b.directions.size(); ++i) {
    if (b.directions[i] == dir) return b.dofs[i];
  }
  return -1;
}

}  // namespace

ParameterOverride ParseOverride(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    throw CaseError("--set '" + text + "': expected name=value, e.g. gamma=0.2");
  }
  ParameterOverride o;
  o.name = text.substr(0, eq);
  const std::string value = text.substr(eq + 1);
  try {
    size_t used = 0;
    o.value = std::stod(value, &used);
    if (used != value.size() || !std::isfinite(o.value)) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw CaseError("--set '" + text + "': value '" + value + "' is not a finite number");
  }
  return o;
}

Case LoadCase(const std::string& path, const std::vector<ParameterOverride>& overrides) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw CaseError(path + ": is a directory, expected a case file (TOML)");
  }
  std::ifstream in(path);
  if (!in) throw CaseError(path + ": cannot open case file");
  std::ostringstream text;
  text << in.rdbuf();
  return ParseCase(text.str(), path, overrides);
}

Case ParseCase(const std::string& toml_text, const std::string& source_name,
               const std::vector<ParameterOverride>& overrides) {
  Reader rd(source_name);
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << source_name << ":" << e.source().begin.line << ":" << e.source().begin.column
      << ": TOML syntax error: " << e.description();
    throw CaseError(s.str());
  }
  if (const toml::node* sn = root.get("schema");
      sn && sn->value<std::string>() == "fricrom-assembly-1") {
    return detail::ParseAssembly(root, source_name, overrides);
  }
  rd.CheckKeys(root, "",
               {"schema", "name", "description", "units", "parameters", "bodies", "springs",
                "contacts", "loads", "response", "analysis"});
  Case cs;
  cs.source = source_name;
  const std::string schema = rd.String(root, "", "schema");
  if (schema != "fricrom-case-1") {
    rd.Fail("schema",
            "expected \"fricrom-case-1\" (lumped) or \"fricrom-assembly-1\" (FE), got \"" + schema +
                "\"",
            root.get("schema"));
  }
  const std::string units = rd.String(root, "", "units");
  if (units != "SI")
    rd.Fail("units", "only \"SI\" is supported, got \"" + units + "\"", root.get("units"));
  cs.name = rd.String(root, "", "name");
  cs.description = rd.StringOr(root, "", "description", "");

  detail::ParseParameters(rd, root, overrides, &cs, nullptr);

  Model& m = cs.model;
  std::vector<Body> bodies;
  toml::table resolved;
  resolved.insert("schema", "fricrom-case-1");
  resolved.insert("units", "SI");
  resolved.insert("name", cs.name);
  if (!cs.description.empty()) resolved.insert("description", cs.description);
  {
    toml::table p;
    for (const auto& [k, v] : cs.parameters) p.insert(k, v);
    resolved.insert("parameters", std::move(p));
  }

  // Bodies: DOFs, mass, grounding.
  const toml::array& body_arr = rd.Array(root, "", "bodies");
  std::vector<double> masses, kground, cground;
  toml::array rbodies;
  for (size_t i = 0; i < body_arr.size(); ++i) {
    const std::string where = "bodies[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, body_arr, i, where);
    rd.CheckKeys(t, where,
                 {"name", "kind", "mass", "ground_stiffness", "ground_damping", "directions",
                  "mass_x", "mass_y", "ground_stiffness_x", "ground_stiffness_y",
                  "ground_damping_x", "ground_damping_y"});
    Body b;
    b.name = rd.String(t, where, "name");
    for (const Body& o : bodies) {
      if (o.name == b.name)
        rd.Fail(where + ".name", "duplicate body name '" + b.name + "'", t.get("name"));
    }
    const std::string kind = rd.String(t, where, "kind");
    if (kind != "blade" && kind != "damper") {
      rd.Fail(where + ".kind", "expected \"blade\" or \"damper\", got \"" + kind + "\"",
              t.get("kind"));
    }
    b.damper = kind == "damper";
    if (t.get("directions")) {
      const toml::array& dirs = rd.Array(t, where, "directions");
      for (const auto& d : dirs) {
        if (!d.is_string() || (*d.value<std::string>() != "x" && *d.value<std::string>() != "y")) {
          rd.Fail(where + ".directions", "entries must be \"x\" or \"y\"", &d);
        }
        b.directions.push_back(*d.value<std::string>());
      }
      if (b.directions.empty())
        rd.Fail(where + ".directions", "must not be empty", t.get("directions"));
    } else {
      b.directions = {"x", "y"};
    }
    const double mass = rd.Positive(t, where, "mass");
    const double kg = rd.NonNegative(t, where, "ground_stiffness", 0.0);
    const double cg = rd.NonNegative(t, where, "ground_damping", 0.0);
    for (const std::string& d : b.directions) {
      b.dofs.push_back(static_cast<int>(m.dof_names.size()));
      m.dof_names.push_back(b.name + "." + d);
      masses.push_back(t.get("mass_" + d) ? rd.Positive(t, where, "mass_" + d) : mass);
      // Per-direction values (a lumped blade is far stiffer radially than circumferentially).
      kground.push_back(rd.NonNegative(t, where, "ground_stiffness_" + d, kg));
      cground.push_back(rd.NonNegative(t, where, "ground_damping_" + d, cg));
      if (!b.damper) m.free_dofs.push_back(b.dofs.back());
    }
    toml::table rb{{"name", b.name},
                   {"kind", kind},
                   {"mass", mass},
                   {"ground_stiffness", kg},
                   {"ground_damping", cg}};
    for (size_t k = 0; k < b.directions.size(); ++k) {
      const size_t at = kground.size() - b.directions.size() + k;
      if (masses[at] != mass) rb.insert("mass_" + b.directions[k], masses[at]);
      if (kground[at] != kg) rb.insert("ground_stiffness_" + b.directions[k], kground[at]);
      if (cground[at] != cg) rb.insert("ground_damping_" + b.directions[k], cground[at]);
    }
    rbodies.push_back(std::move(rb));
    bodies.push_back(std::move(b));
  }
  resolved.insert("bodies", std::move(rbodies));
  const int n = static_cast<int>(m.dof_names.size());
  m.mass = Eigen::MatrixXd::Zero(n, n);
  m.stiffness = Eigen::MatrixXd::Zero(n, n);
  m.damping = Eigen::MatrixXd::Zero(n, n);
  for (int d = 0; d < n; ++d) {
    m.mass(d, d) = masses[d];
    m.stiffness(d, d) = kground[d];
    m.damping(d, d) = cground[d];
  }
  auto find_body = [&](const std::string& name, const std::string& key,
                       const toml::node* node) -> const Body* {
    if (name == "ground") return nullptr;
    for (const Body& b : bodies) {
      if (b.name == name) return &b;
    }
    rd.Fail(key, "no body named '" + name + "' (or \"ground\")", node);
  };

  // Springs between bodies, acting along every direction both bodies have.
  if (root.get("springs")) {
    const toml::array& arr = rd.Array(root, "", "springs");
    toml::array rs;
    for (size_t i = 0; i < arr.size(); ++i) {
      const std::string where = "springs[" + std::to_string(i) + "]";
      const toml::table& t = TableAt(rd, arr, i, where);
      rd.CheckKeys(t, where, {"between", "stiffness", "damping"});
      const toml::array& between = rd.Array(t, where, "between");
      if (between.size() != 2 || !between[0].is_string() || !between[1].is_string()) {
        rd.Fail(where + ".between", "expected two body names", t.get("between"));
      }
      const std::string na(*between[0].value<std::string>()), nb(*between[1].value<std::string>());
      const Body* a = find_body(na, where + ".between", t.get("between"));
      const Body* b = find_body(nb, where + ".between", t.get("between"));
      if (a == b)
        rd.Fail(where + ".between", "a spring needs two different bodies", t.get("between"));
      const double k = rd.NonNegative(t, where, "stiffness");
      const double c = rd.NonNegative(t, where, "damping", 0.0);
      for (const std::string dir : {"x", "y"}) {
        const int da = a ? DirectionIndex(*a, dir) : -1;
        const int db = b ? DirectionIndex(*b, dir) : -1;
        if ((a && da < 0) || (b && db < 0)) continue;
        for (auto [mat, val] : {std::pair{&m.stiffness, k}, std::pair{&m.damping, c}}) {
          if (da >= 0) (*mat)(da, da) += val;
          if (db >= 0) (*mat)(db, db) += val;
          if (da >= 0 && db >= 0) {
            (*mat)(da, db) -= val;
            (*mat)(db, da) -= val;
          }
        }
      }
      rs.push_back(toml::table{{"between", toml::array{na, nb}}, {"stiffness", k}, {"damping", c}});
    }
    resolved.insert("springs", std::move(rs));
  }

  // Wedge contacts: the damper's inclined face against a counterpart.
  const toml::array& carr = rd.Array(root, "", "contacts");
  toml::array rcontacts;
  for (size_t i = 0; i < carr.size(); ++i) {
    const std::string where = "contacts[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, carr, i, where);
    rd.CheckKeys(
        t, where,
        {"name", "damper", "counterpart", "face", "theta", "kn", "kt", "mu", "normal_preload"});
    Contact c;
    c.name = rd.StringOr(t, where, "name", "contact" + std::to_string(i + 1));
    const std::string dname = rd.String(t, where, "damper");
    const Body* d = find_body(dname, where + ".damper", t.get("damper"));
    if (!d) rd.Fail(where + ".damper", "the damper side cannot be ground", t.get("damper"));
    const std::string cname = rd.String(t, where, "counterpart");
    const Body* b = find_body(cname, where + ".counterpart", t.get("counterpart"));
    if (b == d)
      rd.Fail(where + ".counterpart", "must differ from the damper", t.get("counterpart"));
    const std::string face = rd.String(t, where, "face");
    if (face != "left" && face != "right") {
      rd.Fail(where + ".face", "expected \"left\" or \"right\", got \"" + face + "\"",
              t.get("face"));
    }
    const double theta = rd.Number(t, where, "theta");
    if (!(theta > 0.0 && theta < std::numbers::pi / 2)) {
      rd.Fail(where + ".theta", "expected a base angle in (0, pi/2) rad, got " + Reader::Fmt(theta),
              t.get("theta"));
    }
    // Face normals point out of the damper into the counterpart (see docs/theory.md).
    const double s = std::sin(theta), co = std::cos(theta);
    c.normal = Eigen::Vector2d(face == "left" ? -s : s, co);
    c.tangent = Eigen::Vector2d(co, face == "left" ? s : -s);
    for (const std::string dir : {"x", "y"}) {
      const int da = DirectionIndex(*d, dir);
      if (da < 0)
        rd.Fail(where + ".damper", "a wedge damper body needs both x and y directions",
                t.get("damper"));
      c.dofs_a.push_back(da);
      const int db = b ? DirectionIndex(*b, dir) : -1;
      if (b && db < 0)
        rd.Fail(where + ".counterpart", "the counterpart needs both x and y directions",
                t.get("counterpart"));
      c.dofs_b.push_back(db);
    }
    c.kn = rd.NonNegative(t, where, "kn");
    c.kt = rd.Positive(t, where, "kt");
    c.mu = rd.NonNegative(t, where, "mu");
    c.normal_preload = rd.NonNegative(t, where, "normal_preload", 0.0);
    rcontacts.push_back(toml::table{{"name", c.name},
                                    {"damper", dname},
                                    {"counterpart", cname},
                                    {"face", face},
                                    {"theta", theta},
                                    {"kn", c.kn},
                                    {"kt", c.kt},
                                    {"mu", c.mu},
                                    {"normal_preload", c.normal_preload}});
    cs.contact_names.push_back(c.name);
    m.contacts.push_back(std::move(c));
  }
  resolved.insert("contacts", std::move(rcontacts));

  // Loads.
  const toml::array& larr = rd.Array(root, "", "loads");
  toml::array rloads;
  for (size_t i = 0; i < larr.size(); ++i) {
    const std::string where = "loads[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, larr, i, where);
    rd.CheckKeys(t, where, {"dof", "harmonic", "cos", "sin"});
    const std::string dof = rd.String(t, where, "dof");
    const int di = m.DofIndex(dof);
    if (di < 0)
      rd.Fail(where + ".dof", "no DOF named '" + dof + "' (use body.x or body.y)", t.get("dof"));
    const double hv = rd.Number(t, where, "harmonic");
    if (hv < 0 || hv != std::floor(hv))
      rd.Fail(where + ".harmonic", "expected an integer >= 0", t.get("harmonic"));
    const int h = static_cast<int>(hv);
    const double cv = rd.Number(t, where, "cos");
    const double sv = rd.NumberOr(t, where, "sin", 0.0);
    if (h == 0 && sv != 0.0)
      rd.Fail(where + ".sin", "a static load (harmonic 0) has no sine part", t.get("sin"));
    HarmonicLoad* target = nullptr;
    for (HarmonicLoad& l : m.loads) {
      if (l.harmonic == h) target = &l;
    }
    if (!target) {
      m.loads.push_back(HarmonicLoad{h, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)});
      target = &m.loads.back();
    }
    target->cos[di] += cv;
    target->sin[di] += sv;
    rloads.push_back(toml::table{{"dof", dof}, {"harmonic", h}, {"cos", cv}, {"sin", sv}});
  }
  resolved.insert("loads", std::move(rloads));

  // Response.
  {
    const toml::node& rn = rd.Require(root, "", "response");
    if (!rn.is_table()) rd.Fail("response", "expected a table", &rn);
    const toml::table& t = *rn.as_table();
    rd.CheckKeys(t, "response", {"dof"});
    const std::string dof = rd.String(t, "response", "dof");
    m.response_dof = m.DofIndex(dof);
    if (m.response_dof < 0) rd.Fail("response.dof", "no DOF named '" + dof + "'", t.get("dof"));
    resolved.insert("response", toml::table{{"dof", dof}});
  }

  detail::ParseAnalysis(rd, root, larr, m.contacts.size(), BalanceKind::kFull, &cs.analysis,
                        &resolved);
  detail::FinishCase(resolved, &cs);
  return cs;
}

}  // namespace fricrom
