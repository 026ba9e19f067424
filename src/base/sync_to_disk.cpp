#include "base/sync_to_disk.hpp"

#include <fcntl.h>
#include <unistd.h>

namespace tumble {

void sync_to_disk(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace tumble
