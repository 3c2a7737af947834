// core/run_lock.hpp: a second claim on a run folder is refused with the holder's pid and start
// time; the claim ends with its holder.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <optional>
#include <string>

#include "rheosim/core/error.hpp"
#include "rheosim/core/run_lock.hpp"

namespace fs = std::filesystem;

TEST(RunDirectoryLock, SecondClaimIsRefusedWithTheHoldersPid) {
  const fs::path folder = fs::path("test-runs") / "run_lock";
  fs::remove_all(folder);
  std::optional<rheosim::core::RunDirectoryLock> first;
  first.emplace(folder);
  EXPECT_TRUE(fs::exists(first->file()));
  try {
    rheosim::core::RunDirectoryLock second(folder);
    FAIL() << "a second claim on the same folder was granted";
  } catch (const rheosim::core::RunError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("in use by another rheosim run"), std::string::npos) << message;
    EXPECT_NE(message.find("pid " + std::to_string(::getpid())), std::string::npos) << message;
    EXPECT_NE(message.find("started 20"), std::string::npos) << message;
  }
  first.reset();  // the holder ends: the folder is free again
  EXPECT_NO_THROW(rheosim::core::RunDirectoryLock again(folder));
}
