#include "app/run_journal.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace fricrom::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::runtime_error Error(const fs::path& p, const std::string& what) {
  return std::runtime_error(p.string() + ": " + what);
}

void WriteAll(int fd, const std::string& text, const fs::path& p) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw Error(p, std::string("cannot write: ") + std::strerror(errno));
    done += static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0) throw Error(p, std::string("cannot sync: ") + std::strerror(errno));
}

// Temporary files of atomic writes end in ".tmp-PID" (io/atomic_file.cpp); with the lock held no
// other run can be writing them, so every one left is from a killed run.
void RemoveStaleTemporaries(const fs::path& dir) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    const size_t at = name.rfind(".tmp-");
    if (at == std::string::npos || at + 5 >= name.size()) continue;
    if (name.find_first_not_of("0123456789", at + 5) != std::string::npos) continue;
    fs::remove_all(e.path(), ec);
  }
}

}  // namespace

RunJournal::RunJournal(const fs::path& dir, const std::string& name, const json& header,
                       bool require_resume)
    : path_(dir / (name + ".journal")) {
  fs::create_directories(dir);
  const fs::path lock = dir / ".fricrom.lock";
  lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) throw Error(lock, std::string("cannot open: ") + std::strerror(errno));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw Error(dir, "another fricrom run is writing this output folder (" + lock.string() +
                         " is locked); wait for it to end or give another --out");
  }
  RemoveStaleTemporaries(dir);
  // Read back an earlier run: line 1 the header, then one {"unit", "result"} per line. A kill
  // can leave the last line torn; it is dropped (that unit is computed again).
  const std::string want = header.dump();
  bool matches = false;
  if (std::ifstream in(path_); in) {
    std::string line;
    matches = std::getline(in, line) && line == want;
    while (matches && std::getline(in, line)) {
      const json j = json::parse(line, nullptr, false);
      if (j.is_discarded() || !j.contains("unit") || !j["unit"].is_number_integer()) break;
      finished_[j["unit"].get<int>()] = j["result"];
    }
  }
  if (require_resume && !matches) {
    throw Error(path_, fs::exists(path_) ? "belongs to a run with other inputs or options; "
                                           "nothing to resume (run without --resume to start "
                                           "afresh)"
                                         : "no journal to resume from");
  }
  // Rewrite the journal with what is kept (a torn tail must not stay before new lines).
  const fs::path tmp = path_.string() + ".tmp-" + std::to_string(::getpid());
  fd_ = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw Error(tmp, std::string("cannot create: ") + std::strerror(errno));
  std::string text = want + "\n";
  for (const auto& [unit, result] : finished_)
    text += json{{"unit", unit}, {"result", result}}.dump() + "\n";
  WriteAll(fd_, text, tmp);
  fs::rename(tmp, path_);
}

RunJournal::~RunJournal() {
  if (fd_ >= 0) ::close(fd_);
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the flock
}

void RunJournal::Record(int unit, const json& result) {
  WriteAll(fd_, json{{"unit", unit}, {"result", result}}.dump() + "\n", path_);
  finished_[unit] = result;
}

void RunJournal::Complete() {
  std::error_code ec;
  fs::remove(path_, ec);
}

}  // namespace fricrom::app
