#include "base/usable_directory.hpp"

#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace tumble {

std::string cannot_make_directory(const std::string& dir, bool read_only_ok) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (read_only_ok && fs::is_directory(dir, ec)) return "";
  fs::path p = fs::absolute(dir, ec);
  if (ec) return ec.message();
  while (!fs::exists(p, ec) && p != p.parent_path()) p = p.parent_path();
  if (!fs::exists(p, ec)) return "none of its parent folders exists";
  if (!fs::is_directory(p, ec)) return "'" + p.string() + "' is a file, not a folder";
  if (::access(p.c_str(), W_OK | X_OK) != 0)
    return "'" + p.string() + "' is not writable: " + std::strerror(errno);
  // access() answers by the permission bits, which root passes everywhere: /proc, /sys and a
  // read-only mount then failed only when the run wrote (a raw file-system error naming no key,
  // or a settled bed lost). A file made and removed at once asks the file system itself.
  std::string probe = (p / ".tumble-write-test-XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) return "no file can be made in '" + p.string() + "': " + std::strerror(errno);
  ::close(fd);
  ::unlink(probe.c_str());
  return "";
}

}  // namespace tumble
