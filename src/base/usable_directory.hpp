#pragma once
// Whether a directory a run will write into can be made and written, asked before any work: found
// out when the bed had settled (minutes) or the first file was written, the error named no key.
#include <string>

namespace tumble {

// "" if `dir` exists as a directory this process may write into, or can be made: its nearest
// existing ancestor is a writable directory. Otherwise why not ("'/a/b' is a file, not a folder",
// "'/x' is not writable: Permission denied"); writable means a file could be made there (made
// and removed at once: root passes every permission bit, not /proc or a read-only mount).
// `read_only_ok`: a directory that exists is enough (a cache of beds shared read-only).
std::string cannot_make_directory(const std::string& dir, bool read_only_ok = false);

}  // namespace tumble
