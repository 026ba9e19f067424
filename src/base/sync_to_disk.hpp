#pragma once
// The last step before a temporary file is renamed into place: its bytes reach the disk first, so
// that after a power loss the final name holds the whole new file or the old one, never a
// renamed file whose data was still in the page cache.
#include <string>

namespace tumble {

// fsync(2) of `path`; throws RunError naming the file and the system's reason if it cannot be
// opened or its data do not reach the disk (write-back errors show only here), so that the
// caller does not rename it into place.
void sync_to_disk(const std::string& path);

}  // namespace tumble
