#pragma once
// The HDF5 file a `cm` or `analyze` subcommand writes (-o/--output): its folder made, and a path
// that cannot become the file refused as bad input before the work (an mcm run or an island
// search takes minutes; the file is written to a temporary name and renamed into place only
// after it, which is where such a path failed before).
#include <string>

namespace tumble::app {

// Throws InputError naming `option` for an empty path, one that ends in a separator or names a
// directory, or a folder that cannot be made or written into.
void prepare_output_file(const std::string& path, const std::string& option = "-o/--output");

}  // namespace tumble::app
