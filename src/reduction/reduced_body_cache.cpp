// ReduceFeBody: Craig-Bampton reduction of an FE body named in a case file, on first use, with a
// disk cache keyed by a hash of the content of every input file and of the options.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>

#include "fricrom/basic_frame.h"
#include "fricrom/reduced_body.h"
#include "io/content_hash.h"
#include "io/hdf5_file.h"

namespace fricrom {
namespace {

namespace fs = std::filesystem;

// Bumped whenever the reduction or the file layout changes what a cached body holds.
constexpr const char* kCacheVersion = "fricrom-reduced-body-cache-2 fricrom-reduced-model-1";

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
std::string Upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Decks pulled in by `*INCLUDE, INPUT=file` (relative to the including deck), recursively.
void AddDeckWithIncludes(const fs::path& deck, int depth, std::vector<std::string>* out) {
  if (depth > 10 || std::find(out->begin(), out->end(), deck.string()) != out->end()) return;
  out->push_back(deck.string());
  std::ifstream in(deck);
  std::string line;
  while (std::getline(in, line)) {
    const size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || Upper(line.substr(start, 8)) != "*INCLUDE") continue;
    const size_t key = Upper(line).find("INPUT", start);
    const size_t eq = key == std::string::npos ? key : line.find('=', key);
    if (eq == std::string::npos) continue;
    std::string name = line.substr(eq + 1);
    name = name.substr(0, name.find(','));
    name.erase(0, name.find_first_not_of(" \t\"'"));
    name.erase(name.find_last_not_of(" \t\r\"'") + 1);
    if (!name.empty()) AddDeckWithIncludes(deck.parent_path() / name, depth + 1, out);
  }
}

// The files ReadFe opens for `path` (see ReadFe / ReadCalculix / ReadMatrixMarket).
void AddMatrixFiles(const std::string& path, std::vector<std::string>* out) {
  const std::string ext = Lower(fs::path(path).extension().string());
  if (ext == ".sti" || ext == ".mas" || ext == ".dof" || ext == ".inp") {
    const fs::path prefix = fs::path(path).replace_extension();
    for (const char* e : {".dof", ".sti", ".mas"}) {
      const std::string f = prefix.string() + e;
      if (fs::exists(f) && std::find(out->begin(), out->end(), f) == out->end()) out->push_back(f);
    }
    const fs::path deck = prefix.string() + ".inp";
    if (fs::exists(deck)) AddDeckWithIncludes(deck, 0, out);
    return;
  }
  out->push_back(path);
  if (ext == ".mtx" || ext == ".mm") {
    const std::string sidecar = fs::path(path).replace_extension(".dof.csv").string();
    if (fs::exists(sidecar)) out->push_back(sidecar);
  }
}

// Every option that changes the reduced body, in a fixed text form.
std::string CanonicalOptions(const FeBodySpec& spec) {
  std::vector<int> comps = spec.components;
  std::sort(comps.begin(), comps.end());
  std::string s = "components=";
  for (const int c : comps) s += std::to_string(c);
  s += ";boundary=";
  for (const std::string& b : spec.boundary_sets) s += Upper(b) + ",";
  const CraigBamptonOptions& o = spec.reduction;
  char buf[400];
  std::snprintf(buf, sizeof buf,
                ";mass_file=%d;sets_file=%d;num_modes=%d;cutoff_hz=%.17g;shift=%.17g;"
                "eigen_tolerance=%.17g;max_eigen_iterations=%d;dense_eigen_max_size=%d;"
                "check_tolerance=%.17g;modal_damping_ratio=%.17g",
                spec.mass_file.empty() ? 0 : 1, spec.sets_file.empty() ? 0 : 1, o.num_modes,
                o.cutoff_hz, o.shift, o.eigen_tolerance, o.max_eigen_iterations,
                o.dense_eigen_max_size, o.check_tolerance, spec.modal_damping_ratio);
  return s + buf + (spec.dofs_file.empty() ? "" : ";dofs_file=1");
}

// K (or M) of a model: by the usual export names, else the only matrix of the file.
const FeMatrix& PickMatrix(const FeModel& m, const std::vector<std::string>& names,
                           const std::string& what, const std::string& file) {
  for (const std::string& name : names) {
    if (const FeMatrix* mat = m.Find(name)) return *mat;
  }
  if (m.matrices.size() == 1) return m.matrices[0];
  std::string held;
  for (const FeMatrix& mat : m.matrices) held += (held.empty() ? "" : ", ") + mat.name;
  throw std::invalid_argument(file + ": no " + what + " matrix (looked for " + names[0] + ", " +
                              names[1] + ", " + names[2] + ", " + names[3] + "; it holds " +
                              (held.empty() ? std::string("none") : held) + ")");
}

std::string CacheFile(const FeBodySpec& spec, const std::string& cache_dir,
                      const std::string& key) {
  const std::string stem = fs::path(spec.stiffness_file).stem().string();
  return (fs::path(cache_dir) / (stem + "-" + key + ".h5")).string();
}

// The DOF order of `dofs_file` on every square matrix of its size that has none; its grids and
// systems join `model` (as `reduce --dofs`).
void ApplyDofMap(const std::string& dofs_file, FeModel* model, FeModel* mass_model) {
  const FeModel map = ReadDofMap(dofs_file);
  const int64_t n = static_cast<int64_t>(map.external_dofs.size());
  int applied = 0;
  for (FeModel* m : {model, mass_model}) {
    for (FeMatrix& a : m->matrices) {
      if (a.row_dofs.empty() && a.rows == n && a.cols == n) {
        a.row_dofs = a.col_dofs = map.external_dofs;
        ++applied;
      }
    }
  }
  if (applied == 0) {
    throw std::invalid_argument(dofs_file + ": its DOF order has " + std::to_string(n) +
                                " DOFs; no square matrix of that size without a DOF map in " +
                                model->source);
  }
  for (const FeNode& node : map.nodes) {
    if (!model->FindNode(node.id)) model->nodes.push_back(node);
  }
  model->systems.insert(model->systems.end(), map.systems.begin(), map.systems.end());
  for (const NodeSet& set : map.node_sets) {
    if (!model->FindNodeSet(set.name)) model->node_sets.push_back(set);
  }
}

// Reads the FE files, reduces, and writes the cache file when `key` is not empty.
ReducedBody ReduceFromFiles(const FeBodySpec& spec, const ReduceFeBodyOptions& options,
                            const std::string& key, CraigBamptonSummary* summary) {
  const auto say = [&](const std::string& s) {
    if (options.progress) options.progress(s);
  };
  const std::string stiff_name = fs::path(spec.stiffness_file).filename().string();
  say("reading " + stiff_name + (spec.mass_file.empty() ? "" : " and " + spec.mass_file));
  FeModel model = ReadFe(spec.stiffness_file);
  FeModel mass_model;
  if (!spec.mass_file.empty()) mass_model = ReadFe(spec.mass_file);
  if (!spec.sets_file.empty()) ReadMeshDeck(spec.sets_file, model);
  if (!spec.dofs_file.empty()) ApplyDofMap(spec.dofs_file, &model, &mass_model);
  // Positions and DOF directions of grids with CP/CD in the basic frame, before anything uses them.
  ExpressInBasic(&model, {&mass_model});
  const FeMatrix& k =
      PickMatrix(model, {"STIFFNESS", "KAAX", "KXX", "K"}, "stiffness", spec.stiffness_file);
  const std::string mass_path = spec.mass_file.empty() ? spec.stiffness_file : spec.mass_file;
  const FeMatrix& m = PickMatrix(spec.mass_file.empty() ? model : mass_model,
                                 {"MASS", "MAAX", "MXX", "M"}, "mass", mass_path);
  if (k.rows != m.rows || k.cols != m.cols || k.row_dofs != m.row_dofs) {
    throw std::invalid_argument("stiffness " + k.name + " of " + spec.stiffness_file + " (" +
                                std::to_string(k.rows) + " rows) and mass " + m.name + " of " +
                                mass_path + " (" + std::to_string(m.rows) +
                                " rows) have different sizes or DOF maps");
  }
  BoundarySelection sel;
  try {
    sel = SelectBoundaryDofs(model, k, spec.boundary_sets, spec.components);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(spec.stiffness_file + ": boundary: " + e.what());
  }
  say("reducing " + stiff_name + " (" + std::to_string(k.rows) + " DOFs, " +
      std::to_string(sel.indices.size()) + " boundary DOFs)...");
  const ReducedModel red = ReduceCraigBampton(k.real, m.real, sel.indices, spec.reduction, summary);
  if (summary->status != CraigBamptonStatus::kSuccess) {
    throw std::runtime_error(spec.stiffness_file + ": Craig-Bampton reduction " +
                             ToString(summary->status) + ": " + summary->message);
  }
  say(summary->BriefReport());
  const double zeta = spec.modal_damping_ratio > 0 ? spec.modal_damping_ratio : -1.0;
  ReducedBody body = MakeReducedBody(model, m, sel, red, spec.boundary_sets, zeta);
  if (!key.empty()) {
    const std::string file = CacheFile(spec, options.cache_dir, key);
    std::error_code ec;
    fs::create_directories(options.cache_dir, ec);
    if (ec) {
      throw std::runtime_error("cannot create the cache directory " + options.cache_dir + ": " +
                               ec.message());
    }
    ReducedBodyFileInfo info;
    info.cutoff_hz = spec.reduction.cutoff_hz;
    info.full_dofs = k.rows;
    info.modal_damping_ratio = zeta;
    info.cache_key = key;
    WriteReducedBody(body, file, info);
    say("cached " + file);
  }
  return body;
}

// The cached body, or nothing when the file is absent, unreadable or holds another key.
bool ReadCache(const std::string& file, const std::string& key, ReducedBody* body,
               int64_t* full_dofs, const std::function<void(const std::string&)>& say) {
  std::error_code ec;
  if (!fs::exists(file, ec)) return false;
  try {
    {
      const Hdf5Reader r(file);
      const std::string stored =
          r.HasAttribute("", "cache_key") ? r.StringAttribute("", "cache_key") : "";
      if (stored != key) throw std::runtime_error(file + ": cache_key '" + stored + "' differs");
      if (r.HasAttribute("", "full_dofs")) {
        *full_dofs = static_cast<int64_t>(r.DoubleAttribute("", "full_dofs"));
      }
    }
    *body = ReadReducedBody(file);
    body->from_cache = true;
    return true;
  } catch (const std::exception& e) {
    say(std::string("cache file not usable, reducing again: ") + e.what());
    return false;
  }
}

}  // namespace

bool FeBodySpec::IsValid(std::string* error) const {
  const auto bad = [&](const std::string& msg) {
    if (error) *error = msg;
    return false;
  };
  if (stiffness_file.empty()) return bad("stiffness_file: empty (a matrix file is needed)");
  if (boundary_sets.empty()) return bad("boundary_sets: give at least one node set");
  for (const std::string& s : boundary_sets) {
    if (s.empty()) return bad("boundary_sets: an empty set name");
  }
  std::set<int> seen;
  for (const int c : components) {
    if (c < 1 || c > 6 || !seen.insert(c).second) {
      return bad("components: " + std::to_string(c) + " is outside 1..6 or repeated");
    }
  }
  if (!(modal_damping_ratio >= 0 && modal_damping_ratio < 1)) {
    return bad("modal_damping_ratio: must be in [0, 1)");
  }
  std::string why;
  if (!reduction.IsValid(&why)) return bad("reduction." + why);
  return true;
}

std::vector<std::string> FeBodyInputFiles(const FeBodySpec& spec) {
  std::vector<std::string> files;
  AddMatrixFiles(spec.stiffness_file, &files);
  if (!spec.mass_file.empty()) AddMatrixFiles(spec.mass_file, &files);
  if (!spec.sets_file.empty()) AddDeckWithIncludes(spec.sets_file, 0, &files);
  if (!spec.dofs_file.empty()) files.push_back(spec.dofs_file);
  return files;
}

std::string ReducedBodyCacheKey(const FeBodySpec& spec) {
  Hasher h;
  h.Add(kCacheVersion);
  h.Add(CanonicalOptions(spec));
  for (const std::string& f : FeBodyInputFiles(spec)) HashFile(f, &h);
  return h.Hex();
}

std::string ReducedBodyCachePath(const FeBodySpec& spec, const std::string& cache_dir) {
  return CacheFile(spec, cache_dir, ReducedBodyCacheKey(spec));
}

namespace {

// The cache holds the fixed-interface damping (its key knows the ratio); the component basis is
// derived from the body's own K and M after it is read or reduced.
ReducedBody WithDamping(const FeBodySpec& spec, ReducedBody body) {
  if (spec.damping_basis == FeBodySpec::DampingBasis::kComponent && spec.modal_damping_ratio > 0) {
    body.damping = ComponentModalDamping(body.stiffness, body.mass, spec.modal_damping_ratio);
  }
  return body;
}

}  // namespace

ReducedBody ReduceFeBody(const FeBodySpec& spec, const ReduceFeBodyOptions& options,
                         CraigBamptonSummary* summary) {
  std::string why;
  if (!spec.IsValid(&why)) throw std::invalid_argument("FeBodySpec: " + why);
  const auto say = [&](const std::string& s) {
    if (options.progress) options.progress(s);
  };
  CraigBamptonSummary local;
  CraigBamptonSummary* s = summary ? summary : &local;
  *s = CraigBamptonSummary{};
  std::string key;
  if (!options.cache_dir.empty()) {
    key = ReducedBodyCacheKey(spec);
    const std::string file = CacheFile(spec, options.cache_dir, key);
    ReducedBody body;
    int64_t full_dofs = 0;
    if (ReadCache(file, key, &body, &full_dofs, say)) {
      s->message = "read from the cache " + file;
      s->num_boundary = body.num_boundary;
      s->modes = static_cast<int>(body.modal_frequencies_hz.size());
      s->num_dofs = static_cast<int>(full_dofs);
      s->num_interior = std::max(s->num_dofs - s->num_boundary, 0);
      s->frequencies_hz.assign(body.modal_frequencies_hz.data(),
                               body.modal_frequencies_hz.data() + s->modes);
      say(s->message);
      return WithDamping(spec, std::move(body));
    }
  }
  return WithDamping(spec, ReduceFromFiles(spec, options, key, s));
}

}  // namespace fricrom
