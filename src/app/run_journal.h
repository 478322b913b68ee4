// Checkpoint and resume for commands made of independent units of work (sweep values): an
// append-only journal of finished units in the output folder, flushed to disk unit by unit, and a
// lock so that two runs never write one folder at the same time.
#pragma once

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace fricrom::app {

class RunJournal {
 public:
  // Locks `dir` (flock on dir/.fricrom.lock; std::runtime_error naming the folder when another
  // run holds it), removes temporary files a killed run left there (*.tmp-PID), and opens
  // dir/<name>.journal. Units recorded by an earlier run with the same `header` (command, inputs
  // and options: anything that changes a result) are loaded; a journal with another header is
  // discarded, or is an error when `require_resume` (--resume) is set, as is a missing one.
  RunJournal(const std::filesystem::path& dir, const std::string& name,
             const nlohmann::json& header, bool require_resume);
  ~RunJournal();
  RunJournal(const RunJournal&) = delete;
  RunJournal& operator=(const RunJournal&) = delete;

  // Units finished by earlier runs: unit index -> its recorded result.
  const std::map<int, nlohmann::json>& finished() const { return finished_; }
  // Appends one finished unit and makes it durable (write + fsync) before returning.
  void Record(int unit, const nlohmann::json& result);
  // The run's output files are in place: the journal is no longer needed.
  void Complete();

 private:
  std::filesystem::path path_;
  int lock_fd_ = -1;
  int fd_ = -1;
  std::map<int, nlohmann::json> finished_;
};

}  // namespace fricrom::app
