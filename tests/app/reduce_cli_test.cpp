// End-to-end tests of `fricrom reduce` and `fricrom check-reduced`: the committed CalculiX blade
// sector and damper meshes (meshes/), the Nastran EXTSEOUT superelement, and bad input.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "app/cli_test_util.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using fricrom::testing::CliRun;
using fricrom::testing::Quote;
using fricrom::testing::Stderr;
using fricrom::testing::Stdout;
using fricrom::testing::TempDir;

using fricrom::testing::kSource;
const std::string kBlade = kSource + "/meshes/blade_sector/coarse/blade_sector.inp";
const std::string kDamper = kSource + "/meshes/damper/coarse/damper.inp";
const std::string kBladeSets = "CONTACT_LEFT,CONTACT_RIGHT,EXCITATION,RESPONSE";

// Dimensions of a dataset of an HDF5 file (empty if absent).
std::vector<hsize_t> Dims(const std::string& file, const std::string& dataset) {
  std::vector<hsize_t> dims;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return dims;
  if (H5Lexists(f, dataset.c_str(), H5P_DEFAULT) > 0) {
    const hid_t d = H5Dopen2(f, dataset.c_str(), H5P_DEFAULT);
    const hid_t s = H5Dget_space(d);
    dims.resize(static_cast<size_t>(H5Sget_simple_extent_ndims(s)));
    H5Sget_simple_extent_dims(s, dims.data(), nullptr);
    H5Sclose(s);
    H5Dclose(d);
  }
  H5Fclose(f);
  return dims;
}

TEST(ReduceCli, BladeSectorByCutoffPrintsTheIssueKeysAndWritesTheModel) {
  TempDir tmp;
  const std::string out = (tmp.path() / "blade.h5").string();
  const CliRun r =
      Stdout("reduce " + Quote(kBlade) + " --boundary " + kBladeSets +
             " --cutoff-hz 100000 --modal-damping 0.002 --to " + Quote(out) + " --json --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  for (const char* key : {"full_dofs", "boundary_dofs", "modes", "max_rel_eig_error", "checks",
                          "wall_s", "peak_rss_mb"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j.at("full_dofs"), 4077);
  EXPECT_EQ(j.at("boundary_dofs"), 168);
  const int modes = j.at("modes").get<int>();
  EXPECT_GT(modes, 20);
  EXPECT_LE(j.at("fixed_interface_hz").back().get<double>(), 100000.0);
  EXPECT_TRUE(j.at("checks").at("passed").get<bool>());
  EXPECT_FALSE(j.at("rigid_body").at("free_body").get<bool>());  // clamped root
  // The accuracy table: full vs reduced, first mode well below the cutoff within 1e-6.
  const json& table = j.at("eigen_comparison");
  ASSERT_GE(table.size(), 10u);
  EXPECT_NEAR(table.at(0).at("full_hz").get<double>(), 1089.9, 0.1);
  EXPECT_LT(table.at(0).at("rel_error").get<double>(), 1e-6);
  EXPECT_GE(j.at("max_rel_eig_error").get<double>(), table.at(0).at("rel_error").get<double>());
  EXPECT_LT(j.at("static_body_load").at("rel_error_at_boundary").get<double>(), 1e-9);
  // The reduced model file: matrices, DOF map and coordinates of the boundary nodes.
  const hsize_t n = static_cast<hsize_t>(168 + modes);
  EXPECT_EQ(Dims(out, "reduced/stiffness"), (std::vector<hsize_t>{n, n}));
  EXPECT_EQ(Dims(out, "reduced/mass"), (std::vector<hsize_t>{n, n}));
  EXPECT_EQ(Dims(out, "reduced/damping"), (std::vector<hsize_t>{n, n}));
  EXPECT_EQ(Dims(out, "reduced/dof_node"), (std::vector<hsize_t>{n}));
  EXPECT_EQ(Dims(out, "boundary/node_xyz"), (std::vector<hsize_t>{56, 3}));
  EXPECT_EQ(Dims(out, "boundary/sets/EXCITATION"), (std::vector<hsize_t>{1}));
}

TEST(ReduceCli, InfoListsTheNodeSetsOfTheDeck) {
  const CliRun r = Stdout("info " + Quote(kBlade) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("node_sets").at("CONTACT_LEFT"), 27);
  EXPECT_EQ(j.at("node_sets").at("CONTACT_RIGHT"), 27);
  EXPECT_EQ(j.at("node_sets").at("EXCITATION"), 1);
  EXPECT_EQ(j.at("node_sets").at("ROOT"), 57);
}

TEST(ReduceCli, FreeFreeDamperPassesTheRigidBodyChecks) {
  TempDir tmp;
  const CliRun r = Stdout("reduce " + Quote(kDamper) +
                          " --boundary CONTACT_LEFT,CONTACT_RIGHT --modes 10 --to " +
                          Quote((tmp.path() / "damper.h5").string()) + " --json --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  const json& rb = j.at("rigid_body");
  EXPECT_TRUE(rb.at("free_body").get<bool>());
  EXPECT_EQ(rb.at("reduced_zero_modes"), 6);
  EXPECT_TRUE(rb.at("passed").get<bool>());
  EXPECT_NEAR(rb.at("full").at("mass").get<double>(), 9.2865e-3, 1e-7);
  EXPECT_LT(rb.at("mass_properties_rel_diff").get<double>(), 1e-10);
  EXPECT_TRUE(j.at("checks").at("rigid_body_passed").get<bool>());
  // The six rigid-body modes appear in the comparison table as such.
  const json& table = j.at("eigen_comparison");
  ASSERT_GE(table.size(), 7u);
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(table.at(i).at("rigid_body").get<bool>());
  EXPECT_FALSE(table.at(6).at("rigid_body").get<bool>());
}

TEST(ReduceCli, NastranExtseoutSuperelementPassesTheCraigBamptonChecks) {
  const std::string data = kSource + "/tests/data/extseout/";
  const CliRun r = Stdout("check-reduced " + Quote(data + "inboard.op4") + " --dofs " +
                          Quote(data + "inboard.pch") + " --check-tolerance 1e-6 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("boundary_dofs"), 24);  // grids 3, 11, 19, 27 x 6 components
  EXPECT_EQ(j.at("modes"), 8);           // SPOINTs 2995001-2995008
  EXPECT_TRUE(j.at("checks").at("passed").get<bool>());
  EXPECT_LT(j.at("checks").at("modal_mass_Mqq_minus_I").get<double>(), 1e-6);
  EXPECT_LT(j.at("checks").at("stiffness_coupling_Kbq").get<double>(), 1e-6);
  EXPECT_NEAR(j.at("fixed_interface_hz").at(0).get<double>(), 6.13, 0.01);
  // The superelement is unsupported: its boundary stiffness annihilates rigid motions, including
  // those of grid 11, whose displacements are in the rotated system 10.
  EXPECT_LT(j.at("rigid_body").at("K_R_residual").get<double>(), 1e-9);
  EXPECT_GT(j.at("rigid_body").at("mass_properties").at("mass").get<double>(), 0.0);
}

TEST(ReduceCli, CheckReducedWithoutADofOrderIsABadInputError) {
  const std::string data = kSource + "/tests/data/extseout/";
  const CliRun r = Stderr("check-reduced " + Quote(data + "inboard.op4"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("EXTRN"), std::string::npos) << r.output;
}

TEST(ReduceCli, BadArgumentsAreReportedWithExitCode2) {
  TempDir tmp;
  const std::string twobricks = kSource + "/tests/data/calculix/twobricks.inp";
  const std::string to = " --to " + Quote((tmp.path() / "r.h5").string());
  struct Case {
    std::string args, fragment;
  };
  const std::vector<Case> cases = {
      {"--boundary LEFT --modes 3" + to, "unknown node set 'LEFT'"},
      {"--boundary FIXED --modes 3" + to, "node 1 of set FIXED has no DOF"},
      {"--boundary NALL --modes 3 --cutoff-hz 100" + to, "exactly one of --modes"},
      {"--boundary NALL" + to, "exactly one of --modes"},
      {"--boundary NALL --modes 3 --components 17" + to, "expected digits 1-6"},
      {"--boundary NALL --modes 3 --to " + Quote((tmp.path() / "r.txt").string()), "OUT.h5"},
  };
  for (const Case& c : cases) {
    const CliRun r = Stderr("reduce " + Quote(twobricks) + " " + c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.fragment), std::string::npos) << c.args << "\n" << r.output;
  }
  EXPECT_FALSE(fs::exists(tmp.path() / "r.h5"));
  const CliRun missing =
      Stderr("reduce " + Quote(kSource + "/nope/job.inp") + " --boundary A --modes 2" + to);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.output.find("nope/job"), std::string::npos) << missing.output;
}

}  // namespace
