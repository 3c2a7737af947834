#include "rheosim/core/run_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "rheosim/core/error.hpp"

namespace rheosim::core {

RunDirectoryLock::RunDirectoryLock(const std::filesystem::path& folder) : file_(folder / ".rheosim.lock") {
  std::filesystem::create_directories(folder);
  descriptor_ = ::open(file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (descriptor_ < 0)
    throw RunError(fmt::format("cannot open the run lock {}: {}", file_.string(), std::strerror(errno)));
  if (::flock(descriptor_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(descriptor_);
    descriptor_ = -1;
    if (error != EWOULDBLOCK)
      throw RunError(fmt::format("cannot lock the run folder {}: {}", folder.string(), std::strerror(error)));
    std::ifstream in(file_);
    std::stringstream holder;
    holder << in.rdbuf();
    std::string text = holder.str();
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    throw RunError(fmt::format(
        "the run folder {} is in use by another rheosim run ({}); wait for it to finish, or give this run another "
        "--out folder",
        folder.string(), text.empty() ? "its pid is not recorded yet" : text));
  }
  // Ours: record who holds it, for the message a second run prints.
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char stamp[32] = {};
  std::strftime(stamp, sizeof stamp, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
  const std::string text = fmt::format("pid {}, started {}\n", ::getpid(), stamp);
  if (::ftruncate(descriptor_, 0) != 0 || ::pwrite(descriptor_, text.data(), text.size(), 0) < 0) {
    // The claim holds without the note; a second run then says the pid is not recorded.
  }
}

RunDirectoryLock::~RunDirectoryLock() {
  if (descriptor_ >= 0) {
    if (::ftruncate(descriptor_, 0) != 0) {
      // The lock is released below either way.
    }
    ::close(descriptor_);  // releases the flock
  }
}

}  // namespace rheosim::core
