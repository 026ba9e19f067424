#pragma once
// Memory sizes for the resource checks made before any allocation (scene validation, `tumble cm`):
// what the machine has available, a size given on the command line ("2G"), and a size for messages.
#include <string>

namespace tumble {

// Bytes the machine can give this process now: MemAvailable of /proc/meminfo (what the kernel can
// hand out without swapping), else physical pages x page size; 0 if neither can be read.
double available_memory_bytes();
// "2G", "512M", "1.5T", "4096K" or a plain byte count (binary units: K = 1024); throws InputError
// naming `option` when the text is no positive size.
double parse_memory_size(const std::string& text, const std::string& option);
// "1.23 GiB" (binary units, 3 significant digits).
std::string format_bytes(double bytes);

}  // namespace tumble
