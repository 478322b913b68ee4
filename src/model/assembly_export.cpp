// A lumped case written as an FE assembly (fricrom-assembly-1): the blades as one FE body with a
// node per blade, each damper an FE body of one node, the contacts as node pairs with their
// frames — the same model through the FE path (used to check that path against the lumped one).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fricrom/case_file.h"
#include "fricrom/fe_model.h"

namespace fricrom {
namespace {

namespace fs = std::filesystem;

struct Place {
  std::string body;
  int64_t node = 0;
  int component = 0;
};

std::string TomlFloat(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s(buf);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // TOML float, not integer
  return s;
}

// Where every lumped DOF "name.dir" goes: blades -> body "blades", node = blade order; other
// bodies keep their name with node 1. Components x, y, z -> 1, 2, 3.
std::vector<Place> PlaceDofs(const Model& m) {
  std::vector<bool> blade(m.num_dofs(), false);
  for (int d : m.free_dofs) blade[d] = true;
  std::map<std::string, int64_t> blade_node;
  std::vector<Place> out;
  for (int d = 0; d < m.num_dofs(); ++d) {
    const std::string& name = m.dof_names[d];
    const auto dot = name.rfind('.');
    const std::string body = name.substr(0, dot), dir = name.substr(dot + 1);
    const int comp = dir == "x" ? 1 : dir == "y" ? 2 : dir == "z" ? 3 : 0;
    if (dot == std::string::npos || comp == 0) {
      throw CaseError("export: DOF '" + name + "' is not body.x|y|z");
    }
    if (blade[d]) {
      const auto it = blade_node.emplace(body, static_cast<int64_t>(blade_node.size()) + 1).first;
      out.push_back({"blades", it->second, comp});
    } else {
      out.push_back({body, 1, comp});
    }
  }
  return out;
}

void CheckBlockDiagonal(const Model& m, const std::vector<Place>& at) {
  for (const Eigen::MatrixXd* a : {&m.stiffness, &m.mass, &m.damping}) {
    for (int i = 0; i < a->rows(); ++i) {
      for (int j = 0; j < a->cols(); ++j) {
        if ((*a)(i, j) != 0.0 && at[i].body != at[j].body) {
          throw CaseError("export: DOFs " + m.dof_names[i] + " and " + m.dof_names[j] +
                          " of different bodies are coupled by a matrix: not FE bodies");
        }
      }
    }
  }
}

void WriteBody(const Model& m, const std::vector<Place>& at, const std::string& body,
               const fs::path& dir) {
  std::vector<int> dofs;
  for (int d = 0; d < m.num_dofs(); ++d) {
    if (at[d].body == body) dofs.push_back(d);
  }
  const int n = static_cast<int>(dofs.size());
  auto write = [&](const Eigen::MatrixXd& a, const std::string& suffix, bool with_map) {
    FeMatrix fm;
    fm.name = body + suffix;
    fm.rows = fm.cols = n;
    fm.real.resize(n, n);
    std::vector<Eigen::Triplet<double>> trip;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        if (a(dofs[i], dofs[j]) != 0.0) trip.emplace_back(i, j, a(dofs[i], dofs[j]));
      }
    }
    fm.real.setFromTriplets(trip.begin(), trip.end());
    if (with_map) {
      for (int d : dofs) fm.row_dofs.push_back(DofId{at[d].node, at[d].component});
      fm.col_dofs = fm.row_dofs;
    }
    WriteMatrixMarket(fm, (dir / (body + suffix + ".mtx")).string(),
                      with_map ? (dir / (body + ".dofs.csv")).string() : "");
  };
  write(m.stiffness, ".K", true);
  write(m.mass, ".M", false);
  write(m.damping, ".C", false);
}

}  // namespace

std::string ExportAssembly(const Case& c, const std::string& directory) {
  const Model& m = c.model;
  const std::vector<Place> at = PlaceDofs(m);
  CheckBlockDiagonal(m, at);
  const fs::path dir(directory);
  fs::create_directories(dir);
  std::vector<std::string> bodies;
  for (const Place& p : at) {
    if (std::find(bodies.begin(), bodies.end(), p.body) == bodies.end()) bodies.push_back(p.body);
  }
  std::ostringstream t;
  t << "# " << c.name << " written as an FE assembly by fricrom (from " << c.source << ")\n"
    << "schema = \"fricrom-assembly-1\"\nunits = \"SI\"\nname = \"" << c.name << "-as-fe\"\n"
    << "description = \"" << c.name << " as FE data: blades one FE body (node per blade), each "
    << "damper a one-node FE body, contacts as node pairs with given frames\"\n";
  for (const std::string& b : bodies) {
    WriteBody(m, at, b, dir);
    t << "\n[[bodies]]\nname = \"" << b << "\"\nrole = \"" << (b == "blades" ? "blade" : "damper")
      << "\"\nstiffness = \"" << b << ".K.mtx\"\nmass = \"" << b << ".M.mtx\"\ndamping = \"" << b
      << ".C.mtx\"\ndof_map = \"" << b << ".dofs.csv\"\n";
  }
  for (size_t i = 0; i < m.contacts.size(); ++i) {
    const Contact& ct = m.contacts[i];
    if (ct.dofs_a[0] < 0 || ct.dofs_b[0] < 0) throw CaseError("export: grounded contacts");
    const Place& a = at[ct.dofs_a[0]];
    const Place& b = at[ct.dofs_b[0]];
    Eigen::Vector3d n = Eigen::Vector3d::Zero(), tg = Eigen::Vector3d::Zero();
    for (int d = 0; d < ct.normal.size(); ++d) {
      n[at[ct.dofs_a[d]].component - 1] = ct.normal[d];
      tg[at[ct.dofs_a[d]].component - 1] = ct.tangent[d];
    }
    t << "\n[[contacts]]\nname = \"" << ct.name << "\"\na = { body = \"" << a.body
      << "\", node = " << a.node << " }\nb = { body = \"" << b.body << "\", node = " << b.node
      << " }\nnormal = [" << TomlFloat(n[0]) << ", " << TomlFloat(n[1]) << ", " << TomlFloat(n[2])
      << "]\n"
      << "tangent = [" << TomlFloat(tg[0]) << ", " << TomlFloat(tg[1]) << ", " << TomlFloat(tg[2])
      << "]\n"
      << "kn = " << TomlFloat(ct.kn) << "\nkt = " << TomlFloat(ct.kt)
      << "\nmu = " << TomlFloat(ct.mu) << "\nnormal_preload = " << TomlFloat(ct.normal_preload)
      << "\n";
  }
  for (const HarmonicLoad& l : m.loads) {
    for (int d = 0; d < m.num_dofs(); ++d) {
      if (l.cos[d] == 0.0 && l.sin[d] == 0.0) continue;
      t << "\n[[loads]]\nbody = \"" << at[d].body << "\"\nnode = " << at[d].node
        << "\ncomponent = " << at[d].component << "\nharmonic = " << l.harmonic
        << "\ncos = " << TomlFloat(l.cos[d]) << "\nsin = " << TomlFloat(l.sin[d]) << "\n";
    }
  }
  const Place& r = at[m.response_dof];
  t << "\n[response]\nbody = \"" << r.body << "\"\nnode = " << r.node
    << "\ncomponent = " << r.component << "\n\n[analysis]\nharmonics = " << c.analysis.harmonics
    << "\nsamples_per_period = " << c.analysis.samples_per_period
    << "\nfreq_min_hz = " << TomlFloat(c.analysis.freq_min_hz)
    << "\nfreq_max_hz = " << TomlFloat(c.analysis.freq_max_hz) << "\nalpha = [";
  for (size_t i = 0; i < c.analysis.alpha.size(); ++i) {
    t << (i ? ", " : "") << TomlFloat(c.analysis.alpha[i]);
  }
  t << "]\nbalance = \"condensed\"\n";
  const fs::path path = dir / "case.toml";
  const fs::path tmp = dir / "case.toml.tmp";
  {
    std::ofstream out(tmp);
    out << t.str();
    if (!out) throw CaseError(tmp.string() + ": cannot write");
  }
  fs::rename(tmp, path);
  return path.string();
}

}  // namespace fricrom
