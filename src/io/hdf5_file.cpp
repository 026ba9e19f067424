#include "io/hdf5_file.hpp"

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

H5File::H5File(const std::string& path, Mode mode) : path_(path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // we report errors ourselves
  if (mode == Mode::Read)
    file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  else
    file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0)
    throw std::runtime_error("cannot " + std::string(mode == Mode::Read ? "open" : "create") +
                             " HDF5 file '" + path + "'");
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
  if (n > 0) check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write " + name);
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

void H5File::set_attr(const std::string& obj, const std::string& name, const std::string& value) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  write_attr(file_, obj, name, type, value.c_str());
  H5Tclose(type);
}
void H5File::set_attr(const std::string& obj, const std::string& name, double value) {
  write_attr(file_, obj, name, H5T_NATIVE_DOUBLE, &value);
}
void H5File::set_attr(const std::string& obj, const std::string& name, std::int64_t value) {
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

void AtomicH5Writer::commit() {
  H5Fflush(file_->id(), H5F_SCOPE_GLOBAL);
  delete file_;
  file_ = nullptr;
  int fd = ::open(tmp_path_.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  if (std::rename(tmp_path_.c_str(), final_path_.c_str()) != 0)
    throw std::runtime_error("cannot rename " + tmp_path_ + " to " + final_path_);
  committed_ = true;
}

AtomicH5Writer::~AtomicH5Writer() {
  delete file_;
  if (!committed_) std::remove(tmp_path_.c_str());
}

}  // namespace tumble::io
