// [[bodies]] of an FE assembly: a body is given by its matrix files (stiffness/mass/damping with
// a DOF map, as exported), by a reduced model written by `fricrom reduce` (reduced = "r.h5"), or
// by its FE files reduced on first use and cached (fe = {...}, see docs/case-files.md). Each may
// be placed by a rigid transform (translate, rotate) so that one sector model serves several
// blades, carry Rayleigh damping, and name a mesh deck for the coordinates, node sets and faces
// its interfaces need.
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>

#include "assembly_parts.h"
#include "fricrom/basic_frame.h"
#include "fricrom/reduced_body.h"
#include "fricrom/units.h"

namespace fricrom::detail {

namespace fs = std::filesystem;

bool AssemblyBody::HasNode(int64_t node) const { return mesh.FindNode(node) != nullptr; }

Eigen::Vector3d AssemblyBody::PlacedXyz(int64_t node) const {
  return place.Apply(mesh.FindNode(node)->xyz);
}

Eigen::Vector3d Vector3(const Reader& rd, const toml::table& t, const std::string& where,
                        const std::string& key) {
  const toml::array& a = rd.Array(t, where, key);
  if (a.size() != 3) rd.Fail(where + "." + key, "expected 3 components [x, y, z]", t.get(key));
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = rd.Number(a[i], where + "." + key);
  return v;
}

const AssemblyBody& BodyNamed(const Reader& rd, const std::vector<AssemblyBody>& bodies,
                              const std::string& name, const std::string& where,
                              const toml::node* node) {
  for (const AssemblyBody& b : bodies) {
    if (b.name == name) return b;
  }
  std::string names;
  for (const AssemblyBody& b : bodies) names += (names.empty() ? "" : ", ") + b.name;
  rd.Fail(where, "no body named '" + name + "' (bodies: " + names + ")", node);
}

namespace {

// The matrices of one body in its own frame and row order.
struct BodyMatrices {
  Eigen::MatrixXd k, m, c;  // c: 0x0 when none
  std::vector<DofId> dofs;
  Eigen::MatrixXd accel;  // unit-acceleration loads (body frame), 0x0 when unknown
};

// One matrix of a body, as read: `key = "file"` (a file holding one matrix) or `key = {file =
// "f", matrix = "NAME"}` (one of a multi-matrix file: OP4, DMIG punch, ...). A square real matrix
// with a DOF map: its own (DMIG, Abaqus, CalculiX, MM sidecar) or the body's dof_map.
FeModel ReadBodyMatrix(const Reader& rd, const toml::table& t, const std::string& where,
                       const std::string& key, const fs::path& base, const FeModel* dof_map) {
  const toml::node* node = t.get(key);
  const std::string w = where + "." + key;
  std::string file_name;
  FeReadOptions options;
  if (node && node->is_table()) {
    const toml::table& spec = *node->as_table();
    rd.CheckKeys(spec, w, {"file", "matrix"});
    file_name = rd.String(spec, w, "file");
    options.only_matrix = rd.String(spec, w, "matrix");
  } else {
    file_name = rd.String(t, where, key);
  }
  const fs::path file = base / file_name;
  FeModel fe;
  try {
    fe = ReadFe(file.string(), options);
  } catch (const FeReadError& e) {
    rd.Fail(w, e.what(), node);
  }
  if (fe.matrices.size() != 1) {
    std::string names;
    for (const FeMatrix& m : fe.matrices) names += (names.empty() ? "" : ", ") + m.name;
    rd.Fail(w,
            file.string() + " holds " + std::to_string(fe.matrices.size()) + " matrices (" + names +
                "); name one: " + key + " = {file = \"" + file_name + "\", matrix = \"NAME\"}",
            node);
  }
  FeMatrix& m = fe.matrices[0];
  if (m.rows != m.cols || m.is_complex) {
    rd.Fail(w,
            file.string() + ": expected a square real matrix, " + m.name + " is " +
                std::to_string(m.rows) + " x " + std::to_string(m.cols) +
                (m.is_complex ? " complex" : ""),
            node);
  }
  if (dof_map) {
    const size_t n = dof_map->external_dofs.size();
    if (static_cast<int64_t>(n) != m.rows) {
      rd.Fail(w,
              file.string() + ": matrix " + m.name + " has " + std::to_string(m.rows) +
                  " rows, the dof_map " + dof_map->source + " " + std::to_string(n) + " DOFs",
              node);
    }
    m.row_dofs = m.col_dofs = dof_map->external_dofs;
  }
  if (m.row_dofs.empty()) {
    rd.Fail(w,
            file.string() + " has no DOF map: give dof_map = \"file.csv\" (header " +
                "node,component, one row per matrix row) or the EXTRN punch of the superelement",
            node);
  }
  return fe;
}

// The matrix files of a body in the basic frame: the grids of its mesh and of the files
// themselves (Nastran GRID CP/CD) place the nodes and turn the matrices' DOF directions; the
// files' grids become the body's nodes when it has no mesh.
BodyMatrices FromMatrixFiles(const Reader& rd, const toml::table& t, const std::string& where,
                             const fs::path& base, FeModel* mesh) {
  FeModel dof_map;
  if (t.get("dof_map")) {
    try {
      dof_map = ReadDofMap((base / rd.String(t, where, "dof_map")).string());
    } catch (const FeReadError& e) {
      rd.Fail(where + ".dof_map", e.what(), t.get("dof_map"));
    }
  }
  std::vector<FeModel> files;
  for (const char* key : {"stiffness", "mass", "damping"}) {
    if (std::string(key) == "damping" && !t.get("damping")) break;
    files.push_back(ReadBodyMatrix(rd, t, where, key, base, t.get("dof_map") ? &dof_map : nullptr));
    if (files.back().matrices[0].row_dofs != files[0].matrices[0].row_dofs) {
      rd.Fail(where + "." + key, "its DOF map differs from the stiffness matrix's", t.get(key));
    }
  }
  std::vector<FeModel*> others;
  for (FeModel& f : files) others.push_back(&f);
  others.push_back(&dof_map);  // an EXTRN punch's grids (with their CP/CD) and systems
  try {
    ExpressInBasic(mesh, others);
  } catch (const std::invalid_argument& e) {
    rd.Fail(where, e.what(), &t);
  }
  if (mesh->nodes.empty()) {
    for (const FeModel* f : others) {
      for (const FeNode& n : f->nodes) {
        if (!mesh->FindNode(n.id)) mesh->nodes.push_back(n);
      }
    }
  }
  BodyMatrices b;
  b.k = Eigen::MatrixXd(files[0].matrices[0].real);
  b.m = Eigen::MatrixXd(files[1].matrices[0].real);
  if (files.size() > 2) b.c = Eigen::MatrixXd(files[2].matrices[0].real);
  b.dofs = files[0].matrices[0].row_dofs;
  // Full (unreduced) matrices: the acceleration load is M g exactly.
  b.accel = Eigen::MatrixXd::Zero(b.m.rows(), 3);
  for (int k = 0; k < 3; ++k) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(b.m.rows());
    for (size_t r = 0; r < b.dofs.size(); ++r) g[r] = b.dofs[r].component == k + 1;
    b.accel.col(k) = b.m * g;
  }
  return b;
}

BodyMatrices FromReducedBody(const ReducedBody& r, FeModel* mesh) {
  BodyMatrices b;
  b.k = r.stiffness;
  b.m = r.mass;
  b.c = r.damping;
  b.dofs = r.dofs;
  b.accel = r.unit_acceleration_loads;
  if (mesh->nodes.empty()) mesh->nodes = r.nodes;
  if (mesh->node_sets.empty()) mesh->node_sets = r.node_sets;
  return b;
}

std::vector<std::string> Strings(const Reader& rd, const toml::table& t, const std::string& where,
                                 const std::string& key) {
  std::vector<std::string> out;
  const toml::array& a = rd.Array(t, where, key);
  for (size_t i = 0; i < a.size(); ++i) {
    if (!a[i].is_string()) rd.Fail(where + "." + key, "expected an array of strings", &a[i]);
    out.emplace_back(*a[i].value<std::string>());
  }
  return out;
}

// fe = { stiffness, mass, sets, dofs, boundary, components, modes, cutoff_hz, shift_hz,
//        modal_damping, modal_damping_basis }
ReducedBody ReduceFe(const Reader& rd, const toml::table& body, const std::string& where,
                     const fs::path& base) {
  const toml::node& fn = rd.Require(body, where, "fe");
  const std::string w = where + ".fe";
  if (!fn.is_table()) rd.Fail(w, "expected a table {stiffness = ..., boundary = [...]}", &fn);
  const toml::table& t = *fn.as_table();
  rd.CheckKeys(t, w,
               {"stiffness", "mass", "sets", "dofs", "boundary", "components", "modes", "cutoff_hz",
                "shift_hz", "modal_damping", "modal_damping_basis"});
  FeBodySpec spec;
  spec.stiffness_file = (base / rd.String(t, w, "stiffness")).string();
  if (t.get("mass")) spec.mass_file = (base / rd.String(t, w, "mass")).string();
  if (t.get("sets")) spec.sets_file = (base / rd.String(t, w, "sets")).string();
  if (t.get("dofs")) spec.dofs_file = (base / rd.String(t, w, "dofs")).string();
  spec.boundary_sets = Strings(rd, t, w, "boundary");
  if (t.get("components")) {
    spec.components.clear();
    const toml::array& a = rd.Array(t, w, "components");
    for (size_t i = 0; i < a.size(); ++i) {
      const double c = rd.Number(a[i], w + ".components");
      if (c != std::floor(c) || c < 1 || c > 6) rd.Fail(w + ".components", "expected 1..6", &a[i]);
      spec.components.push_back(static_cast<int>(c));
    }
  }
  const double modes = rd.NumberOr(t, w, "modes", spec.reduction.num_modes);
  if (modes != std::floor(modes) || modes < 0) {
    rd.Fail(w + ".modes", "expected an integer >= 0", t.get("modes"));
  }
  spec.reduction.num_modes = static_cast<int>(modes);
  spec.reduction.cutoff_hz = rd.NonNegative(t, w, "cutoff_hz", 0.0);
  const double shift_hz = rd.NonNegative(t, w, "shift_hz", 0.0);
  spec.reduction.shift = -EigenvalueFromHz(shift_hz);
  spec.modal_damping_ratio = rd.NonNegative(t, w, "modal_damping", 0.0);
  if (t.get("modal_damping_basis")) {
    const std::string basis = rd.String(t, w, "modal_damping_basis");
    if (basis == "component") {
      spec.damping_basis = FeBodySpec::DampingBasis::kComponent;
    } else if (basis != "fixed-interface") {
      rd.Fail(w + ".modal_damping_basis", "expected \"fixed-interface\" or \"component\"",
              t.get("modal_damping_basis"));
    }
  }
  std::string error;
  if (!spec.IsValid(&error)) rd.Fail(w, error, &fn);
  ReduceFeBodyOptions opt;
  opt.cache_dir = (base / ".fricrom-cache").string();
  try {
    return ReduceFeBody(spec, opt);
  } catch (const std::exception& e) {
    rd.Fail(w, e.what(), &fn);
  }
}

// translate = [x, y, z], rotate = {axis = [..], angle_deg = a, centre = [..]}
RigidTransform ReadPlacement(const Reader& rd, const toml::table& t, const std::string& where) {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  if (t.get("translate")) translation = Vector3(rd, t, where, "translate");
  if (!t.get("rotate")) {
    RigidTransform p;
    p.translation = translation;
    return p;
  }
  const toml::node& rn = *t.get("rotate");
  const std::string w = where + ".rotate";
  if (!rn.is_table()) rd.Fail(w, "expected {axis = [x, y, z], angle_deg = a, centre = [..]}", &rn);
  const toml::table& r = *rn.as_table();
  rd.CheckKeys(r, w, {"axis", "angle_deg", "centre"});
  const Eigen::Vector3d axis = Vector3(rd, r, w, "axis");
  if (!(axis.norm() > 0)) rd.Fail(w + ".axis", "expected a non-zero axis", r.get("axis"));
  const Eigen::Vector3d centre =
      r.get("centre") ? Vector3(rd, r, w, "centre") : Eigen::Vector3d::Zero();
  const double angle = rd.Number(r, w, "angle_deg") * std::numbers::pi / 180.0;
  return RigidTransform::FromAxisAngle(axis, angle, centre, translation);
}

// Rotates the physical DOFs (translations 1..3 and rotations 4..6 of each node) of a body's
// matrices into the assembly frame: A -> T A Tᵀ; modal coordinates are frame-free.
void Rotate(const Reader& rd, const std::string& where, const Eigen::Matrix3d& rot,
            BodyMatrices* b) {
  if ((rot - Eigen::Matrix3d::Identity()).norm() == 0.0) return;
  const int n = static_cast<int>(b->dofs.size());
  std::map<std::pair<int64_t, int>, int> row;
  for (int i = 0; i < n; ++i) row[{b->dofs[i].node, b->dofs[i].component}] = i;
  Eigen::MatrixXd t = Eigen::MatrixXd::Identity(n, n);
  for (int i = 0; i < n; ++i) {
    const DofId& d = b->dofs[i];
    if (d.component < 1) continue;
    const int base = d.component <= 3 ? 1 : 4;
    t(i, i) = 0.0;  // the row is the rotation's, filled below
    for (int k = 0; k < 3; ++k) {
      // A direction the rotation does not mix in is not needed (a planar body turned in-plane).
      const double v = rot(d.component - base, k);
      if (std::abs(v) <= 1e-12) continue;
      const auto it = row.find({d.node, base + k});
      if (it == row.end()) {
        rd.Fail(where + ".rotate",
                "node " + std::to_string(d.node) + " has component " + std::to_string(d.component) +
                    " but not " + std::to_string(base + k) + ", which the rotation mixes into it");
      }
      t(i, it->second) = v;
    }
  }
  b->k = t * b->k * t.transpose();
  b->m = t * b->m * t.transpose();
  if (b->c.size()) b->c = t * b->c * t.transpose();
  if (b->accel.size()) b->accel = t * b->accel * rot.transpose();
}

// Entries beyond this magnitude overflow double precision in the products the analysis forms.
constexpr double kLargestEntry = 1e150;
// Relative asymmetry |A − Aᵀ| / |A| (max norms) a body matrix may carry (exporters' round-off).
constexpr double kAsymmetry = 1e-8;
// A pivot of the LDLᵀ factorisation below −kIndefinite·(largest pivot) makes a matrix indefinite.
constexpr double kIndefinite = 1e-8;

// A body's stiffness, mass or damping as the analysis needs it: finite and representable,
// symmetric, and (stiffness, mass) positive semi-definite; else an error naming the body.
void CheckBodyMatrix(const Reader& rd, const std::string& where, const std::string& body,
                     const char* what, const Eigen::MatrixXd& a, bool semi_definite,
                     const toml::node* node) {
  if (a.size() == 0) return;
  const double largest = a.cwiseAbs().maxCoeff();
  const std::string of = std::string(what) + " matrix of body '" + body + "'";
  if (!std::isfinite(largest) || largest > kLargestEntry) {
    std::ostringstream s;
    s << "the " << of << " has an entry of magnitude " << largest
      << " (at most 1e150: larger ones overflow double precision)";
    rd.Fail(where, s.str(), node);
  }
  const double asym = (a - a.transpose()).cwiseAbs().maxCoeff();
  if (asym > kAsymmetry * largest) {
    std::ostringstream s;
    s << "the " << of << " is not symmetric (largest |A - A^T| " << asym
      << " against entries up to " << largest << ")";
    rd.Fail(where, s.str(), node);
  }
  if (!semi_definite) return;
  if (largest == 0.0) {
    if (std::string(what) == "mass")
      rd.Fail(where, "the " + of + " is zero: a body needs mass", node);
    return;
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(0.5 * (a + a.transpose()));
  const Eigen::VectorXd d = ldlt.vectorD();
  if (d.minCoeff() < -kIndefinite * d.cwiseAbs().maxCoeff()) {
    std::ostringstream s;
    s << "the " << of << " is indefinite (a negative pivot " << d.minCoeff()
      << " of its LDL^T factorisation, largest " << d.cwiseAbs().maxCoeff()
      << "): a stiffness or mass must be positive semi-definite";
    rd.Fail(where, s.str(), node);
  }
}

std::string DofName(const std::string& body, const DofId& d) {
  if (d.component == 0 && d.node < 0) return body + ".q" + std::to_string(-d.node);
  return body + "." + std::to_string(d.node) + "." + kComponentNames[d.component];
}

void Place(const Eigen::MatrixXd& s, int offset, Eigen::MatrixXd* dense) {
  dense->block(offset, offset, s.rows(), s.cols()) += s;
}

// One [[bodies]] entry: its matrices (any of the three sources), mesh, placement and damping.
BodyMatrices ReadOneBody(const Reader& rd, const toml::table& t, const std::string& where,
                         const fs::path& base, AssemblyBody* b, toml::table* rb) {
  const int sources =
      (t.get("stiffness") ? 1 : 0) + (t.get("reduced") ? 1 : 0) + (t.get("fe") ? 1 : 0);
  if (sources != 1) {
    rd.Fail(where, "give exactly one of: stiffness (+ mass, damping, dof_map), reduced, fe", &t);
  }
  if (t.get("mesh")) {
    const std::string mesh = (base / rd.String(t, where, "mesh")).string();
    try {
      ReadMeshDeck(mesh, b->mesh);
    } catch (const FeReadError& e) {
      rd.Fail(where + ".mesh", e.what(), t.get("mesh"));
    }
    rb->insert("mesh", rd.String(t, where, "mesh"));
  }
  BodyMatrices m;
  if (!t.get("stiffness")) {
    // Reduced bodies are in the basic frame already (reduce and fe = apply CP/CD); the mesh's
    // own grids give positions.
    try {
      ExpressInBasic(&b->mesh);
    } catch (const std::invalid_argument& e) {
      rd.Fail(where + ".mesh", e.what(), t.get("mesh"));
    }
  }
  if (t.get("stiffness")) {
    m = FromMatrixFiles(rd, t, where, base, &b->mesh);
  } else if (t.get("reduced")) {
    const std::string file = (base / rd.String(t, where, "reduced")).string();
    try {
      m = FromReducedBody(ReadReducedBody(file), &b->mesh);
    } catch (const std::exception& e) {
      rd.Fail(where + ".reduced", e.what(), t.get("reduced"));
    }
    rb->insert("reduced", rd.String(t, where, "reduced"));
  } else {
    m = FromReducedBody(ReduceFe(rd, t, where, base), &b->mesh);
    rb->insert("fe", *t.get("fe")->as_table());
  }
  if (t.get("rayleigh")) {
    const toml::array& a = rd.Array(t, where, "rayleigh");
    if (a.size() != 2) rd.Fail(where + ".rayleigh", "expected [a, b]: C += a M + b K", &a);
    const double ra = rd.Number(a[0], where + ".rayleigh[0]");
    const double rb_ = rd.Number(a[1], where + ".rayleigh[1]");
    if (!(ra >= 0 && rb_ >= 0)) rd.Fail(where + ".rayleigh", "expected a, b >= 0", &a);
    if (m.c.size() == 0) m.c = Eigen::MatrixXd::Zero(m.k.rows(), m.k.cols());
    m.c += ra * m.m + rb_ * m.k;
    rb->insert("rayleigh", toml::array{ra, rb_});
  }
  b->place = ReadPlacement(rd, t, where);
  Rotate(rd, where, b->place.rotation, &m);
  if (t.get("ground_stiffness")) {
    // Weak springs to ground on every translational boundary DOF (isotropic, so placement does
    // not matter): they fix the static position of a body whose static tangential contact
    // forces are prescribed by α (the paper's k_D), e.g. a free damper.
    const double kg = rd.NonNegative(t, where, "ground_stiffness");
    for (size_t d = 0; d < m.dofs.size(); ++d) {
      if (m.dofs[d].node >= 0 && m.dofs[d].component >= 1 && m.dofs[d].component <= 3) {
        m.k(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(d)) += kg;
      }
    }
    rb->insert("ground_stiffness", kg);
  }
  if (t.get("ground_rotation_stiffness")) {
    // The same on every rotational DOF (4-6) [N m/rad]: a beam's or shell's free torsion.
    const double kr = rd.NonNegative(t, where, "ground_rotation_stiffness");
    for (size_t d = 0; d < m.dofs.size(); ++d) {
      if (m.dofs[d].component >= 4 && m.dofs[d].component <= 6) {
        m.k(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(d)) += kr;
      }
    }
    rb->insert("ground_rotation_stiffness", kr);
  }
  return m;
}

}  // namespace

std::vector<AssemblyBody> ReadAssemblyBodies(const Reader& rd, const toml::table& root,
                                             const fs::path& base, Model* model,
                                             toml::array* resolved) {
  const toml::array& arr = rd.Array(root, "", "bodies");
  std::vector<AssemblyBody> bodies;
  std::vector<BodyMatrices> mats;
  int n = 0;
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "bodies[" + std::to_string(i) + "]";
    const toml::table& t = TableAt(rd, arr, i, where);
    rd.CheckKeys(
        t, where,
        {"name", "role", "stiffness", "mass", "damping", "dof_map", "reduced", "fe", "mesh",
         "translate", "rotate", "rayleigh", "ground_stiffness", "ground_rotation_stiffness"});
    AssemblyBody b;
    b.name = rd.String(t, where, "name");
    for (const AssemblyBody& o : bodies) {
      if (o.name == b.name) rd.Fail(where + ".name", "duplicate body name", t.get("name"));
    }
    const std::string role = rd.StringOr(t, where, "role", "blade");
    if (role != "blade" && role != "damper") {
      rd.Fail(where + ".role", "expected \"blade\" or \"damper\", got '" + role + "'",
              t.get("role"));
    }
    b.blade = role == "blade";
    toml::table rb{{"name", b.name}, {"role", role}};
    BodyMatrices m = ReadOneBody(rd, t, where, base, &b, &rb);
    CheckBodyMatrix(rd, where, b.name, "stiffness", m.k, true, &t);
    CheckBodyMatrix(rd, where, b.name, "mass", m.m, true, &t);
    CheckBodyMatrix(rd, where, b.name, "damping", m.c, false, &t);
    b.dofs = m.dofs;
    b.offset = n;
    b.unit_acceleration_loads = m.accel;
    for (size_t d = 0; d < b.dofs.size(); ++d) {
      const DofId& id = b.dofs[d];
      if (id.component < 0 || id.component > 6) {
        rd.Fail(where, "DOF map component " + std::to_string(id.component) + " not in 0..6");
      }
      if (!b.index.emplace(std::make_pair(id.node, id.component), n + static_cast<int>(d)).second) {
        rd.Fail(where, "node " + std::to_string(id.node) + " component " +
                           std::to_string(id.component) + " appears twice in the DOF map");
      }
      model->dof_names.push_back(DofName(b.name, id));
      if (b.blade) model->free_dofs.push_back(n + static_cast<int>(d));
    }
    n += static_cast<int>(b.dofs.size());
    rb.insert("dofs", static_cast<int64_t>(b.dofs.size()));
    for (const char* key : {"stiffness", "mass", "damping", "dof_map"}) {
      if (const toml::node* v = t.get(key)) {
        if (v->is_table()) {
          rb.insert(key, *v->as_table());
        } else {
          rb.insert(key, rd.String(t, where, key));
        }
      }
    }
    resolved->push_back(std::move(rb));
    bodies.push_back(std::move(b));
    mats.push_back(std::move(m));
  }
  if (model->free_dofs.empty()) {
    rd.Fail("bodies",
            "no body is a blade (role = \"blade\"): an assembly needs at least one, the dampers "
            "are condensed onto the blades",
            root.get("bodies"));
  }
  model->stiffness.setZero(n, n);
  model->mass.setZero(n, n);
  model->damping.setZero(n, n);
  for (size_t i = 0; i < bodies.size(); ++i) {
    Place(mats[i].k, bodies[i].offset, &model->stiffness);
    Place(mats[i].m, bodies[i].offset, &model->mass);
    if (mats[i].c.size()) Place(mats[i].c, bodies[i].offset, &model->damping);
  }
  return bodies;
}

}  // namespace fricrom::detail
