#pragma once
// Stable 64-bit hashing for case ids, derived seeds and file checksums. FNV-1a gives the same value
// on every machine, compiler and run (std::hash does not), so a case id or a seed written today
// still names the same case after a rebuild or on another cluster.
#include <cstdint>
#include <cstdio>
#include <string>

namespace tumble {

inline constexpr std::uint64_t kFnvOffset = 1469598103934665603ull;

inline std::uint64_t fnv1a64(const void* data, std::size_t n, std::uint64_t h = kFnvOffset) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}
inline std::uint64_t fnv1a64(const std::string& s) { return fnv1a64(s.data(), s.size()); }

// splitmix64 finaliser: spreads nearby FNV values over all bits before they become seeds.
inline std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

inline std::string hex16(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// "fnv1a64:<hex>" of a file's bytes; throws std::runtime_error if it cannot be read.
std::string file_checksum(const std::string& path);

}  // namespace tumble
