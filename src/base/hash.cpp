#include "base/hash.hpp"

#include <fstream>
#include <stdexcept>
#include <vector>

namespace tumble {

std::string file_checksum(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read '" + path + "' for its checksum");
  std::uint64_t h = kFnvOffset;
  std::vector<char> buf(1 << 16);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    h = fnv1a64(buf.data(), static_cast<std::size_t>(in.gcount()), h);
  }
  return "fnv1a64:" + hex16(h);
}

}  // namespace tumble
