// FE assembly cases at the command line: the lumped benchmark as FE data gives the lumped bounds
// (1e-8), bounds report the contact pairs and the number of alpha, and verify time-integrates the
// reduced FE cascade (implicit modal scheme) inside the bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "app/cli_test_util.h"
#include "io/hdf5_file.h"

namespace {

using json = nlohmann::json;
using fricrom::testing::CliRun;
using fricrom::testing::Quote;
using fricrom::testing::Stdout;
using fricrom::testing::TempDir;

const std::string kDir = std::string(FRICROM_SOURCE_DIR) + "/meshes/lumped3/";

// The text of an exporter example (examples/exporters/NAME) with its paths to the sample files
// (relative to the example's folder) made absolute, to be edited and written elsewhere.
std::string ExampleToml(const std::string& name) {
  std::ifstream in(std::string(FRICROM_SOURCE_DIR) + "/examples/exporters/" + name);
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  for (size_t at; (at = toml.find("../../tests/")) != std::string::npos;) {
    toml.replace(at, 12, std::string(FRICROM_SOURCE_DIR) + "/tests/");
  }
  return toml;
}

TEST(AssemblyCli, BoundsThroughTheFePathEqualTheLumpedBounds) {
  TempDir tmp;
  const std::string out = " --out " + Quote(tmp.path().string());
  const CliRun fe =
      Stdout("bounds " + Quote(kDir + "as_fe/case.toml") + " --freq 266 --json" + out);
  const CliRun lumped =
      Stdout("bounds " + Quote(kDir + "baseline.toml") + " --freq 266 --json" + out);
  ASSERT_EQ(fe.exit_code, 0) << fe.output;
  ASSERT_EQ(lumped.exit_code, 0) << lumped.output;
  const json a = json::parse(fe.output), b = json::parse(lumped.output);
  for (const char* key : {"y_min", "y_max"}) {
    EXPECT_NEAR(a.at(key).get<double>(), b.at(key).get<double>(), 1e-8 * b.at(key).get<double>())
        << key;
  }
  EXPECT_EQ(a.at("contact_pairs"), 4);
  EXPECT_EQ(a.at("alpha_count"), 4);
  EXPECT_EQ(b.at("contact_pairs"), 4);
}

// --random-seeds N adds N seeds; the JSON counts them and the bounds stay the lumped ones.
TEST(AssemblyCli, ExtraSeedsAreCountedInTheJson) {
  TempDir tmp;
  const CliRun run =
      Stdout("bounds " + Quote(kDir + "as_fe/case.toml") +
             " --freq 266 --json --random-seeds 4 --out " + Quote(tmp.path().string()));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json j = json::parse(run.output);
  EXPECT_EQ(j.at("seeds").at("base"), 5);
  EXPECT_EQ(j.at("seeds").at("interface_patterns"), 0);
  EXPECT_EQ(j.at("seeds").at("random"), 4);
  EXPECT_EQ(j.at("seeds").at("tried"), 9);
  EXPECT_NEAR(j.at("y_max").get<double>(), 2.5305015e-4, 1e-10);
  const CliRun bad = fricrom::testing::Stderr("bounds " + Quote(kDir + "as_fe/case.toml") +
                                              " --freq 266 --random-seeds -3");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("--random-seeds"), std::string::npos) << bad.output;
}

TEST(AssemblyCli, FrfThroughTheFePathEqualsTheLumpedFrf) {
  TempDir tmp;
  const std::string args = " --freq 258,262,270 --json --out " + Quote(tmp.path().string());
  const json a = json::parse(Stdout("frf " + Quote(kDir + "as_fe/case.toml") + args).output);
  const json b = json::parse(Stdout("frf " + Quote(kDir + "baseline.toml") + args).output);
  for (int i = 0; i < 3; ++i) {
    const double ya = a.at("points")[i].at("amplitude"), yb = b.at("points")[i].at("amplitude");
    EXPECT_NEAR(ya, yb, 1e-8 * yb) << i;
  }
}

// The coarse FE cascade at 1040 Hz (all contacts stuck): time integrations from α = 0 and from the
// alternating corners settle, with the implicit modal scheme, onto forced responses inside the
// bounds (to the H = 1 truncation margin), while the corners leave free vibration of the
// full-stick modes (zeta = 0.002) that the windowed amplitude sees through.
TEST(AssemblyCli, VerifyTimeIntegratesTheFeCascadeInsideTheBounds) {
  TempDir tmp;
  const std::string cascade = std::string(FRICROM_SOURCE_DIR) + "/meshes/cascade3/coarse.toml";
  // 128 steps per period: Newmark's period error (ωdt)²/12 = 2e-4, amplified near the 1096 Hz
  // full-stick family, puts the amplitude ~0.7 % above the 256-step one (64 steps: 2.8 %, beyond
  // the 2 % margin, measured under the sanitizers).
  // FRICROM_TEST_TIME_RUNS=1 (the sanitizer build) integrates from α = 0 only: the corner's run
  // takes the same code path, 2.5x as long to settle.
  const char* runs_env = std::getenv("FRICROM_TEST_TIME_RUNS");
  const int runs = runs_env != nullptr ? std::max(1, std::atoi(runs_env)) : 2;
  const CliRun run = Stdout("verify " + Quote(cascade) +
                            " --freq 1040 --alpha-samples 4 --time-runs " + std::to_string(runs) +
                            " --time-steps 128 --json --quiet --out " + Quote(tmp.path().string()));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json j = json::parse(run.output);
  EXPECT_TRUE(j.at("certified").get<bool>()) << j.dump();
  const double lo = j.at("y_min").get<double>(), hi = j.at("y_max").get<double>();
  ASSERT_EQ(j.at("time_integration").size(), static_cast<size_t>(runs));
  for (const json& r : j.at("time_integration")) {
    EXPECT_EQ(r.at("status"), "steady-state") << r.at("message");
    EXPECT_EQ(r.at("scheme"), "implicit-modal");
    EXPECT_GT(r.at("modes_integrated").get<int>(), 3);
    const double y = r.at("amplitude").get<double>();
    EXPECT_GE(y, 0.98 * lo);
    EXPECT_LE(y, 1.02 * hi);
    EXPECT_TRUE(r.at("inside").get<bool>());
  }
}

}  // namespace

namespace {

// The Nastran EXTSEOUT route (docs/exporters.md): OP4 matrices named from the multi-matrix file,
// the DOF order and grids (one in CD = 10) from the EXTRN punch, a semi-definite superelement
// mass; modes, frf and bounds run end to end with finite numbers.
TEST(AssemblyCli, NastranSuperelementPairRunsEveryCommand) {
  TempDir tmp;
  const std::string c =
      Quote(std::string(FRICROM_SOURCE_DIR) + "/examples/exporters/extseout_pair.toml");
  const std::string out = " --out " + Quote(tmp.path().string());
  const CliRun modes = Stdout("modes " + c + " --json");
  ASSERT_EQ(modes.exit_code, 0) << modes.output;
  const json m = json::parse(modes.output);
  // 2 x 32 DOFs: the blade's 32 free, each superelement's mass with one massless direction.
  EXPECT_EQ(m.at("free_dofs").get<int>() + m.at("free_massless").get<int>(), 32);
  EXPECT_EQ(m.at("stick_dofs").get<int>() + m.at("stick_massless").get<int>(), 64);
  EXPECT_GE(m.at("stick_massless").get<int>(), 1);
  for (const auto& f : m.at("stick_hz")) EXPECT_TRUE(std::isfinite(f.get<double>()));
  // The grounded pair's lowest full-stick modes are the springs' (about 4.1 Hz).
  EXPECT_NEAR(m.at("stick_hz")[0].get<double>(), 4.09, 0.02);
  const CliRun frf = Stdout("frf " + c + " --freq 4.1 --json" + out);
  ASSERT_EQ(frf.exit_code, 0) << frf.output;
  const CliRun bounds = Stdout("bounds " + c + " --freq 4.1 --json" + out);
  ASSERT_EQ(bounds.exit_code, 0) << bounds.output;
  const json b = json::parse(bounds.output);
  EXPECT_EQ(b.at("status"), "converged");
  EXPECT_GT(b.at("y_max").get<double>(), 1e-5);
  EXPECT_LE(b.at("y_min").get<double>(), b.at("y_max").get<double>());
}

}  // namespace

namespace {

// The Abaqus route (docs/exporters.md): *MATRIX GENERATE stiffness and mass of a B33 beam with
// its deck, two beams end to end with a node contact; held in torsion by
// ground_rotation_stiffness. Without it the case is an error naming both bodies.
TEST(AssemblyCli, AbaqusBeamPairRunsEveryCommandAndAFreeOneIsAnError) {
  TempDir tmp;
  const std::string file =
      std::string(FRICROM_SOURCE_DIR) + "/examples/exporters/abaqus_beams.toml";
  const std::string out = " --out " + Quote(tmp.path().string());
  const CliRun modes = Stdout("modes " + Quote(file) + " --json");
  ASSERT_EQ(modes.exit_code, 0) << modes.output;
  const json m = json::parse(modes.output);
  EXPECT_GT(m.at("stick_hz")[0].get<double>(), 0.5);  // every direction held
  const CliRun frf = Stdout("frf " + Quote(file) + " --freq 1 --json" + out);
  ASSERT_EQ(frf.exit_code, 0) << frf.output;
  const CliRun bounds = Stdout("bounds " + Quote(file) + " --freq 1 --json" + out);
  ASSERT_EQ(bounds.exit_code, 0) << bounds.output;
  EXPECT_EQ(json::parse(bounds.output).at("status"), "converged");

  // The same case without the rotational springs: the beams' torsion is free.
  std::string toml = ExampleToml("abaqus_beams.toml");
  for (size_t at; (at = toml.find("ground_rotation_stiffness = 1e3\n")) != std::string::npos;) {
    toml.erase(at, std::string("ground_rotation_stiffness = 1e3\n").size());
  }
  const std::string free_case = tmp.path().string() + "/free.toml";
  std::ofstream(free_case) << toml;
  const CliRun err = fricrom::testing::Stderr("modes " + Quote(free_case));
  EXPECT_EQ(err.exit_code, 2) << err.output;
  for (const char* w : {"zero stiffness", "beam1 1", "beam2 1", "ground_rotation_stiffness"}) {
    EXPECT_NE(err.output.find(w), std::string::npos) << w << "\n" << err.output;
  }
}

}  // namespace

namespace {

// `frf` computes the 400-point linear references only where a figure or a flag asks for them;
// the x layout attribute says what the condensed balance stores.
TEST(AssemblyCli, FrfWritesLinearReferencesOnlyWhenAsked) {
  TempDir tmp;
  const std::string c = Quote(kDir + "as_fe/case.toml");
  const std::string out = " --out " + Quote(tmp.path().string());
  ASSERT_EQ(Stdout("frf " + c + " --freq 262 --quiet" + out).exit_code, 0);
  {
    const fricrom::Hdf5Reader h5((tmp.path() / "frf.h5").string());
    EXPECT_FALSE(h5.Has("linear"));
    EXPECT_TRUE(h5.Has("frf/x"));
    EXPECT_NE(h5.StringAttribute("frf", "x_layout").find("relative displacements"),
              std::string::npos);
  }
  ASSERT_EQ(Stdout("frf " + c + " --freq 262 --quiet --linear-references" + out).exit_code, 0);
  const fricrom::Hdf5Reader h5((tmp.path() / "frf.h5").string());
  ASSERT_TRUE(h5.Has("linear/stick_amplitude_m"));
  EXPECT_EQ(h5.Vector("linear/freq_hz").size(), 400);
  EXPECT_TRUE(h5.Vector("linear/stick_amplitude_m").allFinite());
}

}  // namespace

namespace {

// The EXTSEOUT superelement reduced again on first use: fe = {stiffness = OP4, dofs = its EXTRN
// punch, boundary = the punch's ASET grids}.
TEST(AssemblyCli, NastranSuperelementThroughTheFeRoute) {
  TempDir tmp;
  std::string toml = ExampleToml("extseout_pair.toml");
  const std::string data = std::string(FRICROM_SOURCE_DIR) + "/tests/data/extseout/";
  const std::string se2 =
      "stiffness = {file = \"" + data + "inboard.op4\", matrix = \"KXX\"}\nmass = {file = \"" +
      data + "inboard.op4\", matrix = \"MXX\"}\ndof_map = \"" + data + "inboard.pch\"\ntranslate";
  const size_t at = toml.find(se2);
  ASSERT_NE(at, std::string::npos);
  toml.replace(at, se2.size(),
               "fe = {stiffness = \"" + data + "inboard.op4\", dofs = \"" + data +
                   "inboard.pch\", boundary = [\"ASET\"], modes = 4}\ntranslate");
  const std::string file = tmp.path().string() + "/fe_route.toml";
  std::ofstream(file) << toml;
  const CliRun modes = Stdout("modes " + Quote(file) + " --json");
  ASSERT_EQ(modes.exit_code, 0) << fricrom::testing::Stderr("modes " + Quote(file)).output;
  const json m = json::parse(modes.output);
  // se2 reduced to its 4 ASET grids x 3 translations + 4 modes: 16 DOFs beside se1's 32.
  EXPECT_EQ(m.at("stick_dofs").get<int>() + m.at("stick_massless").get<int>(), 32 + 16);
  const CliRun frf =
      Stdout("frf " + Quote(file) + " --freq 4.1 --json --out " + Quote(tmp.path().string()));
  ASSERT_EQ(frf.exit_code, 0) << frf.output;
}

}  // namespace

namespace {

// An [[interfaces]] entry on beam elements (no solid faces) with kn/kt per pair and a normal
// pairs its nodes without faces and gives the node contact's response.
TEST(AssemblyCli, AnInterfaceOnBeamsNeedsNoFaces) {
  TempDir tmp;
  const std::string example =
      std::string(FRICROM_SOURCE_DIR) + "/examples/exporters/abaqus_beams.toml";
  std::string toml = ExampleToml("abaqus_beams.toml");
  const std::string deck = std::string(FRICROM_SOURCE_DIR) + "/tests/data/abaqus/model.inp";
  std::ofstream(tmp.path() / "sets.inp")
      << "*INCLUDE, INPUT=" << deck << "\n*NSET, NSET=TIP\n2\n*NSET, NSET=ROOT\n1\n";
  for (size_t p; (p = toml.find("mesh = \"" + deck + "\"")) != std::string::npos;) {
    toml.replace(p, deck.size() + 9, "mesh = \"sets.inp\"");
  }
  const size_t i = toml.find("[[contacts]]"), j = toml.find("[[loads]]");
  ASSERT_TRUE(i != std::string::npos && j != std::string::npos);
  toml.replace(i, j - i,
               "[[interfaces]]\nname = \"tip\"\na = { body = \"beam2\", set = \"ROOT\" }\n"
               "b = { body = \"beam1\", set = \"TIP\" }\nnormal = [1.0, 0.0, 0.0]\n"
               "slip_direction = [0.0, 1.0, 0.0]\nkn = 1e6\nkt = 1e6\nmu = 0.5\n"
               "normal_preload = 100.0\n\n");
  const std::string file = (tmp.path() / "interface.toml").string();
  std::ofstream(file) << toml;
  const std::string out = " --out " + Quote(tmp.path().string());
  const CliRun a = Stdout("frf " + Quote(example) + " --freq 1 --json" + out);
  const CliRun b = Stdout("frf " + Quote(file) + " --freq 1 --json" + out);
  ASSERT_EQ(a.exit_code, 0) << a.output;
  ASSERT_EQ(b.exit_code, 0) << fricrom::testing::Stderr("frf " + Quote(file) + " --freq 1").output;
  const double ya = json::parse(a.output).at("points")[0].at("amplitude").get<double>();
  const double yb = json::parse(b.output).at("points")[0].at("amplitude").get<double>();
  EXPECT_NEAR(yb, ya, 1e-10 * ya);
}

}  // namespace

namespace {

// The CalculiX route (docs/exporters.md): the coarse cascade's bodies are CalculiX matrices
// reduced on first use (fe = {...}); modes, frf and bounds run on it end to end.
TEST(AssemblyCli, CalculixCascadeRunsEveryCommand) {
  TempDir tmp;
  const std::string c = Quote(std::string(FRICROM_SOURCE_DIR) + "/meshes/cascade3/coarse.toml");
  const std::string out = " --out " + Quote(tmp.path().string());
  const CliRun modes = Stdout("modes " + c + " --json");
  ASSERT_EQ(modes.exit_code, 0) << modes.output;
  const json m = json::parse(modes.output);
  EXPECT_EQ(m.at("stick_massless"), 0);
  for (const auto& f : m.at("stick_hz")) EXPECT_TRUE(std::isfinite(f.get<double>()));
  const CliRun frf = Stdout("frf " + c + " --freq 1000 --json" + out);
  ASSERT_EQ(frf.exit_code, 0) << frf.output;
  EXPECT_EQ(json::parse(frf.output).at("points")[0].at("status"), "converged");
  const CliRun bounds = Stdout("bounds " + c + " --freq 1000 --search quick --json" + out);
  ASSERT_EQ(bounds.exit_code, 0) << bounds.output;
  const json b = json::parse(bounds.output);
  EXPECT_EQ(b.at("status"), "converged");
  EXPECT_GT(b.at("y_max").get<double>(), 0.0);
}

}  // namespace
