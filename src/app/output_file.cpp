#include "app/output_file.hpp"

#include <unistd.h>

#include <filesystem>
#include <system_error>

#include "base/error.hpp"

namespace tumble::app {

void prepare_output_file(const std::string& path, const std::string& option) {
  namespace fs = std::filesystem;
  if (path.empty()) throw InputError(option + " is empty: give the HDF5 file's path");
  std::error_code ec;  // (is_directory's: a path that is not there yet is no directory)
  const fs::path p(path);
  if (!p.has_filename() || fs::is_directory(p, ec))
    throw InputError(option + " '" + path + "' is a directory: give the HDF5 file's path, e.g. " +
                     (p / "out.h5").lexically_normal().string());
  const fs::path dir = p.parent_path();
  ec.clear();
  if (!dir.empty()) fs::create_directories(dir, ec);
  const std::string where = dir.empty() ? std::string(".") : dir.string();
  if (ec || ::access(where.c_str(), W_OK | X_OK) != 0)
    throw InputError(option + " '" + path + "': cannot write into the folder '" + where + "'" +
                     (ec ? " (" + ec.message() + ")" : std::string()));
}

}  // namespace tumble::app
