// Helpers shared by the OUTPUT4 reader tests (op4_reader_test.cpp: files that read,
// op4_bad_input_test.cpp: corrupted copies): fixture paths, the error check, byte editing.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
#include "io/io_test_util.h"

namespace fricrom::op4_test {
namespace fs = std::filesystem;

inline std::string Fixture(const std::string& name) {
  return std::string(FRICROM_SOURCE_DIR) + "/tests/data/op4/" + name;
}

inline std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in) << path;
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

using TempDir = fricrom::testing::ScratchDir;

inline Eigen::MatrixXd Re(const FeMatrix& m) { return Eigen::MatrixXd(m.real); }
inline Eigen::MatrixXd Im(const FeMatrix& m) {
  return m.is_complex ? Eigen::MatrixXd(m.imag) : Eigen::MatrixXd::Zero(m.rows, m.cols);
}

// The reader throws FeReadError whose message contains every fragment.
inline void ExpectError(const std::string& path, const std::vector<std::string>& fragments) {
  try {
    const FeModel model = ReadOp4(path);
    ADD_FAILURE() << path << ": read " << model.matrices.size() << " matrices, expected an error";
  } catch (const FeReadError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    for (const std::string& f : fragments) {
      EXPECT_NE(msg.find(f), std::string::npos) << "missing '" << f << "' in: " << msg;
    }
  }
}

// The first part.matrices.size() matrices of `full` equal those of `part` (name, real and
// imaginary parts); `part` holds no more matrices than `full`.
inline void ExpectPrefixOf(const FeModel& part, const FeModel& full) {
  ASSERT_LE(part.matrices.size(), full.matrices.size());
  for (size_t i = 0; i < part.matrices.size(); ++i) {
    EXPECT_EQ(part.matrices[i].name, full.matrices[i].name);
    EXPECT_EQ(Re(part.matrices[i]), Re(full.matrices[i]));
    EXPECT_EQ(Im(part.matrices[i]), Im(full.matrices[i]));
  }
}

// ---- little-endian helpers for editing binary fixtures -----------------------------------

inline int32_t GetI32(const std::string& b, size_t off) {
  uint32_t u = 0;
  for (int i = 3; i >= 0; --i) u = (u << 8) | static_cast<uint8_t>(b[off + static_cast<size_t>(i)]);
  return static_cast<int32_t>(u);
}
inline void PutI32(std::string& b, size_t off, int32_t v) {
  auto u = static_cast<uint32_t>(v);
  for (int i = 0; i < 4; ++i)
    b[off + static_cast<size_t>(i)] = static_cast<char>((u >> (8 * i)) & 0xff);
}
inline void PutF64(std::string& b, size_t off, double v) {
  uint64_t u;
  std::memcpy(&u, &v, 8);
  for (int i = 0; i < 8; ++i)
    b[off + static_cast<size_t>(i)] = static_cast<char>((u >> (8 * i)) & 0xff);
}
inline double GetF64(const std::string& b, size_t off) {
  uint64_t u = 0;
  for (int i = 7; i >= 0; --i) u = (u << 8) | static_cast<uint8_t>(b[off + static_cast<size_t>(i)]);
  double v;
  std::memcpy(&v, &u, 8);
  return v;
}

// Record start offsets of a little-endian, 4-byte-marker file.
inline std::vector<size_t> LeRecords(const std::string& b) {
  std::vector<size_t> starts;
  size_t p = 0;
  while (p + 4 <= b.size()) {
    starts.push_back(p);
    p += 8 + static_cast<size_t>(GetI32(b, p));
  }
  EXPECT_EQ(p, b.size());
  return starts;
}

// Rewrites a file with 4-byte markers (either byte order) to 8-byte markers.
inline std::string WidenMarkers(const std::string& b, bool big_endian) {
  auto get = [&](size_t off) {
    uint32_t u = 0;
    for (int i = 0; i < 4; ++i) {
      const auto c = static_cast<uint8_t>(b[off + static_cast<size_t>(big_endian ? i : 3 - i)]);
      u = (u << 8) | c;
    }
    return u;
  };
  auto put8 = [&](std::string& out, uint64_t v) {
    for (int i = 0; i < 8; ++i) {
      const int shift = big_endian ? 8 * (7 - i) : 8 * i;
      out += static_cast<char>((v >> shift) & 0xff);
    }
  };
  std::string out;
  size_t p = 0;
  while (p < b.size()) {
    const uint32_t n = get(p);
    put8(out, n);
    out += b.substr(p + 4, n);
    put8(out, n);
    p += 8 + n;
  }
  return out;
}

}  // namespace fricrom::op4_test
