// Issue 9, defects 6 and 7 at the command line: `reduce` with K and M from two files (Abaqus
// *_STIF1/*_MASS1, Matrix Market), boundary nodes by id, node sets from a separate deck, and a
// positive semi-definite mass (a massless boundary node) that used to stop the accuracy table.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

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
const std::string kAbaqus = kSource + "/tests/data/abaqus/";
const std::string kChain = kSource + "/tests/data/reduce/";
const std::string kBeam = kSource + "/tests/data/c3d20r_beam/beam.inp";
const std::string kExtseout = kSource + "/tests/data/extseout/";

std::string To(const TempDir& t) { return " --to " + Quote((t.path() / "r.h5").string()); }

TEST(ReduceFiles, AbaqusStiffnessAndMassFromTwoFilesWithBoundaryNodesById) {
  TempDir tmp;
  const CliRun r =
      Stdout("reduce " + Quote(kAbaqus + "model_STIF1.mtx") + " --mass-file " +
             Quote(kAbaqus + "model_MASS1.mtx") + " --boundary-nodes 1 --modes 2 --json" + To(tmp));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("status"), "SUCCESS");
  EXPECT_EQ(j.at("full_dofs"), 14);
  EXPECT_EQ(j.at("boundary_dofs"), 6);  // node 1 of the B33 beam: 6 DOFs
  EXPECT_EQ(j.at("modes"), 2);
  EXPECT_TRUE(j.at("checks").at("passed").get<bool>());
  EXPECT_TRUE(fs::exists(tmp.path() / "r.h5"));
}

TEST(ReduceFiles, MatrixMarketPairWithAMasslessBoundaryNode) {
  TempDir tmp;
  // Node 1 is massless: with nodes 1 and 2 on the boundary the reduced M is singular (only
  // positive semi-definite); the accuracy table must still compare with the full model.
  const CliRun r =
      Stdout("reduce " + Quote(kChain + "chain5_K.mtx") + " --mass-file " +
             Quote(kChain + "chain5_M.mtx") + " --boundary-nodes 1,2 --modes 3 --json" + To(tmp));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("status"), "SUCCESS");
  EXPECT_EQ(j.at("reduced_infinite_eigenvalues"), 1);  // the massless boundary DOF, reported
  const json& table = j.at("eigen_comparison");
  ASSERT_EQ(table.size(), 3u);
  for (const json& row : table) {
    EXPECT_GT(row.at("reduced_hz").get<double>(), 1.0);   // no spurious 0 Hz modes
    EXPECT_LT(row.at("rel_error").get<double>(), 1e-10);  // all interior modes kept: exact
  }
  // Closed form: the full chain's lowest mode (k = 1000 N/m, unit masses, node 1 massless).
  EXPECT_NEAR(table[0].at("full_hz").get<double>(), 1.452462941099621, 1e-9);
}

TEST(ReduceFiles, NodeSetsFromASeparateDeck) {
  TempDir tmp;
  const fs::path deck = tmp.path() / "sets.inp";
  std::ofstream(deck) << "** boundary of the chain\n*NSET, NSET=ROOT\n1, 2\n";
  const CliRun r = Stdout("reduce " + Quote(kChain + "chain5_K.mtx") + " --mass-file " +
                          Quote(kChain + "chain5_M.mtx") + " --sets " + Quote(deck.string()) +
                          " --boundary ROOT --modes 2 --json" + To(tmp));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(json::parse(r.output).at("boundary_dofs"), 2);
}

TEST(ReduceFiles, BadInputNamesTheOptionAndFile) {
  TempDir tmp;
  // K and M of different models.
  CliRun r = Stderr("reduce " + Quote(kChain + "chain5_K.mtx") + " --mass-file " +
                    Quote(kAbaqus + "model_MASS1.mtx") + " --boundary-nodes 1 --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--mass-file"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("model_MASS1.mtx"), std::string::npos) << r.output;
  // A node that is not in the model.
  r = Stderr("reduce " + Quote(kChain + "chain5_K.mtx") + " --mass-file " +
             Quote(kChain + "chain5_M.mtx") + " --boundary-nodes 9 --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--boundary-nodes"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("node 9"), std::string::npos) << r.output;
  // Not a number; both --boundary and --boundary-nodes; neither.
  r = Stderr("reduce " + Quote(kChain + "chain5_K.mtx") + " --boundary-nodes 1,x --modes 2" +
             To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'x'"), std::string::npos) << r.output;
  r = Stderr("reduce " + Quote(kChain + "chain5_K.mtx") +
             " --boundary A --boundary-nodes 1 --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = Stderr("reduce " + Quote(kChain + "chain5_K.mtx") + " --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--boundary"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(tmp.path() / "r.h5"));
}

// Issue 9, defect 6: the C3D20R beam (ccx MATRIXSTORAGE: M has 30 null directions). Asking for
// more modes than exist used to give NaN matrices with SUCCESS; now every finite interior mode is
// kept, the reduced model reproduces the full model's spectrum, the reference confirms it.
TEST(ReduceFiles, C3D20RBeamWithSemidefiniteMassMoreModesThanExist) {
  TempDir tmp;
  const CliRun r =
      Stdout("reduce " + Quote(kBeam) + " --boundary TIP --modes 100 --json --quiet" + To(tmp));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("status"), "SUCCESS");
  EXPECT_TRUE(j.at("passed").get<bool>());
  EXPECT_EQ(j.at("modes"), 60);  // 75 interior DOFs, 15 of them without mass
  EXPECT_NE(j.at("message").get<std::string>().find("clamped to 60"), std::string::npos);
  EXPECT_TRUE(j.at("checks").at("reference_passed").get<bool>());
  const json& table = j.at("eigen_comparison");
  ASSERT_GE(table.size(), 10u);
  for (const json& row : table) {
    ASSERT_TRUE(row.at("rel_error").is_number()) << row;          // NaN would print as null
    EXPECT_GT(row.at("reduced_hz").get<double>(), 800.0) << row;  // no spurious 0 Hz modes
    EXPECT_LT(row.at("rel_error").get<double>(), 1e-7) << row;    // all finite modes kept: exact
  }
  EXPECT_TRUE(fs::exists(tmp.path() / "r.h5"));
}

// A cutoff above the whole finite spectrum (5 MHz; issue 9: dsaupd info 3 after 49 s): the
// Sylvester count says every finite mode lies below it, the dense solver delivers them.
TEST(ReduceFiles, C3D20RBeamCutoffAboveTheSpectrum) {
  TempDir tmp;
  const CliRun r =
      Stdout("reduce " + Quote(kBeam) + " --boundary TIP --cutoff-hz 5e6 --json --quiet" + To(tmp));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("status"), "SUCCESS");
  EXPECT_EQ(j.at("modes"), 60);
  EXPECT_TRUE(j.at("eigen").at("dense").get<bool>());
}

// Matrix Market without DOF-map sidecars: boundary by 1-based rows; node ids are refused with a
// message that says what to do.
TEST(ReduceFiles, MatrixMarketWithoutDofMapTakesRows) {
  TempDir tmp;
  for (const char* f : {"chain5_K.mtx", "chain5_M.mtx"}) fs::copy_file(kChain + f, tmp.path() / f);
  const std::string pair = Quote((tmp.path() / "chain5_K.mtx").string()) + " --mass-file " +
                           Quote((tmp.path() / "chain5_M.mtx").string());
  CliRun r = Stderr("reduce " + pair + " --boundary-nodes 1 --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--boundary-nodes"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("chain5_K.mtx has no DOF map"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--boundary-dofs"), std::string::npos) << r.output;
  r = Stdout("reduce " + pair + " --boundary-dofs 1,2 --modes 3 --json --quiet" + To(tmp));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("boundary_dofs"), 2);
  EXPECT_NEAR(j.at("eigen_comparison")[0].at("full_hz").get<double>(), 1.452462941099621, 1e-9);
  EXPECT_FALSE(j.at("static_body_load").at("solved").get<bool>());  // no translational DOFs known
  r = Stderr("reduce " + pair + " --boundary-dofs 1,9 --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--boundary-dofs: row 9 is outside 1..5"), std::string::npos) << r.output;
  r = Stderr("reduce " + pair + " --boundary-dofs 1 --components 1 --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--components"), std::string::npos) << r.output;
}

// DOF maps of K and M that differ: exit 2 naming both files and the first row that differs.
TEST(ReduceFiles, DifferentDofMapsNameBothFilesAndTheRow) {
  TempDir tmp;
  for (const char* f : {"chain5_K.mtx", "chain5_M.mtx", "chain5_K.dof.csv"}) {
    fs::copy_file(kChain + f, tmp.path() / f);
  }
  std::ofstream(tmp.path() / "chain5_M.dof.csv") << "node,component\n1,1\n3,1\n2,1\n4,1\n5,1\n";
  const CliRun r = Stderr("reduce " + Quote((tmp.path() / "chain5_K.mtx").string()) +
                          " --mass-file " + Quote((tmp.path() / "chain5_M.mtx").string()) +
                          " --boundary-nodes 1 --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--mass-file"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("chain5_K.mtx"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("chain5_M.mtx"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("row 2 is node 2 component 1 in the stiffness but node 3"),
            std::string::npos)
      << r.output;
}

// Nastran OUTPUT4 K and M by name, DOF order and grids from the punch (EXTRN, GRID), boundary by
// grid id: the free-free superelement keeps its rigid-body modes and mass properties.
TEST(ReduceFiles, NastranOp4WithPunchDofOrderAndGridIds) {
  TempDir tmp;
  const std::string op4 = Quote(kExtseout + "inboard.op4");
  CliRun r = Stdout("reduce " + op4 + " --stiffness KXX --mass MXX --dofs " +
                    Quote(kExtseout + "inboard.pch") +
                    " --boundary-nodes 3,11 --modes 4 --json --quiet" + To(tmp));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("full_dofs"), 32);
  EXPECT_EQ(j.at("boundary_dofs"), 12);  // grids 3 and 11, 6 components each
  EXPECT_TRUE(j.at("checks").at("reference_passed").get<bool>());
  EXPECT_TRUE(j.at("rigid_body").at("passed").get<bool>());
  EXPECT_EQ(j.at("rigid_body").at("reduced_zero_modes"), 6);
  EXPECT_NEAR(j.at("rigid_body").at("reduced").at("mass").get<double>(), 1.755051826, 1e-8);
  // Without the DOF order, grid ids cannot be found; a --dofs file without EXTRN is refused.
  r = Stderr("reduce " + op4 + " --stiffness KXX --mass MXX --boundary-nodes 3 --modes 4" +
             To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("inboard.op4 has no DOF map"), std::string::npos) << r.output;
  r = Stderr("reduce " + op4 + " --stiffness KXX --mass MXX --dofs " +
             Quote(kSource + "/tests/data/dmig/dmig.pch") + " --boundary-nodes 3 --modes 4" +
             To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--dofs"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("dmig.pch"), std::string::npos) << r.output;
}

}  // namespace
