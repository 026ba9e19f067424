#pragma once
// Provenance written into every HDF5 file. Defined in a file generated at build time
// (cmake/write_version.cmake), so the hash is the commit the binary was built from.
namespace tumble {
extern const char* const kVersion;
extern const char* const kGitHash;  // short commit hash, "-dirty" if tracked files differed
}  // namespace tumble
