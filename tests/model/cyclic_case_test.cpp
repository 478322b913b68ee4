// Cyclic-symmetry assembly cases (schema fricrom-assembly-2, [cyclic]): what a case that cannot
// be a sector of a disk is told, checked on variants of the flat coarse cascade.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/cli_test_util.h"
#include "fricrom/case_file.h"
#include "fricrom/condensed_system.h"
#include "fricrom/cyclic.h"
#include "fricrom/frf.h"
#include "fricrom/hbm_system.h"
#include "fricrom/units.h"

namespace fricrom {
namespace {

namespace fs = std::filesystem;
const fs::path kCascade = fs::path(FRICROM_SOURCE_DIR) / "meshes/cascade3";

// The cascade with text replacements, written beside it (relative paths hold); the load's
// CaseError message, or "" (and a failure) when it loads.
std::string LoadError(const std::vector<std::pair<std::string, std::string>>& edits) {
  std::string text = testing::ReadFile(kCascade / "coarse.toml");
  for (const auto& [from, to] : edits) {
    const size_t at = text.find(from);
    if (at == std::string::npos) return "edit not found: " + from;
    text.replace(at, from.size(), to);
  }
  const fs::path path = kCascade / ("test-cyclic-" + std::to_string(getpid()) + ".toml");
  std::ofstream(path) << text;
  std::string message;
  try {
    LoadCase(path.string());
    ADD_FAILURE() << "expected a CaseError";
  } catch (const CaseError& e) {
    message = e.what();
  }
  fs::remove(path);
  return message;
}

const std::pair<std::string, std::string> kSchema2{"schema = \"fricrom-assembly-1\"",
                                                   "schema = \"fricrom-assembly-2\""};
std::pair<std::string, std::string> Cyclic(const std::string& keys) {
  return {"[analysis]", "[cyclic]\n" + keys + "\n\n[analysis]"};
}
const std::pair<std::string, std::string> kNextSector{
    "b = { body = \"blade3\", set = \"CONTACT_LEFT\" }",
    "b = { body = \"blade1\", set = \"CONTACT_LEFT\", sector = \"next\" }"};

TEST(CyclicCase, CyclicSectionNeedsTheNewSchema) {
  const std::string e = LoadError({Cyclic("sectors = 24\nengine_order = 2\naxis = [-1, 0, 0]")});
  EXPECT_NE(e.find("key 'cyclic'"), std::string::npos) << e;
  EXPECT_NE(e.find("fricrom-assembly-2"), std::string::npos) << e;
}

TEST(CyclicCase, OneSectorOrAnEngineOrderAboveHalfTheSectorsIsAnError) {
  std::string e = LoadError({kSchema2, Cyclic("sectors = 1\nengine_order = 0\naxis = [-1, 0, 0]")});
  EXPECT_NE(e.find("key 'cyclic.sectors'"), std::string::npos) << e;
  EXPECT_NE(e.find(">= 2"), std::string::npos) << e;
  e = LoadError({kSchema2, Cyclic("sectors = 24\nengine_order = 13\naxis = [-1, 0, 0]")});
  EXPECT_NE(e.find("key 'cyclic.engine_order'"), std::string::npos) << e;
  EXPECT_NE(e.find("0..12"), std::string::npos) << e;
  e = LoadError({kSchema2, Cyclic("sectors = 24\nengine_order = 2\naxis = [0, 0, 0]")});
  EXPECT_NE(e.find("key 'cyclic.axis'"), std::string::npos) << e;
}

TEST(CyclicCase, NextSectorWithoutCyclicSectionIsAnError) {
  const std::string e = LoadError({kNextSector});
  EXPECT_NE(e.find("sector = \"next\" needs a [cyclic] section"), std::string::npos) << e;
}

// The flat cascade is no sector of a disk: after the rotation the next blade's nodes lie nowhere
// near the damper's, and the error names them.
TEST(CyclicCase, CyclicInterfaceThatDoesNotPairAfterRotationNamesTheNodes) {
  const std::string e = LoadError(
      {kSchema2, Cyclic("sectors = 24\nengine_order = 2\naxis = [-1, 0, 0]"), kNextSector});
  EXPECT_NE(e.find("interfaces[3]"), std::string::npos) << e;
  EXPECT_NE(e.find("node"), std::string::npos) << e;
  EXPECT_NE(e.find("next sector"), std::string::npos) << e;
}

TEST(CyclicCase, CyclicSectionWithoutAnInterfaceToTheNextSectorIsAnError) {
  const std::string e =
      LoadError({kSchema2, Cyclic("sectors = 24\nengine_order = 2\naxis = [-1, 0, 0]")});
  EXPECT_NE(e.find("no interface couples to the next sector"), std::string::npos) << e;
}

}  // namespace
}  // namespace fricrom

namespace fricrom {
namespace {

// The disk24 sector coupled as a ring of 6 at EO 1: its cyclic contacts keep the disk's
// geometry (the 15° rotation of their directions) and take the phase 2π/6 — a ring small enough
// to hold explicitly. Solved as a sector on the condensed balance, its solution spread over the
// explicit ring of 6 sectors solves the ring's full balance.
Case DiskSectorOfSix() {
  Case c = LoadCase((fs::path(FRICROM_SOURCE_DIR) / "meshes/disk24/coarse.toml").string());
  c.model.cyclic.sectors = 6;
  c.model.cyclic.engine_order = 1;
  for (Contact& ct : c.model.contacts) {
    if (ct.cyclic()) ct.phase_b = c.model.cyclic.phase();
  }
  return c;
}

TEST(CyclicCase, FeSectorSolutionsSolveTheExplicitRingOfSixAtHarmonicsOneAndThree) {
  const Case c = DiskSectorOfSix();
  ASSERT_EQ(c.model.cyclic.sectors, 6);
  const Model ring = ExpandCyclicRing(c.model);
  for (const int harmonics : {1, 3}) {
    HbmOptions o{harmonics, 96};
    o.receptance = ReceptanceMethod::kDense;
    const CondensedSystem sector(c.model, o);
    const HbmSystem full_ring(ring, o);
    const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(c.model.num_alpha(), -0.8, 0.8);
    const Eigen::VectorXd contact_alpha = c.model.ContactAlpha(alpha);
    int slipping = 0;
    for (const double f : {1100.0, 1124.0}) {
      const double w = kTwoPi * f;
      const FrfPoint s =
          SolveAtFrequency(sector, contact_alpha, f, Eigen::VectorXd(), FrfOptions{});
      ASSERT_EQ(s.status, SolverStatus::kConverged) << harmonics << " " << f;
      const Eigen::VectorXd x = sector.Recover(s.x, w, contact_alpha);
      const Eigen::VectorXd xr = SpreadOverRing(c.model, x, harmonics);
      const Eigen::VectorXd ring_alpha =
          RingContactAlpha(c.model, sector.ContactHistories(s.x, w, contact_alpha), contact_alpha);
      HbmEvaluation e;
      full_ring.Evaluate(xr, w, ring_alpha, HbmRequest{}, &e);
      EXPECT_LE(e.residual.norm(), 1e-8 * full_ring.ResidualScale()) << harmonics << " " << f;
      for (const ContactRegime r : sector.ContactRegimes(s.x, w, contact_alpha)) {
        slipping += r != ContactRegime::kFullStick;
      }
    }
    EXPECT_GT(slipping, 0) << "the check needs contacts that slip";
  }
}

}  // namespace
}  // namespace fricrom
