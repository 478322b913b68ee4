// The mutation corpus (tests/data/mutants/mutants.json): committed cases with one defect each —
// a broken matrix, a meaningless case, a key out of range, a file that is not what it claims —
// and the outcome fricrom must give: exit 2 with a message naming the file, key or body (or, for
// a warning, exit 0 with the warning). No mutant may crash, hang or give a number silently.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "app/cli_test_util.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using fricrom::testing::CliRun;
using fricrom::testing::Quote;
using fricrom::testing::TempDir;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every occurrence of `from` in `text` replaced by `to`; false when there is none (a stale edit).
bool ReplaceAll(std::string* text, const std::string& from, const std::string& to) {
  bool found = false;
  for (size_t at = 0; (at = text->find(from, at)) != std::string::npos; at += to.size()) {
    text->replace(at, from.size(), to);
    found = true;
  }
  return found;
}

TEST(Mutants, EveryMutantEndsAsTheCorpusSays) {
  const fs::path root(FRICROM_SOURCE_DIR);
  const json corpus = json::parse(Slurp(root / "tests/data/mutants/mutants.json"));
  ASSERT_GE(corpus.at("mutants").size(), 25u);
  for (const json& m : corpus.at("mutants")) {
    const std::string name = m.at("name");
    SCOPED_TRACE(name);
    TempDir tmp;
    // The base's folder at the same place below the scratch root, tests/ beside it, so that the
    // case's relative paths (../../tests/data/...) still resolve.
    const fs::path base = root / m.at("base").get<std::string>();
    const fs::path rel = fs::relative(base.parent_path(), root);
    const fs::path dir = tmp.path() / rel;
    fs::create_directories(dir.parent_path());
    fs::copy(base.parent_path(), dir, fs::copy_options::recursive);
    fs::create_directory_symlink(root / "tests", tmp.path() / "tests");
    for (const json& e : m.at("edits")) {
      const fs::path file = dir / e.at(0).get<std::string>();
      std::string text = Slurp(file);
      ASSERT_TRUE(ReplaceAll(&text, e.at(1), e.at(2))) << "stale edit: " << e.dump();
      std::ofstream(file, std::ios::binary) << text;
    }
    std::string args = m.at("args");
    ReplaceAll(&args, "CASE", Quote((dir / base.filename()).string()));
    if (args.rfind("modes", 0) != 0) args += " --out " + Quote((tmp.path() / "out").string());
    const CliRun r = fricrom::testing::Stderr(args);
    EXPECT_EQ(r.exit_code, m.at("expect_exit").get<int>()) << r.output;
    for (const json& fragment : m.at("expect")) {
      EXPECT_NE(r.output.find(fragment.get<std::string>()), std::string::npos)
          << "expected '" << fragment.get<std::string>() << "' in:\n"
          << r.output;
    }
  }
}

}  // namespace
