#pragma once
// A thin RAII wrapper over the HDF5 C API: files, groups, datasets of double/int64/int32, and
// scalar/string attributes. Everything Tumble writes goes through here, so that the parallel
// (MPI-IO) variant can be added in one place.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

namespace tumble::io {

class H5File {
 public:
  enum class Mode { Read, Truncate };
  H5File(const std::string& path, Mode mode);
  ~H5File();
  H5File(const H5File&) = delete;
  H5File& operator=(const H5File&) = delete;

  hid_t id() const { return file_; }
  const std::string& path() const { return path_; }

  // Groups are created on demand; names may be paths like "a/b".
  void create_group(const std::string& name);
  bool exists(const std::string& name) const;

  // Datasets: `dims` gives the shape (row-major); data.size() must equal the product.
  void write(const std::string& name, const std::vector<double>& data,
             std::vector<hsize_t> dims = {});
  void write(const std::string& name, const std::vector<std::int64_t>& data,
             std::vector<hsize_t> dims = {});
  void write(const std::string& name, const std::vector<std::int32_t>& data,
             std::vector<hsize_t> dims = {});
  void write(const std::string& name, const double* data, std::vector<hsize_t> dims);

  std::vector<double> read_double(const std::string& name) const;
  std::vector<std::int64_t> read_int64(const std::string& name) const;
  std::vector<std::int32_t> read_int32(const std::string& name) const;
  std::vector<hsize_t> shape(const std::string& name) const;

  // Attributes on an object ("/" for the file root).
  void set_attr(const std::string& obj, const std::string& name, const std::string& value);
  void set_attr(const std::string& obj, const std::string& name, double value);
  void set_attr(const std::string& obj, const std::string& name, std::int64_t value);
  std::string attr_string(const std::string& obj, const std::string& name) const;
  double attr_double(const std::string& obj, const std::string& name) const;
  std::int64_t attr_int64(const std::string& obj, const std::string& name) const;
  bool has_attr(const std::string& obj, const std::string& name) const;

 private:
  void write_raw(const std::string& name, hid_t type, const void* data, std::vector<hsize_t> dims,
                 std::size_t n);
  void read_raw(const std::string& name, hid_t type, void* data) const;
  std::size_t count(const std::string& name) const;

  hid_t file_ = -1;
  std::string path_;
};

// Writes through a temporary file that is renamed into place only once complete, so a crash
// never leaves a truncated result behind (checkpoints, beds, per-case results).
class AtomicH5Writer {
 public:
  explicit AtomicH5Writer(const std::string& final_path);
  H5File& file() { return *file_; }
  // Closes the file, fsyncs and renames it over the final path.
  void commit();
  ~AtomicH5Writer();

 private:
  std::string final_path_, tmp_path_;
  H5File* file_ = nullptr;
  bool committed_ = false;
};

}  // namespace tumble::io
