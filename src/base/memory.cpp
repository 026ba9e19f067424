#include "base/memory.hpp"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "base/error.hpp"

namespace tumble {

double available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  for (std::string key; in >> key;) {
    double kib = 0;
    std::string unit;
    if (!(in >> kib >> unit)) break;
    if (key == "MemAvailable:") return kib * 1024.0;
  }
  // Not Linux (or an old kernel without MemAvailable): physical memory, an upper bound.
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
}

double parse_memory_size(const std::string& text, const std::string& option) {
  const auto bad = [&] {
    throw InputError(option + " '" + text +
                     "' is not a memory size: give bytes or a number with K, M, G or T (e.g. 2G)");
  };
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || !std::isfinite(v) || v <= 0) bad();
  std::string unit(end);
  // "G", "GB", "GiB" and "g" all mean 2^30 bytes: a job script's memory is binary either way.
  for (auto& ch : unit) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  if (unit.size() > 1 && (unit.substr(1) == "B" || unit.substr(1) == "IB"))
    unit = unit.substr(0, 1);
  double scale = 1;
  if (unit.empty() || unit == "B")
    scale = 1;
  else if (unit == "K")
    scale = 1024.0;
  else if (unit == "M")
    scale = 1024.0 * 1024;
  else if (unit == "G")
    scale = 1024.0 * 1024 * 1024;
  else if (unit == "T")
    scale = 1024.0 * 1024 * 1024 * 1024;
  else
    bad();
  // Above an exbibyte no machine has it: a slip of the unit (or a number beyond double's range),
  // which would turn the check off without saying so.
  const double bytes = v * scale, most = 1024.0 * 1024 * 1024 * 1024 * 1024 * 1024;
  if (!(bytes <= most))
    throw InputError(option + " '" + text +
                     "' is above 1 EiB (1048576T), more than any machine has (left out, the "
                     "check is against the memory available)");
  return bytes;
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024.0 && u < 6) bytes /= 1024.0, ++u;
  std::ostringstream os;
  os.precision(3);
  os << bytes << " " << units[u];
  return os.str();
}

}  // namespace tumble
