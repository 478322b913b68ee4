// Reduced bodies in the library (include/fricrom/reduced_body.h): ReduceFeBody on the coarse free
// damper and blade sector, the reduced.h5 round trip, equality with the file `fricrom reduce`
// writes, the content-hashed cache (hit, changed input, changed option, damaged cache file), the
// reader's errors on damaged files, and the fixed-interface modal damping.
#include "fricrom/reduced_body.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "app/cli_test_util.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace fricrom {
namespace {

namespace fs = std::filesystem;
using testing::Quote;
using testing::TempDir;

using testing::kMeshes;
const std::string kDamperDir = kMeshes + "damper/coarse/";

// The free damper reduced onto its two contact faces. Its interior is held by the faces, so
// shift 0 would do; a small negative shift (1 Hz) is what `reduce --shift-hz 1` gives.
FeBodySpec DamperSpec(const std::string& sti = kDamperDir + "damper.sti") {
  FeBodySpec s;
  s.stiffness_file = sti;
  s.boundary_sets = {"CONTACT_LEFT", "CONTACT_RIGHT"};
  s.reduction.num_modes = 6;
  s.reduction.shift = -std::pow(kTwoPi * 1.0, 2);
  return s;
}

double RelDiff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return INFINITY;
  if (a.size() == 0) return 0.0;
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

void ExpectSameLayout(const ReducedBody& a, const ReducedBody& b) {
  EXPECT_EQ(a.num_boundary, b.num_boundary);
  EXPECT_EQ(a.dofs, b.dofs);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].id, b.nodes[i].id);
    EXPECT_EQ(a.nodes[i].xyz, b.nodes[i].xyz) << "node " << a.nodes[i].id;
  }
  ASSERT_EQ(a.node_sets.size(), b.node_sets.size());
  for (size_t i = 0; i < a.node_sets.size(); ++i) {
    EXPECT_EQ(a.node_sets[i].name, b.node_sets[i].name);
    EXPECT_EQ(a.node_sets[i].nodes, b.node_sets[i].nodes);
  }
}

void ExpectBitEqual(const ReducedBody& a, const ReducedBody& b) {
  ExpectSameLayout(a, b);
  EXPECT_TRUE(a.stiffness == b.stiffness);
  EXPECT_TRUE(a.mass == b.mass);
  EXPECT_TRUE(a.damping.size() == b.damping.size() && a.damping == b.damping);
  EXPECT_TRUE(a.modal_frequencies_hz == b.modal_frequencies_hz);
  EXPECT_TRUE(a.unit_acceleration_loads == b.unit_acceleration_loads);
}

TEST(ReducedBody, DamperRoundTripThroughReducedH5IsBitEqual) {
  FeBodySpec spec = DamperSpec();
  spec.modal_damping_ratio = 0.01;
  CraigBamptonSummary summary;
  const ReducedBody body = ReduceFeBody(spec, {}, &summary);
  ASSERT_EQ(summary.status, CraigBamptonStatus::kSuccess) << summary.BriefReport();
  EXPECT_FALSE(body.from_cache);
  EXPECT_EQ(body.num_boundary, 162);  // 2 x 27 nodes x 3 translations
  ASSERT_EQ(body.stiffness.rows(), 168);
  ASSERT_EQ(body.dofs.size(), 168u);
  EXPECT_EQ(body.dofs[162], (DofId{-1, 0}));  // modal coordinates: node -1 - k
  EXPECT_EQ(body.dofs[167], (DofId{-6, 0}));
  EXPECT_EQ(body.nodes.size(), 54u);
  ASSERT_EQ(body.node_sets.size(), 2u);
  EXPECT_EQ(body.node_sets[0].name, "CONTACT_LEFT");
  EXPECT_EQ(body.node_sets[0].nodes.size(), 27u);
  EXPECT_TRUE(body.nodes[0].xyz.allFinite());
  // The free body's unit x-acceleration load does the work m * 1 on a rigid x translation
  // (constraint modes carry it exactly): the damper's 9.2865 g.
  ASSERT_EQ(body.unit_acceleration_loads.rows(), 168);
  double work = 0.0;
  for (int i = 0; i < body.num_boundary; ++i) {
    if (body.dofs[i].component == 1) work += body.unit_acceleration_loads(i, 0);
  }
  EXPECT_NEAR(work, 9.2865e-3, 1e-7);

  TempDir tmp;
  const std::string file = (tmp.path() / "damper.h5").string();
  WriteReducedBody(body, file);
  EXPECT_FALSE(fs::exists(file + ".tmp-" + std::to_string(::getpid())));
  const ReducedBody back = ReadReducedBody(file);
  EXPECT_EQ(back.source, file);
  EXPECT_FALSE(back.from_cache);
  ExpectBitEqual(back, body);
}

TEST(ReducedBody, FileWrittenByTheReduceCliEqualsTheLibraryBody) {
  TempDir tmp;
  const std::string out = (tmp.path() / "damper_cli.h5").string();
  const testing::CliRun r = testing::Stdout(
      "reduce " + Quote(kDamperDir + "damper.inp") +
      " --boundary CONTACT_LEFT,CONTACT_RIGHT --modes 6 --shift-hz 1 --modal-damping 0.01 "
      "--no-reference --to " +
      Quote(out) + " --json --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const ReducedBody cli = ReadReducedBody(out);
  FeBodySpec spec = DamperSpec();
  spec.modal_damping_ratio = 0.01;
  const ReducedBody lib = ReduceFeBody(spec, {});
  ExpectSameLayout(cli, lib);
  EXPECT_LT(RelDiff(cli.stiffness, lib.stiffness), 1e-12);
  EXPECT_LT(RelDiff(cli.mass, lib.mass), 1e-12);
  EXPECT_LT(RelDiff(cli.damping, lib.damping), 1e-12);
  EXPECT_LT(RelDiff(cli.unit_acceleration_loads, lib.unit_acceleration_loads), 1e-12);
  EXPECT_LT(RelDiff(cli.modal_frequencies_hz, lib.modal_frequencies_hz), 1e-12);
  EXPECT_EQ(cli.damping.rows(), 168);
}

// Copies the damper's CalculiX job (matrices, DOF map, deck and its *INCLUDEd mesh) into `dir`.
std::string CopyDamper(const fs::path& dir) {
  fs::create_directories(dir);
  for (const char* f :
       {"damper.sti", "damper.mas", "damper.dof", "damper.inp", "damper_mesh.inp"}) {
    fs::copy_file(kDamperDir + f, dir / f);
  }
  return (dir / "damper.sti").string();
}

// Multiplies the value of the first line of a CalculiX .sti (entry 1,1: K stays symmetric).
void ScaleFirstEntry(const std::string& sti, double factor) {
  std::ifstream in(sti);
  std::string first, rest((std::istreambuf_iterator<char>(in)), {});
  const size_t eol = rest.find('\n');
  first = rest.substr(0, eol);
  rest = rest.substr(eol);
  int i = 0, j = 0;
  double v = 0;
  ASSERT_EQ(std::sscanf(first.c_str(), "%d %d %lf", &i, &j, &v), 3);
  char line[100];
  std::snprintf(line, sizeof line, "%d %d  %.13e", i, j, v * factor);
  in.close();
  std::ofstream(sti, std::ios::trunc) << line << rest;
}

TEST(ReducedBody, CacheHitsOnlyForTheSameContentAndOptions) {
  TempDir tmp;
  const std::string sti = CopyDamper(tmp.path() / "in");
  const std::string cache = (tmp.path() / "cache").string();
  std::vector<std::string> said;
  ReduceFeBodyOptions opt;
  opt.cache_dir = cache;
  opt.progress = [&](const std::string& s) { said.push_back(s); };
  FeBodySpec spec = DamperSpec(sti);
  const std::vector<std::string> inputs = FeBodyInputFiles(spec);
  EXPECT_EQ(inputs.size(), 5u);  // .dof, .sti, .mas, .inp and the *INCLUDEd damper_mesh.inp

  const ReducedBody first = ReduceFeBody(spec, opt);
  EXPECT_FALSE(first.from_cache);
  const std::string file = ReducedBodyCachePath(spec, cache);
  EXPECT_TRUE(fs::exists(file)) << file;
  EXPECT_EQ(fs::path(file).filename().string().rfind("damper-", 0), 0u);
  ASSERT_FALSE(said.empty());
  EXPECT_NE(said.front().find("reading damper.sti"), std::string::npos) << said.front();

  CraigBamptonSummary s;
  const ReducedBody second = ReduceFeBody(spec, opt, &s);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(s.status, CraigBamptonStatus::kSuccess);
  EXPECT_NE(s.message.find("cache"), std::string::npos) << s.message;
  EXPECT_EQ(s.num_dofs, 990);
  EXPECT_EQ(s.modes, 6);
  ExpectBitEqual(second, first);

  // A changed input file re-reduces under another key; so does an *INCLUDEd deck (key only).
  const std::string key_before = ReducedBodyCacheKey(spec);
  ScaleFirstEntry(sti, 1.0 + 1e-6);
  const std::string key_changed = ReducedBodyCacheKey(spec);
  EXPECT_NE(key_changed, key_before);
  const ReducedBody changed = ReduceFeBody(spec, opt);
  EXPECT_FALSE(changed.from_cache);
  EXPECT_TRUE(fs::exists(ReducedBodyCachePath(spec, cache)));
  EXPECT_FALSE(changed.stiffness == first.stiffness);
  std::ofstream(tmp.path() / "in" / "damper_mesh.inp", std::ios::app) << "** comment\n";
  EXPECT_NE(ReducedBodyCacheKey(spec), key_changed);

  // A changed option re-reduces.
  spec.reduction.num_modes = 8;
  const ReducedBody eight = ReduceFeBody(spec, opt);
  EXPECT_FALSE(eight.from_cache);
  EXPECT_EQ(eight.modal_frequencies_hz.size(), 8);

  // A truncated cache file is reduced again and replaced, not thrown and not trusted.
  const std::string eight_file = ReducedBodyCachePath(spec, cache);
  const auto size = fs::file_size(eight_file);
  fs::resize_file(eight_file, size / 2);
  said.clear();
  const ReducedBody again = ReduceFeBody(spec, opt);
  EXPECT_FALSE(again.from_cache);
  ExpectBitEqual(again, eight);
  bool reported = false;
  for (const std::string& line : said) reported |= line.find("not usable") != std::string::npos;
  EXPECT_TRUE(reported);
  EXPECT_EQ(fs::file_size(eight_file), size);
  EXPECT_TRUE(ReduceFeBody(spec, opt).from_cache);
}

// ---- Reader errors on damaged files (edited with the HDF5 C API, not with our writer) ------

ReducedBody SmallBody() {
  ReducedBody b;
  b.stiffness = Eigen::Matrix3d{{2, -1, 0}, {-1, 2, 0}, {0, 0, 4}};
  b.mass = Eigen::Matrix3d::Identity();
  b.dofs = {{7, 1}, {8, 1}, {-1, 0}};
  b.num_boundary = 2;
  b.modal_frequencies_hz = Eigen::VectorXd::Constant(1, 2.0 / kTwoPi);
  b.nodes = {FeNode{7, {0, 0, 0}, 0, 0}, FeNode{8, {1, 0, 0}, 0, 0}};
  b.node_sets = {NodeSet{"FACE", {7, 8}}};
  return b;
}

// Applies `edit` to a copy of a valid file, then expects ReadReducedBody to name the file and
// `fragment`.
template <typename Edit>
void ExpectReadError(const std::string& fragment, Edit edit) {
  TempDir tmp;
  const std::string file = (tmp.path() / "body.h5").string();
  WriteReducedBody(SmallBody(), file);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  edit(f);
  H5Fclose(f);
  try {
    ReadReducedBody(file);
    ADD_FAILURE() << "no error; expected one naming " << fragment;
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file), std::string::npos) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
  }
}

void ReplaceDoubles(hid_t f, const char* name, const std::vector<hsize_t>& dims,
                    const std::vector<double>& v) {
  H5Ldelete(f, name, H5P_DEFAULT);
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t d =
      H5Dcreate2(f, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Dclose(d);
  H5Sclose(space);
}

void ReplaceStringAttribute(hid_t f, const char* name, const char* value) {
  H5Adelete(f, name);
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, std::strlen(value));
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(f, name, t, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, t, value);
  H5Aclose(a);
  H5Sclose(space);
  H5Tclose(t);
}

TEST(ReducedBody, ReaderNamesTheFileAndTheDamagedDataset) {
  ExpectReadError("'reduced/mass'", [](hid_t f) { H5Ldelete(f, "reduced/mass", H5P_DEFAULT); });
  ExpectReadError("reduced/mass is 2 x 2", [](hid_t f) {
    ReplaceDoubles(f, "reduced/mass", {2, 2}, {1, 0, 0, 1});
  });
  ExpectReadError("reduced/stiffness has a non-finite value (row 2, column 1)", [](hid_t f) {
    ReplaceDoubles(f, "reduced/stiffness", {3, 3}, {2, -1, 0, NAN, 2, 0, 0, 0, 4});
  });
  ExpectReadError("reduced/fixed_interface_hz", [](hid_t f) {
    ReplaceDoubles(f, "reduced/fixed_interface_hz", {2}, {1, 2});  // 2 modes, num_boundary 2
  });
  ExpectReadError("unknown schema",
                  [](hid_t f) { ReplaceStringAttribute(f, "schema", "fricrom-reduced-model-99"); });
  ExpectReadError("'CHECKS_FAILED'",
                  [](hid_t f) { ReplaceStringAttribute(f, "status", "CHECKS_FAILED"); });
  ExpectReadError("boundary/sets/FACE has node 9", [](hid_t f) {
    H5Ldelete(f, "boundary/sets/FACE", H5P_DEFAULT);
    const hsize_t n = 1;
    const int64_t id = 9;
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t d = H5Dcreate2(f, "boundary/sets/FACE", H5T_NATIVE_INT64, space, H5P_DEFAULT,
                               H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &id);
    H5Dclose(d);
    H5Sclose(space);
  });

  // The small body itself reads back, with its fixed-length-free layout intact.
  TempDir tmp;
  const std::string file = (tmp.path() / "ok.h5").string();
  WriteReducedBody(SmallBody(), file);
  const ReducedBody b = ReadReducedBody(file);
  EXPECT_EQ(b.dofs, SmallBody().dofs);
  EXPECT_EQ(b.damping.size(), 0);
  EXPECT_EQ(b.unit_acceleration_loads.size(), 0);

  // Not HDF5 at all / truncated / missing.
  const std::string text = (tmp.path() / "text.h5").string();
  std::ofstream(text) << "not hdf5\n";
  EXPECT_THROW(ReadReducedBody(text), std::runtime_error);
  fs::resize_file(file, fs::file_size(file) / 2);
  try {
    ReadReducedBody(file);
    ADD_FAILURE() << "a truncated file was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadReducedBody((tmp.path() / "absent.h5").string()), std::runtime_error);
}

TEST(ReducedBody, SpecErrorsNameTheSetOrTheField) {
  FeBodySpec spec = DamperSpec();
  spec.boundary_sets = {"CONTACT_LEFT", "NO_SUCH_SET"};
  try {
    ReduceFeBody(spec, {});
    ADD_FAILURE() << "an unknown set was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("NO_SUCH_SET"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("damper.sti"), std::string::npos) << e.what();
  }
  std::string why;
  spec = DamperSpec();
  spec.components = {1, 7};
  EXPECT_FALSE(spec.IsValid(&why));
  EXPECT_NE(why.find("components"), std::string::npos) << why;
  spec = DamperSpec();
  spec.modal_damping_ratio = -0.1;
  EXPECT_FALSE(spec.IsValid(&why));
  EXPECT_NE(why.find("modal_damping_ratio"), std::string::npos) << why;
  spec = DamperSpec();
  spec.boundary_sets.clear();
  EXPECT_THROW(ReduceFeBody(spec, {}), std::invalid_argument);
  spec = DamperSpec();
  spec.reduction.shift = 1.0;
  EXPECT_FALSE(spec.IsValid(&why));
  EXPECT_NE(why.find("reduction.shift"), std::string::npos) << why;
}

// ---- Modal damping -------------------------------------------------------------------------

TEST(ReducedBody, ModalDampingIsTwoZetaOmegaOnTheFixedInterfaceModesOnly) {
  FeBodySpec spec = DamperSpec();
  spec.modal_damping_ratio = 0.02;
  const ReducedBody b = ReduceFeBody(spec, {});
  const int nb = b.num_boundary, n = static_cast<int>(b.stiffness.rows());
  ASSERT_EQ(b.damping.rows(), n);
  // Known construction: zero on and next to the boundary, diag(2 zeta w_j) on the modes with
  // w_j = 2 pi f_j (M_qq = I, K_qq = w_j^2 to the reduction's check tolerance).
  EXPECT_EQ(b.damping.topRows(nb).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(b.damping.leftCols(nb).cwiseAbs().maxCoeff(), 0.0);
  for (int j = 0; j < n - nb; ++j) {
    const double w = kTwoPi * b.modal_frequencies_hz(j);
    EXPECT_NEAR(b.damping(nb + j, nb + j), 2 * 0.02 * w, 1e-9 * 2 * 0.02 * w) << "mode " << j;
    for (int i = 0; i < n - nb; ++i) {
      if (i != j) {
        EXPECT_EQ(b.damping(nb + i, nb + j), 0.0);
      }
    }
  }
  // Exactly the function `reduce --modal-damping` uses (2 zeta sqrt(K_qq(j, j))).
  EXPECT_TRUE(b.damping == FixedInterfaceModalDamping(b.stiffness, nb, 0.02));
  // zeta = 0: no damping matrix at all.
  spec.modal_damping_ratio = 0.0;
  EXPECT_EQ(ReduceFeBody(spec, {}).damping.size(), 0);
}

// Component basis: every mode of the free body has the ratio zeta, checked on the eigenvalues of
// the damped first-order system (an independent route: a nonsymmetric complex eigensolver), and a
// rigid motion is undamped.
TEST(ReducedBody, ComponentModalDampingGivesEveryElasticModeTheRatio) {
  FeBodySpec spec = DamperSpec();
  spec.modal_damping_ratio = 0.02;
  spec.damping_basis = FeBodySpec::DampingBasis::kComponent;
  const ReducedBody b = ReduceFeBody(spec, {});
  const int n = static_cast<int>(b.stiffness.rows());
  ASSERT_EQ(b.damping.rows(), n);
  EXPECT_TRUE(b.damping == ComponentModalDamping(b.stiffness, b.mass, 0.02));
  // Every mode: the undamped modes (M-orthonormal) diagonalise C to diag(2 zeta w).
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(b.stiffness, b.mass);
  const Eigen::MatrixXd p = modes.eigenvectors().transpose() * b.damping * modes.eigenvectors();
  for (int k = 6; k < n; ++k) {
    const double w = std::sqrt(modes.eigenvalues()[k]);
    EXPECT_NEAR(p(k, k), 2 * 0.02 * w, 1e-8 * 2 * 0.02 * w) << k;
  }
  // A rigid x translation (the constraint modes carry it exactly) meets no damping force.
  Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < b.num_boundary; ++i) r[i] = b.dofs[i].component == 1 ? 1.0 : 0.0;
  EXPECT_LT((b.damping * r).norm(), 1e-9 * b.damping.norm() * r.norm());
  // A well-conditioned random pair (K, M), 6 DOFs: the damped first-order system's eigenvalues
  // (nonsymmetric solver, an independent route) all have -Re λ / |λ| = zeta.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd ka(6, 6), ma(6, 6);
  for (int i = 0; i < 36; ++i) ka(i) = u(rng), ma(i) = u(rng);
  const Eigen::MatrixXd ks = ka * ka.transpose() + 6 * Eigen::MatrixXd::Identity(6, 6);
  const Eigen::MatrixXd ms = ma * ma.transpose() + 6 * Eigen::MatrixXd::Identity(6, 6);
  const Eigen::MatrixXd cs = ComponentModalDamping(ks, ms, 0.05);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(12, 12);
  a.topRightCorner(6, 6).setIdentity();
  a.bottomLeftCorner(6, 6) = -ms.inverse() * ks;
  a.bottomRightCorner(6, 6) = -ms.inverse() * cs;
  const Eigen::EigenSolver<Eigen::MatrixXd> first_order(a);
  for (const std::complex<double>& l : first_order.eigenvalues()) {
    EXPECT_NEAR(-l.real() / std::abs(l), 0.05, 1e-12) << l;
  }
  // Hand case: M = I, K = diag(4, 9): C = diag(2 zeta 2, 2 zeta 3).
  const Eigen::MatrixXd c = ComponentModalDamping(
      Eigen::Vector2d(4, 9).asDiagonal().toDenseMatrix(), Eigen::Matrix2d::Identity(), 0.1);
  EXPECT_NEAR(c(0, 0), 0.4, 1e-14);
  EXPECT_NEAR(c(1, 1), 0.6, 1e-14);
  EXPECT_NEAR(c(0, 1), 0.0, 1e-14);
  EXPECT_THROW(ComponentModalDamping(Eigen::Matrix2d::Identity(), Eigen::Matrix3d::Identity(), 0.1),
               std::invalid_argument);
  EXPECT_THROW(ComponentModalDamping(Eigen::Matrix2d::Identity(), Eigen::Matrix2d::Identity(), -1),
               std::invalid_argument);
  EXPECT_THROW(
      ComponentModalDamping(Eigen::Matrix2d::Identity(), -Eigen::Matrix2d::Identity(), 0.1),
      std::invalid_argument);
}

TEST(ReducedBody, ReduceCliModalDampingIsTheLibraryConstruction) {
  TempDir tmp;
  const std::string out = (tmp.path() / "d.h5").string();
  const testing::CliRun r = testing::Stdout(
      "reduce " + Quote(kDamperDir + "damper.sti") +
      " --boundary CONTACT_LEFT,CONTACT_RIGHT --modes 6 --modal-damping 0.05 --no-reference "
      "--to " +
      Quote(out) + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const ReducedBody b = ReadReducedBody(out);
  EXPECT_TRUE(b.damping == FixedInterfaceModalDamping(b.stiffness, b.num_boundary, 0.05));
  const int nb = b.num_boundary;
  for (int j = 0; j < 6; ++j) {
    EXPECT_NEAR(b.damping(nb + j, nb + j), 2 * 0.05 * kTwoPi * b.modal_frequencies_hz(j),
                1e-9 * b.damping(nb + j, nb + j));
  }
}

// ---- The coarse blade sector: first call vs cached call --------------------------------------

TEST(ReducedBody, CoarseBladeSecondCallReadsTheCache) {
  TempDir tmp;
  FeBodySpec spec;
  spec.stiffness_file = kMeshes + "blade_sector/coarse/blade_sector.sti";
  spec.boundary_sets = {"CONTACT_LEFT", "CONTACT_RIGHT", "EXCITATION", "RESPONSE"};
  spec.reduction.num_modes = 20;
  ReduceFeBodyOptions opt;
  opt.cache_dir = (tmp.path() / "cache").string();
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const ReducedBody first = ReduceFeBody(spec, opt);
  const auto t1 = Clock::now();
  const ReducedBody cached = ReduceFeBody(spec, opt);
  const auto t2 = Clock::now();
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(cached.from_cache);
  EXPECT_EQ(first.num_boundary, 168);
  ExpectBitEqual(cached, first);
  const double reduce_s = std::chrono::duration<double>(t1 - t0).count();
  const double cached_s = std::chrono::duration<double>(t2 - t1).count();
  RecordProperty("first_call_s", std::to_string(reduce_s));
  RecordProperty("cached_call_s", std::to_string(cached_s));
  std::printf("coarse blade: first call %.3f s, cached call %.3f s\n", reduce_s, cached_s);
}

}  // namespace
}  // namespace fricrom
