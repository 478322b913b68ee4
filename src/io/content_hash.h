// Content hashes for cache keys and run journals: two independent 64-bit hashes of a byte
// stream, so that a changed input file (not its name or date) changes the key.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace fricrom {

// Two 64-bit hashes of one byte stream: FNV-1a byte by byte, and a multiply-xorshift over 8-byte
// words (independent mixing, so one collision does not imply the other).
class Hasher {
 public:
  void Add(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) {
      fnv_ = (fnv_ ^ p[i]) * 0x100000001b3ULL;
      word_ |= static_cast<uint64_t>(p[i]) << (8 * fill_);
      if (++fill_ == 8) Flush();
    }
  }
  void Add(const std::string& s) {
    const uint64_t n = s.size();
    Add(&n, sizeof n);  // length prefix: "ab"+"c" differs from "a"+"bc"
    Add(s.data(), s.size());
  }
  std::string Hex() {
    Flush();
    char buf[40];
    std::snprintf(buf, sizeof buf, "%016llx%016llx", static_cast<unsigned long long>(fnv_),
                  static_cast<unsigned long long>(Mix(mix_ ^ count_)));
    return buf;
  }

 private:
  static uint64_t Mix(uint64_t x) {  // splitmix64 finaliser
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  }
  void Flush() {
    if (fill_ == 0) return;
    mix_ = Mix(mix_ ^ word_ ^ (static_cast<uint64_t>(fill_) << 56)) * 0x9e3779b97f4a7c15ULL;
    count_ += fill_;
    word_ = 0;
    fill_ = 0;
  }
  uint64_t fnv_ = 0xcbf29ce484222325ULL;
  uint64_t mix_ = 0x243f6a8885a308d3ULL;
  uint64_t word_ = 0, count_ = 0;
  int fill_ = 0;
};

// Adds the extension, the bytes and the length of the file at `path` (a missing file adds a
// marker naming it, so the key differs and the reader reports the error).
void HashFile(const std::string& path, Hasher* h);

}  // namespace fricrom
