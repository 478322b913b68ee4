// libFuzzer target for the Nastran OUTPUT4 reader: every input must either read or throw
// FeReadError; crashes, sanitizer reports, other exceptions and huge allocations are bugs.
//
//   clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -Iinclude -I/usr/include/eigen3 \
//     src/io/op4_reader.cpp tests/fuzz/op4_fuzz.cpp -o op4_fuzz
//   ./op4_fuzz -max_total_time=60 corpus/ tests/data/op4/
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fricrom/fe_model.h"
#include "fuzz_util.h"

namespace {

// One scratch file name per fuzzing process (libFuzzer leaves with _Exit, so the file is
// removed after every input rather than at exit).
const std::string& ScratchPath() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    std::string tmpl =
        std::string(dir != nullptr && *dir != '\0' ? dir : "/tmp") + "/fricrom-op4-fuzz-XXXXXX";
    const int fd = mkstemp(tmpl.data());
    if (fd < 0) std::abort();
    close(fd);
    return tmpl;
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = ScratchPath();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  try {
    const fricrom::FeModel model = fricrom::ReadOp4(path, fricrom_fuzz::Options());
    // Check the result so that a malformed matrix would be noticed; NaN/Inf must never pass.
    auto check = [](const Eigen::SparseMatrix<double>& a) {
      for (Eigen::Index k = 0; k < a.nonZeros(); ++k) {
        if (!std::isfinite(a.valuePtr()[k])) std::abort();
      }
    };
    for (const fricrom::FeMatrix& m : model.matrices) {
      if (m.real.rows() != m.rows || m.real.cols() != m.cols) std::abort();
      check(m.real);
      if (m.is_complex) {
        if (m.imag.rows() != m.rows || m.imag.cols() != m.cols) std::abort();
        check(m.imag);
      }
    }
    fricrom_fuzz::CheckCoordinatesAgree(model, fricrom::ReadOp4(path, fricrom_fuzz::Options(true)));
    // Records (binary) and end-of-matrix records (ASCII): a cut fails or drops whole matrices.
    fricrom_fuzz::CheckCuts(
        std::string_view(reinterpret_cast<const char*>(data), size), model,
        [&](std::string_view cut) {
          fricrom_fuzz::WriteFile(path, cut);
          return fricrom::ReadOp4(path, fricrom_fuzz::Options());
        },
        false);
  } catch (const fricrom::FeReadError&) {
  }
  std::remove(path.c_str());
  return 0;
}
