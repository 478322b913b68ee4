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

// Reads a lumped case (schema fricrom-case-1) section by section into the Case and the resolved
// table (the case as run, with every default filled in) that FinishCase records.
class LumpedCaseParser {
 public:
  LumpedCaseParser(Reader& rd, const toml::table& root) : rd_(rd), root_(root) {}

  Case Parse(const std::vector<ParameterOverride>& overrides) {
    ParseHeader(overrides);
    ParseBodies();
    ParseSprings();
    ParseContacts();
    const toml::array& loads = ParseLoads();
    ParseResponse();
    detail::ParseAnalysis(rd_, root_, loads, m().contacts.size(), BalanceKind::kFull, &cs_.analysis,
                          &resolved_);
    detail::FinishCase(resolved_, &cs_);
    return std::move(cs_);
  }

 private:
  Model& m() { return cs_.model; }

  void ParseHeader(const std::vector<ParameterOverride>& overrides) {
    rd_.CheckKeys(root_, "",
                  {"schema", "name", "description", "units", "parameters", "bodies", "springs",
                   "contacts", "loads", "response", "analysis"});
    const std::string schema = rd_.String(root_, "", "schema");
    if (schema != "fricrom-case-1") {
      rd_.Fail("schema",
               "expected \"fricrom-case-1\" (lumped) or \"fricrom-assembly-1\" / "
               "\"fricrom-assembly-2\" (FE), got \"" +
                   schema + "\"",
               root_.get("schema"));
    }
    const std::string units = rd_.String(root_, "", "units");
    if (units != "SI")
      rd_.Fail("units", "only \"SI\" is supported, got \"" + units + "\"", root_.get("units"));
    cs_.source = rd_.source();
    cs_.name = rd_.String(root_, "", "name");
    cs_.description = rd_.StringOr(root_, "", "description", "");
    detail::ParseParameters(rd_, root_, overrides, &cs_, nullptr);
    resolved_.insert("schema", "fricrom-case-1");
    resolved_.insert("units", "SI");
    resolved_.insert("name", cs_.name);
    if (!cs_.description.empty()) resolved_.insert("description", cs_.description);
    toml::table p;
    for (const auto& [k, v] : cs_.parameters) p.insert(k, v);
    resolved_.insert("parameters", std::move(p));
  }

  std::vector<std::string> Directions(const toml::table& t, const std::string& where) {
    if (!t.get("directions")) return {"x", "y"};
    std::vector<std::string> out;
    const toml::array& dirs = rd_.Array(t, where, "directions");
    for (const auto& d : dirs) {
      if (!d.is_string() || (*d.value<std::string>() != "x" && *d.value<std::string>() != "y")) {
        rd_.Fail(where + ".directions", "entries must be \"x\" or \"y\"", &d);
      }
      out.push_back(*d.value<std::string>());
    }
    if (out.empty()) rd_.Fail(where + ".directions", "must not be empty", t.get("directions"));
    return out;
  }

  // One body: its DOFs with their diagonal mass, ground stiffness and ground damping.
  void ParseBody(const toml::table& t, const std::string& where, toml::array* rbodies) {
    rd_.CheckKeys(t, where,
                  {"name", "kind", "mass", "ground_stiffness", "ground_damping", "directions",
                   "mass_x", "mass_y", "ground_stiffness_x", "ground_stiffness_y",
                   "ground_damping_x", "ground_damping_y"});
    Body b;
    b.name = rd_.String(t, where, "name");
    for (const Body& o : bodies_) {
      if (o.name == b.name)
        rd_.Fail(where + ".name", "duplicate body name '" + b.name + "'", t.get("name"));
    }
    const std::string kind = rd_.String(t, where, "kind");
    if (kind != "blade" && kind != "damper") {
      rd_.Fail(where + ".kind", "expected \"blade\" or \"damper\", got \"" + kind + "\"",
               t.get("kind"));
    }
    b.damper = kind == "damper";
    b.directions = Directions(t, where);
    const double mass = rd_.Positive(t, where, "mass");
    const double kg = rd_.NonNegative(t, where, "ground_stiffness", 0.0);
    const double cg = rd_.NonNegative(t, where, "ground_damping", 0.0);
    toml::table rb{{"name", b.name},
                   {"kind", kind},
                   {"mass", mass},
                   {"ground_stiffness", kg},
                   {"ground_damping", cg}};
    for (const std::string& d : b.directions) {
      b.dofs.push_back(static_cast<int>(m().dof_names.size()));
      m().dof_names.push_back(b.name + "." + d);
      masses_.push_back(t.get("mass_" + d) ? rd_.Positive(t, where, "mass_" + d) : mass);
      // Per-direction values (a lumped blade is far stiffer radially than circumferentially).
      kground_.push_back(rd_.NonNegative(t, where, "ground_stiffness_" + d, kg));
      cground_.push_back(rd_.NonNegative(t, where, "ground_damping_" + d, cg));
      if (!b.damper) m().free_dofs.push_back(b.dofs.back());
      if (masses_.back() != mass) rb.insert("mass_" + d, masses_.back());
      if (kground_.back() != kg) rb.insert("ground_stiffness_" + d, kground_.back());
      if (cground_.back() != cg) rb.insert("ground_damping_" + d, cground_.back());
    }
    rbodies->push_back(std::move(rb));
    bodies_.push_back(std::move(b));
  }

  void ParseBodies() {
    const toml::array& arr = rd_.Array(root_, "", "bodies");
    toml::array rbodies;
    for (size_t i = 0; i < arr.size(); ++i) {
      const std::string where = "bodies[" + std::to_string(i) + "]";
      ParseBody(TableAt(rd_, arr, i, where), where, &rbodies);
    }
    resolved_.insert("bodies", std::move(rbodies));
    const int n = static_cast<int>(m().dof_names.size());
    m().mass = Eigen::MatrixXd::Zero(n, n);
    m().stiffness = Eigen::MatrixXd::Zero(n, n);
    m().damping = Eigen::MatrixXd::Zero(n, n);
    for (int d = 0; d < n; ++d) {
      m().mass(d, d) = masses_[d];
      m().stiffness(d, d) = kground_[d];
      m().damping(d, d) = cground_[d];
    }
  }

  const Body* FindBody(const std::string& name, const std::string& key, const toml::node* node) {
    if (name == "ground") return nullptr;
    for (const Body& b : bodies_) {
      if (b.name == name) return &b;
    }
    rd_.Fail(key, "no body named '" + name + "' (or \"ground\")", node);
  }

  // Springs between bodies, acting along every direction both bodies have.
  void ParseSprings() {
    if (!root_.get("springs")) return;
    const toml::array& arr = rd_.Array(root_, "", "springs");
    toml::array rs;
    for (size_t i = 0; i < arr.size(); ++i) {
      const std::string where = "springs[" + std::to_string(i) + "]";
      const toml::table& t = TableAt(rd_, arr, i, where);
      rd_.CheckKeys(t, where, {"between", "stiffness", "damping"});
      const toml::array& between = rd_.Array(t, where, "between");
      if (between.size() != 2 || !between[0].is_string() || !between[1].is_string()) {
        rd_.Fail(where + ".between", "expected two body names", t.get("between"));
      }
      const std::string na(*between[0].value<std::string>()), nb(*between[1].value<std::string>());
      const Body* a = FindBody(na, where + ".between", t.get("between"));
      const Body* b = FindBody(nb, where + ".between", t.get("between"));
      if (a == b)
        rd_.Fail(where + ".between", "a spring needs two different bodies", t.get("between"));
      const double k = rd_.NonNegative(t, where, "stiffness");
      const double c = rd_.NonNegative(t, where, "damping", 0.0);
      AddSpring(a, b, k, c);
      rs.push_back(toml::table{{"between", toml::array{na, nb}}, {"stiffness", k}, {"damping", c}});
    }
    resolved_.insert("springs", std::move(rs));
  }

  void AddSpring(const Body* a, const Body* b, double k, double c) {
    for (const std::string dir : {"x", "y"}) {
      const int da = a ? DirectionIndex(*a, dir) : -1;
      const int db = b ? DirectionIndex(*b, dir) : -1;
      if ((a && da < 0) || (b && db < 0)) continue;
      for (auto [mat, val] : {std::pair{&m().stiffness, k}, std::pair{&m().damping, c}}) {
        if (da >= 0) (*mat)(da, da) += val;
        if (db >= 0) (*mat)(db, db) += val;
        if (da >= 0 && db >= 0) {
          (*mat)(da, db) -= val;
          (*mat)(db, da) -= val;
        }
      }
    }
  }

  // A wedge contact: the damper's inclined face against a counterpart.
  void ParseContact(const toml::table& t, const std::string& where, size_t i,
                    toml::array* rcontacts) {
    rd_.CheckKeys(
        t, where,
        {"name", "damper", "counterpart", "face", "theta", "kn", "kt", "mu", "normal_preload"});
    Contact c;
    c.name = rd_.StringOr(t, where, "name", "contact" + std::to_string(i + 1));
    const std::string dname = rd_.String(t, where, "damper");
    const Body* d = FindBody(dname, where + ".damper", t.get("damper"));
    if (!d) rd_.Fail(where + ".damper", "the damper side cannot be ground", t.get("damper"));
    const std::string cname = rd_.String(t, where, "counterpart");
    const Body* b = FindBody(cname, where + ".counterpart", t.get("counterpart"));
    if (b == d)
      rd_.Fail(where + ".counterpart", "must differ from the damper", t.get("counterpart"));
    const std::string face = rd_.String(t, where, "face");
    if (face != "left" && face != "right") {
      rd_.Fail(where + ".face", "expected \"left\" or \"right\", got \"" + face + "\"",
               t.get("face"));
    }
    const double theta = rd_.Number(t, where, "theta");
    if (!(theta > 0.0 && theta < std::numbers::pi / 2)) {
      rd_.Fail(where + ".theta",
               "expected a base angle in (0, pi/2) rad, got " + Reader::Fmt(theta), t.get("theta"));
    }
    // Face normals point out of the damper into the counterpart (see docs/theory.md).
    const double s = std::sin(theta), co = std::cos(theta);
    c.normal = Eigen::VectorXd{{face == "left" ? -s : s, co}};
    c.tangent = Eigen::VectorXd{{co, face == "left" ? s : -s}};
    for (const std::string dir : {"x", "y"}) {
      const int da = DirectionIndex(*d, dir);
      if (da < 0)
        rd_.Fail(where + ".damper", "a wedge damper body needs both x and y directions",
                 t.get("damper"));
      c.dofs_a.push_back(da);
      const int db = b ? DirectionIndex(*b, dir) : -1;
      if (b && db < 0)
        rd_.Fail(where + ".counterpart", "the counterpart needs both x and y directions",
                 t.get("counterpart"));
      c.dofs_b.push_back(db);
    }
    c.kn = rd_.NonNegative(t, where, "kn");
    c.kt = rd_.Positive(t, where, "kt");
    c.mu = rd_.NonNegative(t, where, "mu");
    c.normal_preload = rd_.NonNegative(t, where, "normal_preload", 0.0);
    rcontacts->push_back(toml::table{{"name", c.name},
                                     {"damper", dname},
                                     {"counterpart", cname},
                                     {"face", face},
                                     {"theta", theta},
                                     {"kn", c.kn},
                                     {"kt", c.kt},
                                     {"mu", c.mu},
                                     {"normal_preload", c.normal_preload}});
    cs_.contact_names.push_back(c.name);
    m().contacts.push_back(std::move(c));
  }

  void ParseContacts() {
    const toml::array& arr = rd_.Array(root_, "", "contacts");
    toml::array rcontacts;
    for (size_t i = 0; i < arr.size(); ++i) {
      const std::string where = "contacts[" + std::to_string(i) + "]";
      ParseContact(TableAt(rd_, arr, i, where), where, i, &rcontacts);
    }
    resolved_.insert("contacts", std::move(rcontacts));
  }

  // Harmonic loads on named DOFs; loads of the same harmonic add up.
  const toml::array& ParseLoads() {
    const toml::array& arr = rd_.Array(root_, "", "loads");
    const int n = static_cast<int>(m().dof_names.size());
    toml::array rloads;
    for (size_t i = 0; i < arr.size(); ++i) {
      const std::string where = "loads[" + std::to_string(i) + "]";
      const toml::table& t = TableAt(rd_, arr, i, where);
      rd_.CheckKeys(t, where, {"dof", "harmonic", "cos", "sin"});
      const std::string dof = rd_.String(t, where, "dof");
      const int di = m().DofIndex(dof);
      if (di < 0)
        rd_.Fail(where + ".dof", "no DOF named '" + dof + "' (use body.x or body.y)", t.get("dof"));
      const double hv = rd_.Number(t, where, "harmonic");
      if (hv < 0 || hv != std::floor(hv))
        rd_.Fail(where + ".harmonic", "expected an integer >= 0", t.get("harmonic"));
      const int h = static_cast<int>(hv);
      const double cv = rd_.Number(t, where, "cos");
      const double sv = rd_.NumberOr(t, where, "sin", 0.0);
      if (h == 0 && sv != 0.0)
        rd_.Fail(where + ".sin", "a static load (harmonic 0) has no sine part", t.get("sin"));
      HarmonicLoad* target = nullptr;
      for (HarmonicLoad& l : m().loads) {
        if (l.harmonic == h) target = &l;
      }
      if (!target) {
        m().loads.push_back(HarmonicLoad{h, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)});
        target = &m().loads.back();
      }
      target->cos[di] += cv;
      target->sin[di] += sv;
      rloads.push_back(toml::table{{"dof", dof}, {"harmonic", h}, {"cos", cv}, {"sin", sv}});
    }
    resolved_.insert("loads", std::move(rloads));
    return arr;
  }

  void ParseResponse() {
    const toml::node& rn = rd_.Require(root_, "", "response");
    if (!rn.is_table()) rd_.Fail("response", "expected a table", &rn);
    const toml::table& t = *rn.as_table();
    rd_.CheckKeys(t, "response", {"dof"});
    const std::string dof = rd_.String(t, "response", "dof");
    m().response_dof = m().DofIndex(dof);
    if (m().response_dof < 0) rd_.Fail("response.dof", "no DOF named '" + dof + "'", t.get("dof"));
    resolved_.insert("response", toml::table{{"dof", dof}});
  }

  Reader& rd_;
  const toml::table& root_;
  Case cs_;
  std::vector<Body> bodies_;
  std::vector<double> masses_, kground_, cground_;  // per DOF, in DOF order
  toml::table resolved_;
};

}  // namespace

Case ParseCase(const std::string& toml_text, const std::string& source_name,
               const std::vector<ParameterOverride>& overrides) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << source_name << ":" << e.source().begin.line << ":" << e.source().begin.column
      << ": TOML syntax error: " << e.description();
    throw CaseError(s.str());
  }
  Case c;
  if (const toml::node* sn = root.get("schema");
      sn && (sn->value<std::string>() == "fricrom-assembly-1" ||
             sn->value<std::string>() == "fricrom-assembly-2")) {
    c = detail::ParseAssembly(root, source_name, overrides);
  } else {
    Reader rd(source_name);
    LumpedCaseParser parser(rd, root);
    c = parser.Parse(overrides);
  }
  // Without a harmonic load every response is zero and every bound an empty statement.
  bool excited = false;
  for (const HarmonicLoad& l : c.model.loads) {
    excited = excited || (l.harmonic >= 1 &&
                          (l.cos.cwiseAbs().maxCoeff() > 0.0 || l.sin.cwiseAbs().maxCoeff() > 0.0));
  }
  if (!excited) {
    Reader(source_name)
        .Fail("loads",
              "no harmonic load (a load with harmonic >= 1 and a nonzero cos or sin): the "
              "forced response would be zero",
              root.get("loads"));
  }
  return c;
}

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
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::is_directory(status)) {
    throw CaseError(path + ": is a directory, expected a case file (TOML)");
  }
  // A device (/dev/zero) never ends: reading it would take all memory.
  if (std::filesystem::is_character_file(status) || std::filesystem::is_block_file(status)) {
    throw CaseError(path + ": is a device, expected a case file (TOML)");
  }
  std::ifstream in(path);
  if (!in) throw CaseError(path + ": cannot open case file");
  std::ostringstream text;
  text << in.rdbuf();
  return ParseCase(text.str(), path, overrides);
}

}  // namespace fricrom
