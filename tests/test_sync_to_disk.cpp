// base/sync_to_disk: the fsync before a temporary file is renamed into place. A file that cannot
// be opened, and one whose fsync fails, are a RunError naming the file and the system's reason
// (before, a failed fsync was ignored and the file renamed into place all the same). Linux's
// fsync of a character device fails with EINVAL: /dev/null stands in for a disk's write-back
// error, which a test cannot cause.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "base/error.hpp"
#include "base/sync_to_disk.hpp"

using namespace tumble;

namespace {
// The message of the RunError `path` gives, or "" when it throws none.
std::string refusal(const std::string& path) {
  try {
    sync_to_disk(path);
  } catch (const RunError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SyncToDisk, AWrittenFileReachesTheDisk) {
  const std::string dir = std::string(TUMBLE_TEST_SCRATCH) + "/sync_to_disk";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/file.tmp";
  std::ofstream(path) << "bytes";
  EXPECT_EQ(refusal(path), "");
}

TEST(SyncToDisk, AFileThatCannotBeOpenedIsARunError) {
  const std::string path = std::string(TUMBLE_TEST_SCRATCH) + "/sync_to_disk/no_such_file";
  const std::string why = refusal(path);
  EXPECT_NE(why.find(path), std::string::npos) << why;
  EXPECT_NE(why.find("(errno 2)"), std::string::npos) << why;
  EXPECT_NE(why.find("not put in place"), std::string::npos) << why;
}

TEST(SyncToDisk, AFailedFsyncIsARunError) {
  const std::string why = refusal("/dev/null");
  EXPECT_NE(why.find("/dev/null"), std::string::npos) << why;
  EXPECT_NE(why.find("(errno 22)"), std::string::npos) << why;
}
