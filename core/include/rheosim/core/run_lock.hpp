#pragma once
// An exclusive claim on a run folder: `rheosim run` holds one while it writes into --out, so a
// second run given the same folder is refused (naming the first one's pid and start time)
// instead of mixing its points into the first one's store. The claim is an flock(2) on
// <folder>/.rheosim.lock: the kernel drops it when the holder exits or is killed, so a
// crashed run never leaves the folder locked.
#include <filesystem>
#include <string>

namespace rheosim::core {

class RunDirectoryLock {
 public:
  // Creates the folder if needed and takes the claim. Throws RunError when another process
  // holds it (the message names its pid and start time) or the lock file cannot be opened.
  explicit RunDirectoryLock(const std::filesystem::path& folder);
  ~RunDirectoryLock();
  RunDirectoryLock(const RunDirectoryLock&) = delete;
  RunDirectoryLock& operator=(const RunDirectoryLock&) = delete;

  [[nodiscard]] const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  int descriptor_ = -1;
};

}  // namespace rheosim::core
