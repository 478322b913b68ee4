// Atomic output: write to a temporary sibling, then rename over the target, so an interrupted run
// leaves either the old file or the complete new one, never half of it.
#pragma once

#include <filesystem>
#include <string>

namespace fricrom {

// Temporary sibling path of `target` (same directory, so rename is atomic).
std::filesystem::path TemporarySibling(const std::filesystem::path& target);
// Renames tmp over target; throws std::runtime_error naming both on failure.
void CommitFile(const std::filesystem::path& tmp, const std::filesystem::path& target);
// Writes text atomically; throws std::runtime_error naming the file on failure.
void WriteTextAtomically(const std::filesystem::path& target, const std::string& text);

}  // namespace fricrom
