#pragma once
// The last step before a temporary file is renamed into place: its bytes reach the disk first, so
// that after a power loss the final name holds the whole new file or the old one, never a
// renamed file whose data was still in the page cache.
#include <string>

namespace tumble {

// fsync(2) of `path` (best effort: a file that cannot be opened is left as it is; the write
// itself reported its errors).
void sync_to_disk(const std::string& path);

}  // namespace tumble
