// libFuzzer target for ReadCalculix (prefix.dof, prefix.sti, prefix.mas).
// Not built by CMake. Build and run by hand, e.g.:
//   clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
//     -Iinclude -isystem /usr/include/eigen3 tests/fuzz/calculix_fuzz.cpp src/io/*.cpp \
//     -o calculix_fuzz
//   ./calculix_fuzz -max_total_time=30 CORPUS_DIR
// Input: the .dof bytes, then "@@\n" and the .sti bytes, then "@@\n" and the .mas bytes (a
// missing part means a missing file).
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
  const std::string prefix = TempDir() + "/c";
  const char* ext[3] = {".dof", ".sti", ".mas"};
  for (size_t i = 0; i < 3; ++i) {
    std::error_code ec;
    std::filesystem::remove(prefix + ext[i], ec);
    if (i < parts.size()) WriteFile(prefix + ext[i], parts[i]);
  }
  fricrom::FeModel model;
  try {
    model = fricrom::ReadCalculix(prefix, Options());
  } catch (const fricrom::FeReadError&) {
    return 0;
  }
  CheckModel(model);
  CheckCoordinatesAgree(model, fricrom::ReadCalculix(prefix, Options(true)));
  // The .sti and .mas files are checked against the .dof file: every cut of either must fail or
  // read the same matrices.
  for (size_t i = 1; i < 3 && i < parts.size(); ++i) {
    CheckCuts(
        parts[i], model,
        [&](std::string_view cut) {
          WriteFile(prefix + ext[i], cut);
          return fricrom::ReadCalculix(prefix, Options());
        },
        false);
    WriteFile(prefix + ext[i], parts[i]);
  }
  return 0;
}
