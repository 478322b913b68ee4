// Helpers shared by the FE-reader tests.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"

namespace fricrom::testing {

// A fresh directory under the system temp dir, removed with everything in it at scope exit.
class ScratchDir {
 public:
  ScratchDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "fricrom-io-test-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  // Writes `text` to `name` inside the directory and returns the file's path.
  std::string Write(const std::string& name, const std::string& text) const {
    const std::string p = (path_ / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  const std::filesystem::path& path() const { return path_; }
  // Path of `name` inside the directory (the file need not exist).
  std::string Path(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// Expects `read` to throw a FeReadError whose message names `file`, `line` (when > 0) and
// contains `what`.
template <typename F>
void ExpectError(F read, const std::string& file, int line, const std::string& what) {
  try {
    read();
    ADD_FAILURE() << "no FeReadError; expected one containing '" << what << "'";
  } catch (const FeReadError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file), std::string::npos) << msg;
    if (line > 0) {
      EXPECT_NE(msg.find(":" + std::to_string(line) + ":"), std::string::npos) << msg;
    }
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

// Expects `read` to throw a FeReadError whose message contains every fragment.
template <typename F>
void ExpectError(F read, const std::vector<std::string>& fragments) {
  try {
    read();
    ADD_FAILURE() << "no FeReadError; expected one containing '" << fragments.front() << "'";
  } catch (const FeReadError& e) {
    const std::string msg = e.what();
    for (const std::string& f : fragments) {
      EXPECT_NE(msg.find(f), std::string::npos) << "missing '" << f << "' in: " << msg;
    }
  }
}

}  // namespace fricrom::testing
