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

#include "fricrom/case_file.h"
#include "model/case_reader.h"

namespace {

void Check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "invariant broken: %s\n", what);
    std::abort();
  }
}

}  // namespace

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
  const fricrom::Model& m = c.model;
  Check(m.num_dofs() > 0, "a case has DOFs");
  Check(m.mass.allFinite() && m.stiffness.allFinite() && m.damping.allFinite(), "finite matrices");
  Check(m.response_dof >= 0 && m.response_dof < m.num_dofs(), "response DOF in range");
  for (const fricrom::Contact& k : m.contacts) {
    Check(std::isfinite(k.kn) && std::isfinite(k.kt) && std::isfinite(k.mu) &&
              std::isfinite(k.normal_preload),
          "finite contact law");
  }
  for (const fricrom::HarmonicLoad& l : m.loads) {
    Check(l.cos.allFinite() && l.sin.allFinite(), "finite loads");
    Check(l.harmonic >= 0 && l.harmonic <= c.analysis.harmonics, "load harmonic within H");
  }
  Check(c.analysis.harmonics >= 1 && c.analysis.samples_per_period > 2 * c.analysis.harmonics,
        "AFT samples resolve H");
  Check(static_cast<int>(c.analysis.alpha.size()) == m.num_alpha(), "one default alpha per alpha");
  for (double a : c.analysis.alpha) Check(std::abs(a) <= 1.0, "default alpha in [-1, 1]");
  return 0;
}
