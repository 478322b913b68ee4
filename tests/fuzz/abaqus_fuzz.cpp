// libFuzzer target for ReadAbaqusMatrix (node-DOF and COORDINATE forms, DOF sidecar).
// Not built by CMake. Build and run by hand, e.g.:
//   clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
//     -Iinclude -isystem /usr/include/eigen3 tests/fuzz/abaqus_fuzz.cpp src/io/*.cpp -o abaqus_fuzz
//   ./abaqus_fuzz -max_total_time=30 CORPUS_DIR tests/data/abaqus
// Input: the .mtx bytes, optionally followed by "@@\n" and the sidecar <name>.dof.csv.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "fricrom/fe_model.h"
#include "fuzz_util.h"

using namespace fricrom_fuzz;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<std::string_view> parts = Parts(data, size);
  const std::string mtx = TempDir() + "/m.mtx", csv = TempDir() + "/m.dof.csv";
  WriteFile(mtx, parts[0]);
  std::error_code ec;
  std::filesystem::remove(csv, ec);
  if (parts.size() > 1) WriteFile(csv, parts[1]);
  fricrom::FeModel model;
  try {
    model = fricrom::ReadAbaqusMatrix(mtx, Options());
  } catch (const fricrom::FeReadError&) {
    return 0;
  }
  CheckModel(model);
  CheckCoordinatesAgree(model, fricrom::ReadAbaqusMatrix(mtx, Options(true)));
  // No declared counts: cuts at a line end may read as a smaller matrix (documented).
  CheckCuts(
      parts[0], model,
      [&](std::string_view cut) {
        WriteFile(mtx, cut);
        return fricrom::ReadAbaqusMatrix(mtx, Options());
      },
      true);
  return 0;
}
