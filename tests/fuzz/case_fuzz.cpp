// libFuzzer target for the lumped case-file reader (ParseCase, schema fricrom-case-1): any text
// either reads as a case whose model passes its checks with finite numbers, or throws CaseError.
// Any other exception, a crash or a sanitizer report is a finding. Assembly cases (which name FE
// files to read) are left out: the FE readers have their own targets.
// Not built by CMake; scripts/fuzz_smoke.sh builds and runs it, or by hand:
//   clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
//     -Iinclude -Isrc -isystem /usr/include/eigen3 tests/fuzz/case_fuzz.cpp \
//     src/model/case_file.cpp src/model/case_reader.cpp src/model/model.cpp -lmuparser -o case_fuzz
//   ./case_fuzz -max_total_time=30 CORPUS_DIR meshes/lumped3
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "case_invariants.h"
#include "fricrom/case_file.h"
#include "model/case_reader.h"

// The FE assembly reader is not linked: a case that reaches it is refused like bad input.
fricrom::Case fricrom::detail::ParseAssembly(const toml::table&, const std::string& source,
                                             const std::vector<ParameterOverride>&) {
  throw CaseError(source + ": assembly cases are not fuzzed here");
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fricrom::Case c;
  try {
    c = fricrom::ParseCase(text, "fuzz.toml");
  } catch (const fricrom::CaseError&) {
    return 0;
  }
  fricrom_fuzz::CheckCase(c);
  return 0;
}
