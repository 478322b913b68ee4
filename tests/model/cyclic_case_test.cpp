// Cyclic-symmetry assembly cases (schema fricrom-assembly-2, [cyclic]): what a case that cannot
// be a sector of a disk is told, checked on variants of the flat coarse cascade.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "app/cli_test_util.h"
#include "fricrom/case_file.h"

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
