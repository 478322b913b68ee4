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

const std::string kSource = FRICROM_SOURCE_DIR;
const std::string kAbaqus = kSource + "/tests/data/abaqus/";
const std::string kChain = kSource + "/tests/data/reduce/";

std::string To(const TempDir& t) { return " --to " + Quote((t.path() / "r.h5").string()); }

TEST(ReduceFiles, AbaqusStiffnessAndMassFromTwoFilesWithBoundaryNodesById) {
  TempDir tmp;
  const CliRun r = Stdout("reduce " + Quote(kAbaqus + "model_STIF1.mtx") + " --mass-file " +
                          Quote(kAbaqus + "model_MASS1.mtx") +
                          " --boundary-nodes 1 --modes 2 --json" + To(tmp));
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
  const CliRun r = Stdout("reduce " + Quote(kChain + "chain5_K.mtx") + " --mass-file " +
                          Quote(kChain + "chain5_M.mtx") +
                          " --boundary-nodes 1,2 --modes 3 --json" + To(tmp));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("status"), "SUCCESS");
  const json& table = j.at("eigen_comparison");
  ASSERT_EQ(table.size(), 3u);
  for (const json& row : table) {
    EXPECT_GT(row.at("reduced_hz").get<double>(), 1.0);  // no spurious 0 Hz modes
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
  r = Stderr("reduce " + Quote(kChain + "chain5_K.mtx") + " --boundary-nodes 1,x --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'x'"), std::string::npos) << r.output;
  r = Stderr("reduce " + Quote(kChain + "chain5_K.mtx") + " --boundary A --boundary-nodes 1 --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = Stderr("reduce " + Quote(kChain + "chain5_K.mtx") + " --modes 2" + To(tmp));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--boundary"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(tmp.path() / "r.h5"));
}

}  // namespace
