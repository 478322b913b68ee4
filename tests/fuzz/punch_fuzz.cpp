// libFuzzer target for ReadNastranPunch (DMIG, GRID, CORD2R, EXTRN cards).
// Not built by CMake. Build and run by hand, e.g.:
//   clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
//     -Iinclude -isystem /usr/include/eigen3 tests/fuzz/punch_fuzz.cpp src/io/*.cpp -o punch_fuzz
//   ./punch_fuzz -max_total_time=30 -dict=... CORPUS_DIR tests/data/dmig tests/data/extseout
// The input bytes are written to a temporary .pch file; any exception other than FeReadError,
// a crash, a sanitizer report or a broken invariant of the result is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fricrom_fuzz::TempDir() + "/input.pch";
  fricrom_fuzz::WriteFile(path, std::string_view(reinterpret_cast<const char*>(data), size));
  fricrom::FeModel model;
  try {
    model = fricrom::ReadNastranPunch(path, fricrom_fuzz::Options());
  } catch (const fricrom::FeReadError&) {
    return 0;
  }
  fricrom_fuzz::CheckModel(model);
  fricrom_fuzz::CheckCoordinatesAgree(model,
                                      fricrom::ReadNastranPunch(path, fricrom_fuzz::Options(true)));
  // No per-column count in DMIG: a cut at a line end between terms may read (documented).
  fricrom_fuzz::CheckCuts(
      std::string_view(reinterpret_cast<const char*>(data), size), model,
      [&](std::string_view cut) {
        fricrom_fuzz::WriteFile(path, cut);
        return fricrom::ReadNastranPunch(path, fricrom_fuzz::Options());
      },
      true);
  return 0;
}
