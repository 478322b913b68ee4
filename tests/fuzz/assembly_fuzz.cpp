// libFuzzer target for the FE assembly reader (ParseCase on fricrom-assembly-1 text whose files
// are those of meshes/lumped3/as_fe: matrices, DOF maps): any text either reads as a case whose
// model passes its checks with finite numbers, or throws CaseError. Any other exception, a crash
// or a sanitizer report is a finding. The reduced-body routes (reduced = "r.h5", fe = {...}) need
// HDF5, ARPACK and CHOLMOD and are refused here like a missing file; the matrix readers have
// their own targets. Run from the repository root (the case's files are found relative to it).
// Not built by CMake; scripts/fuzz_smoke.sh builds and runs it.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "case_invariants.h"
#include "fricrom/case_file.h"
#include "fricrom/reduced_body.h"

fricrom::ReducedBody fricrom::ReadReducedBody(const std::string& path) {
  throw std::runtime_error(path + ": reduced bodies are not fuzzed here");
}

// The spec's own checks live with the reduction (not linked): every spec goes on to the stub.
bool fricrom::FeBodySpec::IsValid(std::string*) const { return true; }

fricrom::ReducedBody fricrom::ReduceFeBody(const FeBodySpec& spec, const ReduceFeBodyOptions&,
                                           CraigBamptonSummary*) {
  throw std::runtime_error(spec.stiffness_file + ": FE reductions are not fuzzed here");
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fricrom::Case c;
  try {
    c = fricrom::ParseCase(text, "meshes/lumped3/as_fe/fuzz.toml");
  } catch (const fricrom::CaseError&) {
    return 0;
  }
  fricrom_fuzz::CheckCase(c);
  // The assembly's own: a blade, and unit contact frames (checked on input with their keys).
  fricrom_fuzz::Check(!c.model.free_dofs.empty(), "a blade");
  for (const fricrom::Contact& k : c.model.contacts) {
    fricrom_fuzz::Check(
        std::abs(k.normal.norm() - 1.0) < 1e-6 && std::abs(k.tangent.norm() - 1.0) < 1e-6,
        "unit contact frame");
  }
  return 0;
}
