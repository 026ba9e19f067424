#include "base/sync_to_disk.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "base/error.hpp"

namespace tumble {

void sync_to_disk(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  int err = fd < 0 ? errno : 0;
  // Write-back errors (EIO; ENOSPC on a file system that allocates late, NFS) show only here.
  if (fd >= 0 && ::fsync(fd) != 0) err = errno;
  if (fd >= 0) ::close(fd);
  if (err != 0)
    throw RunError("cannot sync " + path + " to disk: " + std::strerror(err) + " (errno " +
                   std::to_string(err) + "); it is not put in place");
}

}  // namespace tumble
