// `fricrom lump` (CalibrateLumped): the lumped 3-blade / 2-damper case calibrated from the coarse
// FE cascade. Checked against the geometry and materials of the meshes (meshes/README.md), the
// FE model's own modes, and the lumped schema (the written case must load).
#include "fricrom/lumped_calibration.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "fricrom/linear.h"

namespace fricrom {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = FRICROM_SOURCE_DIR;
const double kStripArea = 0.03 * 0.0025 * std::numbers::sqrt2;  // contact strip [m^2]
const double kArea = 4.0e11;                                    // k_area of the case [N/m^3]
// Damper prism: trapezoid (top 0.003, bottom 0.008, height 0.0025) on a 0.008 x 0.003 block,
// 0.03 long, density 8200 kg/m^3 (meshes/damper/damper_deck.inp).
const double kDamperMassFromGeometry =
    8200.0 * 0.03 * (0.5 * (0.003 + 0.008) * 0.0025 + 0.008 * 0.003);

const LumpedCalibration& Cascade() {
  static const LumpedCalibration l =
      CalibrateLumped(LoadCase((kSource / "meshes/cascade3/coarse.toml").string()));
  return l;
}

TEST(LumpedCalibration, ContactsDampersAndPreloadFollowFromTheGeometry) {
  const LumpedCalibration& l = Cascade();
  ASSERT_EQ(l.blades.size(), 3u);
  ASSERT_EQ(l.dampers.size(), 2u);
  ASSERT_EQ(l.contacts.size(), 4u);
  for (const LumpedContact& c : l.contacts) {
    EXPECT_EQ(c.pairs, 27) << c.name;
    EXPECT_NEAR(c.theta, std::numbers::pi / 4, 1e-9) << c.name;  // 45° chamfers
    EXPECT_NEAR(c.kn, kArea * kStripArea, 1e-9 * kArea * kStripArea) << c.name;
    EXPECT_NEAR(c.kt, kArea * kStripArea, 1e-9 * kArea * kStripArea) << c.name;
    EXPECT_NEAR(c.mu, 0.5, 1e-12) << c.name;
  }
  // The paper's order: damper 1 left on blade 1, right on blade 2; damper 2 left on blade 2, ...
  EXPECT_TRUE(l.contacts[0].left_face && l.contacts[0].counterpart == "blade1");
  EXPECT_TRUE(!l.contacts[1].left_face && l.contacts[1].counterpart == "blade2");
  EXPECT_TRUE(l.contacts[2].left_face && l.contacts[2].counterpart == "blade2");
  EXPECT_TRUE(!l.contacts[3].left_face && l.contacts[3].counterpart == "blade3");
  const double accel = std::pow(2 * std::numbers::pi * 6000.0 / 60.0, 2) * 0.25;  // rpm, radius
  for (const LumpedDamper& d : l.dampers) {
    EXPECT_NEAR(d.mass, kDamperMassFromGeometry, 1e-6 * kDamperMassFromGeometry)
        << d.name;  // a tet mesh of a prism
    EXPECT_NEAR(d.preload / d.mass, accel, 1e-9 * accel) << d.name;
  }
}

TEST(LumpedCalibration, BladesCarryTheFeBladeModeAndTheCaseLoads) {
  const Case fe = LoadCase((kSource / "meshes/cascade3/coarse.toml").string());
  const LumpedCalibration& l = Cascade();
  const double f1 = FreeSystemModes(fe.model).frequencies_hz[0];  // the blades alone, FE
  EXPECT_EQ(l.response_blade, "blade2");
  EXPECT_GT(l.response_scale, 1.0);  // the tip moves more than the platform
  for (const LumpedBlade& b : l.blades) {
    EXPECT_NEAR(b.mode_hz, f1, 1e-9 * f1) << b.name;
    EXPECT_NEAR(b.k_circumferential / b.modal_mass, std::pow(2 * std::numbers::pi * f1, 2),
                1e-9 * b.k_circumferential / b.modal_mass);
    EXPECT_GT(b.k_radial, 0.0);
    EXPECT_GT(b.radial_mode_hz, f1);
  }
  EXPECT_NE(l.blades[0].force_cos, 0.0);  // blades 1 and 3 are excited, blade 2 is not
  EXPECT_EQ(l.blades[1].force_cos, 0.0);
  EXPECT_NE(l.blades[2].force_cos, 0.0);

  // The written case loads, and its blades resonate where the FE blades do (the scaling by s
  // leaves frequencies alone).
  const Case lumped = ParseCase(l.toml, "lumped.toml");
  EXPECT_EQ(lumped.model.contacts.size(), 4u);
  EXPECT_EQ(lumped.model.dof_names[lumped.model.response_dof], "blade2.x");
  const Eigen::VectorXd fl = FreeSystemModes(lumped.model).frequencies_hz;
  const Eigen::VectorXd ff = FreeSystemModes(fe.model).frequencies_hz;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(fl[k], ff[k], 1e-6 * ff[k]) << k;
  // Per-direction mass and grounding (mass_y, ground_stiffness_x/_y), scaled by 1/s².
  const double s2 = l.response_scale * l.response_scale;
  const int x1 = lumped.model.DofIndex("blade1.x"), y1 = lumped.model.DofIndex("blade1.y");
  EXPECT_NEAR(lumped.model.mass(x1, x1) * s2, l.blades[0].modal_mass,
              1e-9 * l.blades[0].modal_mass);
  EXPECT_NEAR(lumped.model.mass(y1, y1) * s2, l.blades[0].radial_mass,
              1e-9 * l.blades[0].radial_mass);
  EXPECT_NEAR(lumped.model.stiffness(y1, y1) * s2, l.blades[0].k_radial,
              1e-9 * l.blades[0].k_radial);
}

TEST(LumpedCalibration, RefusesWhatTheLumpedModelCannotRepresent) {
  // A lumped case is not an FE cascade; the lumped case written as FE data has node-pair
  // contacts but no interfaces and its blades are one body.
  for (const char* path : {"meshes/lumped3/baseline.toml", "meshes/lumped3/as_fe/case.toml"}) {
    const Case c = LoadCase((kSource / path).string());
    EXPECT_THROW(CalibrateLumped(c), CaseError) << path;
  }
  LumpOptions bad;
  bad.radial = bad.circumferential;
  std::string error;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_THROW(CalibrateLumped(LoadCase((kSource / "meshes/cascade3/coarse.toml").string()), bad),
               std::invalid_argument);
}

// A case name with quotes and a backslash survives into the written TOML, which still loads.
TEST(LumpedCalibration, WrittenCaseEscapesTheCaseName) {
  const fs::path dir = kSource / "meshes/cascade3";
  const fs::path variant = dir / (".lump_name_" + std::to_string(::getpid()) + ".toml");
  {
    std::ifstream in(dir / "coarse.toml");
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    const std::string from = "name = \"cascade3-coarse\"";
    ASSERT_NE(s.find(from), std::string::npos);
    s.replace(s.find(from), from.size(), "name = 'cas\"ca\\de'");
    std::ofstream(variant) << s;
  }
  const LumpedCalibration l = CalibrateLumped(LoadCase(variant.string()));
  fs::remove(variant);
  const Case lumped = ParseCase(l.toml, "lumped.toml");
  EXPECT_EQ(lumped.name, "cas\"ca\\de-lumped");
}

TEST(LumpedCalibration, CliWritesACaseEveryCommandReads) {
  const fs::path out =
      fs::temp_directory_path() / ("lumped_" + std::to_string(::getpid()) + ".toml");
  const std::string cli = FRICROM_CLI;
  const std::string cmd = cli + " lump " + (kSource / "meshes/cascade3/coarse.toml").string() +
                          " --to " + out.string() + " --json > " + out.string() + ".json";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_EQ(std::system((cli + " modes " + out.string() + " > /dev/null").c_str()), 0);
  EXPECT_EQ(std::system((cli + " bounds " + out.string() + " --freq 1000 > /dev/null").c_str()), 0);
  EXPECT_NE(std::system((cli + " lump " + (kSource / "meshes/lumped3/baseline.toml").string() +
                         " --to " + out.string() + " 2> /dev/null")
                            .c_str()),
            0);
  fs::remove(out);
  fs::remove(out.string() + ".json");
}

}  // namespace
}  // namespace fricrom
