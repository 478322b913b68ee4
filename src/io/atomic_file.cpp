#include "io/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <system_error>

namespace fricrom {

std::filesystem::path TemporarySibling(const std::filesystem::path& target) {
  std::filesystem::path tmp = target;
  tmp += ".tmp-" + std::to_string(::getpid());
  return tmp;
}

void CommitFile(const std::filesystem::path& tmp, const std::filesystem::path& target) {
  std::error_code ec;
  std::filesystem::rename(tmp, target, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error("cannot move " + tmp.string() + " to " + target.string() + ": " +
                             ec.message());
  }
}

void WriteTextAtomically(const std::filesystem::path& target, const std::string& text) {
  const std::filesystem::path tmp = TemporarySibling(target);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
    out << text;
    out.flush();
    if (!out) throw std::runtime_error("error while writing " + tmp.string());
  }
  CommitFile(tmp, target);
}

}  // namespace fricrom
