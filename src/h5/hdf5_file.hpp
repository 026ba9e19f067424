#pragma once
// A thin RAII wrapper over the HDF5 C API: files, groups, datasets of double/int64/int32, and
// scalar/string attributes. Everything Tumble writes goes through here, so that the parallel
// (MPI-IO) variant can be added in one place.
#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

namespace tumble::io {

// Whether HDF5 still holds a file open: after every H5File is gone, only one it could not close
// (a failed flush) is left, and HDF5 1.10 crashes on it while shutting down (src/app/main.cpp).
bool files_left_open();

class H5File {
 public:
  enum class Mode { Read, Truncate };
  H5File(const std::string& path, Mode mode);
  // Parallel HDF5 (MPI-IO), collective over `comm`: every rank opens and closes the file and
  // makes every call below in the same order. write() and set_attr() store rank 0's values (the
  // shapes must agree); write_rows() stores each rank's rows after those of lower ranks.
  // (MPI_COMM_NULL or one rank: an ordinary serial file.)
  H5File(const std::string& path, Mode mode, MPI_Comm comm);
  ~H5File();
  // Flushes and closes, throwing (with the file and the system's reason) if either fails; the
  // destructor closes silently.
  void close();
  H5File(const H5File&) = delete;
  H5File& operator=(const H5File&) = delete;

  hid_t id() const { return file_; }
  const std::string& path() const { return path_; }

  // Groups are created on demand; names may be paths like "a/b".
  void create_group(const std::string& name);
  bool exists(const std::string& name) const;
  // The names of a group's members (groups and datasets), in name order; empty if it is absent.
  std::vector<std::string> children(const std::string& group) const;

  // Datasets: `dims` gives the shape (row-major); data.size() must equal the product.
  void write(const std::string& name, const std::vector<double>& data,
             std::vector<hsize_t> dims = {});
  void write(const std::string& name, const std::vector<std::int64_t>& data,
             std::vector<hsize_t> dims = {});
  void write(const std::string& name, const std::vector<std::int32_t>& data,
             std::vector<hsize_t> dims = {});
  void write(const std::string& name, const double* data, std::vector<hsize_t> dims);

  // Distributed rows of a 1-D (cols = 0) or 2-D dataset; ranks may hold none. Collective.
  void write_rows(const std::string& name, const std::vector<double>& local, hsize_t cols = 0);
  void write_rows(const std::string& name, const std::vector<std::int64_t>& local,
                  hsize_t cols = 0);
  void write_rows(const std::string& name, const std::vector<std::int32_t>& local,
                  hsize_t cols = 0);
  // Rows [begin, begin + count) of a 1-D or 2-D dataset (any rank, independently).
  std::vector<double> read_rows_double(const std::string& name, hsize_t begin, hsize_t count) const;
  std::vector<std::int64_t> read_rows_int64(const std::string& name, hsize_t begin,
                                            hsize_t count) const;
  std::vector<std::int32_t> read_rows_int32(const std::string& name, hsize_t begin,
                                            hsize_t count) const;
  bool parallel() const { return comm_ != MPI_COMM_NULL; }

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
  void write_rows_raw(const std::string& name, hid_t type, const void* data, hsize_t rows,
                      hsize_t cols);
  void read_rows_raw(const std::string& name, hid_t type, void* data, hsize_t begin,
                     hsize_t count) const;
  std::string shared(const std::string& value) const;  // rank 0's value on every rank
  std::size_t count(const std::string& name) const;

  hid_t file_ = -1;
  std::string path_;
  MPI_Comm comm_ = MPI_COMM_NULL;  // parallel file when set
  int rank_ = 0;
};

// Writes through a temporary file that is renamed into place only once complete, so a crash
// never leaves a truncated result behind (checkpoints, beds, per-case results).
class AtomicH5Writer {
 public:
  explicit AtomicH5Writer(const std::string& final_path);
  // Collective over `comm` (a parallel file; rank 0 renames it once every rank has closed it).
  AtomicH5Writer(const std::string& final_path, MPI_Comm comm);
  H5File& file() { return *file_; }
  // Closes the file, fsyncs and renames it over the final path.
  void commit();
  ~AtomicH5Writer();

 private:
  std::string final_path_, tmp_path_;
  H5File* file_ = nullptr;
  MPI_Comm comm_ = MPI_COMM_NULL;
  bool committed_ = false;
};

}  // namespace tumble::io
