#include "io/content_hash.h"

#include <filesystem>
#include <fstream>
#include <vector>

namespace fricrom {

void HashFile(const std::string& path, Hasher* h) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    h->Add("missing " + path);  // the reader will fail on it; the key just has to differ
    return;
  }
  h->Add(std::filesystem::path(path).extension().string());
  std::vector<char> buf(1 << 20);
  uint64_t total = 0;
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const size_t got = static_cast<size_t>(in.gcount());
    h->Add(buf.data(), got);
    total += got;
  }
  h->Add(&total, sizeof total);
}

}  // namespace fricrom
