#include "campaign/directory_lock.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "base/error.hpp"

namespace tumble::campaign {
namespace {
// Whether another process holds a lock that conflicts with a write lock on [start, start + len),
// and its pid where the kernel can tell (a holder in another pid namespace or on another NFS
// client may read as 0 or less: held all the same).
struct Holder {
  bool held = false;
  pid_t pid = 0;
};
Holder holder(int fd, off_t start, off_t len) {
  struct flock q {};
  q.l_type = F_WRLCK;
  q.l_whence = SEEK_SET;
  q.l_start = start;
  q.l_len = len;
  if (::fcntl(fd, F_GETLK, &q) != 0 || q.l_type == F_UNLCK) return {};
  return {true, q.l_pid};
}

// The lock file at `path`, made if missing.
int open_lock_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw RunError("cannot open '" + path + "': " + std::strerror(errno));
  return fd;
}
}  // namespace

DirectoryLock::DirectoryLock(const std::string& dir, int slicing) {
  fd_ = open_lock_file(dir + "/campaign.lock");
  struct flock mine {};
  mine.l_type = F_RDLCK;
  mine.l_whence = SEEK_SET;
  mine.l_start = slicing;
  mine.l_len = 1;
  const bool got = ::fcntl(fd_, F_SETLK, &mine) == 0;
  // Another slicing: a lock on any byte but ours (both sides checked after taking ours, so two
  // slicings starting at once both refuse rather than both run).
  Holder other = got ? holder(fd_, 0, slicing) : Holder{};
  if (got && !other.held) other = holder(fd_, slicing + 1, 0);  // len 0: to the end of the file
  if (got && !other.held) return;
  ::close(fd_);
  fd_ = -1;
  throw InputError("campaign error: '" + dir + "' is being run right now with another slicing" +
                   (other.pid > 0 ? " (process " + std::to_string(other.pid) + ")" : "") +
                   ": a whole campaign, its slices i/" + std::to_string(slicing) +
                   " and other slicings i/m would compute the same cases twice; wait for it to "
                   "end, or run into another --output");
}

int DirectoryLock::running_process(const std::string& dir) {
  const std::string path = dir + "/campaign.lock";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  const Holder h = holder(fd, 0, 0);  // len 0: every byte, every slicing
  ::close(fd);
  if (!h.held) return 0;
  return h.pid > 0 ? static_cast<int>(h.pid) : -1;
}

DirectoryLock::~DirectoryLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

CaseTableLock::CaseTableLock(const std::string& dir) {
  const std::string path = dir + "/campaign.table.lock";
  fd_ = open_lock_file(path);
  struct flock mine {};
  mine.l_type = F_WRLCK;
  mine.l_whence = SEEK_SET;
  int rc;
  while ((rc = ::fcntl(fd_, F_SETLKW, &mine)) != 0 && errno == EINTR) {
  }
  if (rc != 0) {
    const int e = errno;
    ::close(fd_);
    fd_ = -1;
    throw RunError("cannot lock '" + path + "': " + std::strerror(e));
  }
}

CaseTableLock::~CaseTableLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

}  // namespace tumble::campaign
