// Helpers of the CLI end-to-end tests: run the built executable (FRICROM_CLI) through the shell,
// temporary directories, file reading.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fricrom::testing {

namespace fs = std::filesystem;

inline const std::string kCli = FRICROM_CLI;
inline const std::string kSource = FRICROM_SOURCE_DIR;
inline const std::string kBaseline = kSource + "/meshes/lumped3/baseline.toml";

struct CliRun {
  int exit_code = -1;
  std::string output;
};

inline std::string Quote(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

// Runs `fricrom ARGS REDIRECTIONS` through the shell; returns the exit code and what the command
// wrote to the pipe (stdout, after the redirections are applied).
inline CliRun Fricrom(const std::string& args, const std::string& redirections) {
  const std::string cmd = Quote(kCli) + " " + args + " " + redirections;
  CliRun r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) {
    ADD_FAILURE() << "popen failed: " << cmd;
    return r;
  }
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}
inline CliRun Stdout(const std::string& args) { return Fricrom(args, "2>/dev/null"); }
inline CliRun Stderr(const std::string& args) { return Fricrom(args, "2>&1 >/dev/null"); }

// A fresh directory under /tmp, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "fricrom-cli-test-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) ADD_FAILURE() << "mkdtemp failed";
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

inline std::string ReadFile(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace fricrom::testing
