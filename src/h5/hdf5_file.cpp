#include "h5/hdf5_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <stdexcept>

namespace tumble::io {
namespace {
void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: " + what + " failed");
}

// Opens the parent group chain of `name`, creating missing groups (like `mkdir -p`).
void ensure_parents(hid_t file, const std::string& name) {
  std::size_t pos = 0;
  while ((pos = name.find('/', pos + 1)) != std::string::npos) {
    const std::string parent = name.substr(0, pos);
    if (parent.empty() || parent == "/") continue;
    if (H5Lexists(file, parent.c_str(), H5P_DEFAULT) <= 0) {
      hid_t g = H5Gcreate2(file, parent.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      check(g, "create group " + parent);
      H5Gclose(g);
    }
  }
}
}  // namespace

H5File::H5File(const std::string& path, Mode mode) : H5File(path, mode, MPI_COMM_NULL) {}

H5File::H5File(const std::string& path, Mode mode, MPI_Comm comm) : path_(path) {
  int size = 1;
  if (comm != MPI_COMM_NULL) MPI_Comm_size(comm, &size);
  if (size > 1) {
    comm_ = comm;
    MPI_Comm_rank(comm, &rank_);
  }
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // we report errors ourselves
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  if (parallel()) H5Pset_fapl_mpio(fapl, comm_, MPI_INFO_NULL);
  if (mode == Mode::Read)
    file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
  else
    file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  if (file_ < 0)
    throw std::runtime_error("cannot " + std::string(mode == Mode::Read ? "open" : "create") +
                             " HDF5 file '" + path + "'");
}

std::string H5File::shared(const std::string& value) const {
  if (!parallel()) return value;
  int n = static_cast<int>(value.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, comm_);
  std::string out = value;
  out.resize(n);
  MPI_Bcast(out.data(), n, MPI_CHAR, 0, comm_);
  return out;
}

void H5File::write_rows_raw(const std::string& name, hid_t type, const void* data, hsize_t rows,
                            hsize_t cols) {
  // Offsets: the rows of lower ranks come first.
  unsigned long long mine = rows, before = 0, total = rows;
  if (parallel()) {
    MPI_Exscan(&mine, &before, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_);
    if (rank_ == 0) before = 0;
    MPI_Allreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_);
  }
  ensure_parents(file_, name);
  const int nd = cols > 0 ? 2 : 1;
  const hsize_t dims[2] = {total, cols}, start[2] = {before, 0}, count[2] = {rows, cols};
  hid_t space = H5Screate_simple(nd, dims, nullptr);
  hid_t set = H5Dcreate2(file_, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  check(set, "create dataset " + name);
  hid_t mem = H5Screate_simple(nd, count, nullptr);
  if (rows > 0)
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  else {
    H5Sselect_none(space);
    H5Sselect_none(mem);
  }
  hid_t xfer = H5Pcreate(H5P_DATASET_XFER);
  if (parallel()) H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE);
  if (total > 0) check(H5Dwrite(set, type, mem, space, xfer, data), "write " + name);
  H5Pclose(xfer);
  H5Sclose(mem);
  H5Dclose(set);
  H5Sclose(space);
}

void H5File::write_rows(const std::string& name, const std::vector<double>& d, hsize_t cols) {
  write_rows_raw(name, H5T_NATIVE_DOUBLE, d.data(), cols ? d.size() / cols : d.size(), cols);
}
void H5File::write_rows(const std::string& name, const std::vector<std::int64_t>& d, hsize_t cols) {
  write_rows_raw(name, H5T_NATIVE_INT64, d.data(), cols ? d.size() / cols : d.size(), cols);
}
void H5File::write_rows(const std::string& name, const std::vector<std::int32_t>& d, hsize_t cols) {
  write_rows_raw(name, H5T_NATIVE_INT32, d.data(), cols ? d.size() / cols : d.size(), cols);
}

void H5File::read_rows_raw(const std::string& name, hid_t type, void* data, hsize_t begin,
                           hsize_t count) const {
  const std::vector<hsize_t> dims = shape(name);
  hid_t set = H5Dopen2(file_, name.c_str(), H5P_DEFAULT);
  if (set < 0) throw std::runtime_error("HDF5: no dataset '" + name + "' in " + path_);
  hid_t space = H5Dget_space(set);
  const int nd = static_cast<int>(dims.size());
  const hsize_t start[2] = {begin, 0}, cnt[2] = {count, nd > 1 ? dims[1] : 1};
  hid_t mem = H5Screate_simple(nd, cnt, nullptr);
  if (count > 0) {
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, cnt, nullptr);
  } else {
    H5Sselect_none(space);
    H5Sselect_none(mem);
  }
  hid_t xfer = H5Pcreate(H5P_DATASET_XFER);
  if (parallel()) H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE);
  const herr_t st = H5Dread(set, type, mem, space, xfer, data);
  H5Pclose(xfer);
  H5Sclose(mem);
  H5Sclose(space);
  H5Dclose(set);
  check(st, "read rows of " + name);
}

namespace {
hsize_t row_width(const std::vector<hsize_t>& dims) { return dims.size() > 1 ? dims[1] : 1; }
}  // namespace

std::vector<double> H5File::read_rows_double(const std::string& name, hsize_t begin,
                                             hsize_t count) const {
  std::vector<double> v(count * row_width(shape(name)));
  read_rows_raw(name, H5T_NATIVE_DOUBLE, v.data(), begin, count);
  return v;
}
std::vector<std::int64_t> H5File::read_rows_int64(const std::string& name, hsize_t begin,
                                                  hsize_t count) const {
  std::vector<std::int64_t> v(count * row_width(shape(name)));
  read_rows_raw(name, H5T_NATIVE_INT64, v.data(), begin, count);
  return v;
}
std::vector<std::int32_t> H5File::read_rows_int32(const std::string& name, hsize_t begin,
                                                  hsize_t count) const {
  std::vector<std::int32_t> v(count * row_width(shape(name)));
  read_rows_raw(name, H5T_NATIVE_INT32, v.data(), begin, count);
  return v;
}

H5File::~H5File() {
  if (file_ >= 0) H5Fclose(file_);
}

void H5File::create_group(const std::string& name) { ensure_parents(file_, name + "/"); }

bool H5File::exists(const std::string& name) const {
  // Check each prefix: H5Lexists fails on missing intermediate groups.
  std::size_t pos = 0;
  while (true) {
    pos = name.find('/', pos + 1);
    const std::string prefix = name.substr(0, pos);
    if (!prefix.empty() && prefix != "/" && H5Lexists(file_, prefix.c_str(), H5P_DEFAULT) <= 0)
      return false;
    if (pos == std::string::npos) return true;
  }
}

void H5File::write_raw(const std::string& name, hid_t type, const void* data,
                       std::vector<hsize_t> dims, std::size_t n) {
  if (dims.empty()) dims = {static_cast<hsize_t>(n)};
  hsize_t prod = 1;
  for (auto d : dims) prod *= d;
  if (prod != n) throw std::runtime_error("HDF5: shape does not match data size for " + name);
  ensure_parents(file_, name);
  hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  hid_t set = H5Dcreate2(file_, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  check(set, "create dataset " + name);
  if (n > 0) {
    if (parallel()) {  // rank 0's data; the others take part in the collective write with none
      hid_t mem = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
      if (rank_ != 0) {
        H5Sselect_none(mem);
        H5Sselect_none(space);
      }
      hid_t xfer = H5Pcreate(H5P_DATASET_XFER);
      H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE);
      check(H5Dwrite(set, type, mem, space, xfer, data), "write " + name);
      H5Pclose(xfer);
      H5Sclose(mem);
    } else {
      check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write " + name);
    }
  }
  H5Dclose(set);
  H5Sclose(space);
}

void H5File::write(const std::string& name, const std::vector<double>& d,
                   std::vector<hsize_t> dims) {
  write_raw(name, H5T_NATIVE_DOUBLE, d.data(), std::move(dims), d.size());
}
void H5File::write(const std::string& name, const std::vector<std::int64_t>& d,
                   std::vector<hsize_t> dims) {
  write_raw(name, H5T_NATIVE_INT64, d.data(), std::move(dims), d.size());
}
void H5File::write(const std::string& name, const std::vector<std::int32_t>& d,
                   std::vector<hsize_t> dims) {
  write_raw(name, H5T_NATIVE_INT32, d.data(), std::move(dims), d.size());
}
void H5File::write(const std::string& name, const double* data, std::vector<hsize_t> dims) {
  std::size_t n = 1;
  for (auto x : dims) n *= x;
  write_raw(name, H5T_NATIVE_DOUBLE, data, std::move(dims), n);
}

std::vector<hsize_t> H5File::shape(const std::string& name) const {
  hid_t set = H5Dopen2(file_, name.c_str(), H5P_DEFAULT);
  if (set < 0) throw std::runtime_error("HDF5: no dataset '" + name + "' in " + path_);
  hid_t space = H5Dget_space(set);
  int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(rank > 0 ? rank : 0);
  if (rank > 0) H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  H5Sclose(space);
  H5Dclose(set);
  return dims;
}

std::size_t H5File::count(const std::string& name) const {
  std::size_t n = 1;
  for (auto d : shape(name)) n *= d;
  return n;
}

void H5File::read_raw(const std::string& name, hid_t type, void* data) const {
  hid_t set = H5Dopen2(file_, name.c_str(), H5P_DEFAULT);
  if (set < 0) throw std::runtime_error("HDF5: no dataset '" + name + "' in " + path_);
  check(H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "read " + name);
  H5Dclose(set);
}

std::vector<double> H5File::read_double(const std::string& name) const {
  std::vector<double> v(count(name));
  if (!v.empty()) read_raw(name, H5T_NATIVE_DOUBLE, v.data());
  return v;
}
std::vector<std::int64_t> H5File::read_int64(const std::string& name) const {
  std::vector<std::int64_t> v(count(name));
  if (!v.empty()) read_raw(name, H5T_NATIVE_INT64, v.data());
  return v;
}
std::vector<std::int32_t> H5File::read_int32(const std::string& name) const {
  std::vector<std::int32_t> v(count(name));
  if (!v.empty()) read_raw(name, H5T_NATIVE_INT32, v.data());
  return v;
}

namespace {
hid_t open_obj(hid_t file, const std::string& obj) {
  hid_t o = H5Oopen(file, obj.c_str(), H5P_DEFAULT);
  if (o < 0) throw std::runtime_error("HDF5: no object '" + obj + "'");
  return o;
}
void write_attr(hid_t file, const std::string& obj, const std::string& name, hid_t type,
                const void* value) {
  hid_t o = open_obj(file, obj);
  if (H5Aexists(o, name.c_str()) > 0) H5Adelete(o, name.c_str());
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(o, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  check(a, "create attribute " + name);
  check(H5Awrite(a, type, value), "write attribute " + name);
  H5Aclose(a);
  H5Sclose(space);
  H5Oclose(o);
}
void read_attr(hid_t file, const std::string& obj, const std::string& name, hid_t type,
               void* value) {
  hid_t o = open_obj(file, obj);
  hid_t a = H5Aopen(o, name.c_str(), H5P_DEFAULT);
  if (a < 0) {
    H5Oclose(o);
    throw std::runtime_error("HDF5: no attribute '" + name + "' on " + obj);
  }
  check(H5Aread(a, type, value), "read attribute " + name);
  H5Aclose(a);
  H5Oclose(o);
}
}  // namespace

void H5File::set_attr(const std::string& obj, const std::string& name, const std::string& text) {
  const std::string value = shared(text);  // every rank writes the same bytes
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  write_attr(file_, obj, name, type, value.c_str());
  H5Tclose(type);
}
void H5File::set_attr(const std::string& obj, const std::string& name, double value) {
  if (parallel()) MPI_Bcast(&value, 1, MPI_DOUBLE, 0, comm_);
  write_attr(file_, obj, name, H5T_NATIVE_DOUBLE, &value);
}
void H5File::set_attr(const std::string& obj, const std::string& name, std::int64_t value) {
  if (parallel()) MPI_Bcast(&value, 1, MPI_INT64_T, 0, comm_);
  write_attr(file_, obj, name, H5T_NATIVE_INT64, &value);
}
std::string H5File::attr_string(const std::string& obj, const std::string& name) const {
  hid_t o = open_obj(file_, obj);
  hid_t a = H5Aopen(o, name.c_str(), H5P_DEFAULT);
  if (a < 0) {
    H5Oclose(o);
    throw std::runtime_error("HDF5: no attribute '" + name + "' on " + obj);
  }
  hid_t ftype = H5Aget_type(a);
  std::size_t size = H5Tget_size(ftype);
  std::string out(size, '\0');
  hid_t mtype = H5Tcopy(H5T_C_S1);
  H5Tset_size(mtype, size);
  check(H5Aread(a, mtype, out.data()), "read attribute " + name);
  H5Tclose(mtype);
  H5Tclose(ftype);
  H5Aclose(a);
  H5Oclose(o);
  out.resize(out.find('\0') == std::string::npos ? out.size() : out.find('\0'));
  return out;
}
double H5File::attr_double(const std::string& obj, const std::string& name) const {
  double v = 0;
  read_attr(file_, obj, name, H5T_NATIVE_DOUBLE, &v);
  return v;
}
std::int64_t H5File::attr_int64(const std::string& obj, const std::string& name) const {
  std::int64_t v = 0;
  read_attr(file_, obj, name, H5T_NATIVE_INT64, &v);
  return v;
}
bool H5File::has_attr(const std::string& obj, const std::string& name) const {
  hid_t o = H5Oopen(file_, obj.c_str(), H5P_DEFAULT);
  if (o < 0) return false;
  bool r = H5Aexists(o, name.c_str()) > 0;
  H5Oclose(o);
  return r;
}

AtomicH5Writer::AtomicH5Writer(const std::string& final_path)
    : final_path_(final_path), tmp_path_(final_path + ".tmp." + std::to_string(::getpid())) {
  file_ = new H5File(tmp_path_, H5File::Mode::Truncate);
}

AtomicH5Writer::AtomicH5Writer(const std::string& final_path, MPI_Comm comm)
    : final_path_(final_path) {
  int size = 1, rank = 0;
  if (comm != MPI_COMM_NULL) MPI_Comm_size(comm, &size);
  if (size > 1) {
    comm_ = comm;
    MPI_Comm_rank(comm, &rank);
  }
  // One temporary name for all ranks: rank 0's process id.
  long pid = ::getpid();
  if (size > 1) MPI_Bcast(&pid, 1, MPI_LONG, 0, comm);
  tmp_path_ = final_path + ".tmp." + std::to_string(pid);
  file_ = new H5File(tmp_path_, H5File::Mode::Truncate, comm_);
}

void AtomicH5Writer::commit() {
  H5Fflush(file_->id(), H5F_SCOPE_GLOBAL);
  delete file_;
  file_ = nullptr;
  int rank = 0;
  if (comm_ != MPI_COMM_NULL) {  // every rank has closed (and flushed) before the rename
    MPI_Barrier(comm_);
    MPI_Comm_rank(comm_, &rank);
  }
  if (rank != 0) {
    MPI_Barrier(comm_);
    committed_ = true;
    return;
  }
  int fd = ::open(tmp_path_.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  const bool renamed = std::rename(tmp_path_.c_str(), final_path_.c_str()) == 0;
  if (comm_ != MPI_COMM_NULL) MPI_Barrier(comm_);  // the final file exists for everyone after this
  if (!renamed) throw std::runtime_error("cannot rename " + tmp_path_ + " to " + final_path_);
  committed_ = true;
}

AtomicH5Writer::~AtomicH5Writer() {
  delete file_;
  int rank = 0;
  if (comm_ != MPI_COMM_NULL) MPI_Comm_rank(comm_, &rank);
  if (!committed_ && rank == 0) std::remove(tmp_path_.c_str());
}

}  // namespace tumble::io
