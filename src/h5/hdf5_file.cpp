#include "h5/hdf5_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "base/agreed_input.hpp"
#include "base/error.hpp"
#include "base/sync_to_disk.hpp"
#include "base/temporary_files.hpp"

namespace tumble::io {
namespace {
// An HDF5 handle closed when it leaves scope, also when a check throws on the way: a dataset
// left open keeps its file open past H5Fclose (a serial file's weak close degree), and with it a
// removed temporary's disk space while the process lives, and files_left_open() at exit.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: " + what + " failed");
}

std::string hdf5_reason();

// A failed write, named with its file and HDF5's innermost reason (for the POSIX driver that
// holds the system's: "errno = 28, error message = 'No space left on device'").
void check_in(const std::string& path, herr_t status, const std::string& what) {
  if (status < 0)
    throw std::runtime_error("HDF5: cannot " + what + " in '" + path + "'" + hdf5_reason());
}

// The system's reason for a failed file operation (a full disk: "No space left on device"), which
// HDF5's own messages leave out. errno is cleared before the operation, so a stale value from an
// earlier call is never shown.
std::string system_reason(int err) {
  return err ? ": " + std::string(std::strerror(err)) + " (errno " + std::to_string(err) + ")" : "";
}

// The innermost message of HDF5's error stack ("Fletcher32 checksum failed", "incorrect metadata
// checksum after all read tries", ...): what tells a damaged file from a missing object.
std::string hdf5_reason() {
  std::string reason;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* e, void* out) -> herr_t {
        if (n == 0 && e->desc) *static_cast<std::string*>(out) = e->desc;
        return 0;
      },
      &reason);
  return reason.empty() ? "" : " (" + reason + ")";
}

// Reading a file Tumble wrote failed: the file is damaged (a checksum of the data or of the
// metadata no longer matches) or is not what Tumble writes. Named with file and object so the
// user knows what to delete or regenerate.
[[noreturn]] void corrupt(const std::string& path, const std::string& what) {
  throw CorruptInputError("'" + path + "': " + what + hdf5_reason() +
                          "; the file is damaged or was not written by Tumble");
}

// Creation properties of a dataset of `dims` elements of `type`: chunked, with HDF5's Fletcher32
// checksum per chunk, so that every read verifies the data it returns (H5Dread fails on a
// mismatch). Chunks of at most ~1 MiB of whole rows fit HDF5's default chunk cache and keep
// row-block reads (read_rows_*) cheap. An empty dataset cannot be chunked (a chunk dimension
// must be >= 1 and <= a fixed extent of 0): it stays contiguous, there is nothing to check.
hid_t checksummed_dcpl(hid_t type, const std::vector<hsize_t>& dims) {
  hsize_t n = 1;
  for (auto d : dims) n *= d;
  if (dims.empty() || n == 0) return H5P_DEFAULT;
  std::vector<hsize_t> chunk = dims;
  const hsize_t row_bytes = (n / dims[0]) * H5Tget_size(type);
  chunk[0] = std::max<hsize_t>(1, std::min<hsize_t>(dims[0], (hsize_t{1} << 20) / row_bytes));
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  check(H5Pset_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data()), "set chunk");
  check(H5Pset_fletcher32(dcpl), "set Fletcher32 filter");
  return dcpl;
}
void close_dcpl(hid_t dcpl) {
  if (dcpl != H5P_DEFAULT) H5Pclose(dcpl);
}

// Opens the parent group chain of `name`, creating missing groups (like `mkdir -p`).
void ensure_parents(hid_t file, const std::string& name) {
  std::size_t pos = 0;
  while ((pos = name.find('/', pos + 1)) != std::string::npos) {
    const std::string parent = name.substr(0, pos);
    if (parent.empty() || parent == "/") continue;
    if (H5Lexists(file, parent.c_str(), H5P_DEFAULT) <= 0) {
      const Handle g(H5Gcreate2(file, parent.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                     H5Gclose);
      check(g, "create group " + parent);
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
  // The 1.8 file format and later: its superblock, object headers (and with them the attributes
  // and the links of compact groups) and B-trees carry checksums that HDF5 verifies on read. The
  // datasets' own checksums are the Fletcher32 filter (checksummed_dcpl). Readers of HDF5 >= 1.8
  // (h5py, PETSc, h5dump) read these files; files written before still read (no checksums).
  if (mode != Mode::Read) H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_LATEST);
  errno = 0;
  if (mode == Mode::Read)
    file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
  else
    file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  const int err = errno;
  H5Pclose(fapl);
  if (file_ < 0) {
    // An existing, readable file that HDF5 cannot open is damaged (its superblock checksum, its
    // signature) or not HDF5 at all; a missing one is an ordinary error.
    if (mode == Mode::Read && ::access(path.c_str(), R_OK) == 0)
      corrupt(path, "cannot be opened as an HDF5 file");
    // A file this call created (a full disk leaves it at 0 bytes) is not left behind.
    if (mode != Mode::Read) std::remove(path.c_str());
    throw std::runtime_error("cannot " + std::string(mode == Mode::Read ? "open" : "create") +
                             " HDF5 file '" + path + "'" + system_reason(err) + hdf5_reason());
  }
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
  const Handle space(H5Screate_simple(nd, dims, nullptr), H5Sclose);
  const hid_t dcpl = checksummed_dcpl(type, std::vector<hsize_t>(dims, dims + nd));
  const Handle set(H5Dcreate2(file_, name.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT),
                   H5Dclose);
  close_dcpl(dcpl);
  check_in(path_, set, "create dataset " + name);
  const Handle mem(H5Screate_simple(nd, count, nullptr), H5Sclose);
  if (rows > 0)
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  else {
    H5Sselect_none(space);
    H5Sselect_none(mem);
  }
  const Handle xfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
  if (parallel()) H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE);
  if (total > 0) check_in(path_, H5Dwrite(set, type, mem, space, xfer, data), "write " + name);
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
  if (set < 0) corrupt(path_, "dataset '" + name + "' is missing or unreadable");
  hid_t space = H5Dget_space(set);
  const int nd = static_cast<int>(dims.size());
  if (nd < 1 || nd > 2 || begin + count > dims[0]) {
    H5Sclose(space);
    H5Dclose(set);
    corrupt(path_, "dataset '" + name + "' has " + std::to_string(nd) + " dimensions / " +
                       std::to_string(nd ? dims[0] : 0) + " rows, rows " + std::to_string(begin) +
                       ".." + std::to_string(begin + count) + " asked for");
  }
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
  if (st < 0) corrupt(path_, "dataset '" + name + "' fails its checksum or cannot be read");
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

bool files_left_open() { return H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_FILE) > 0; }

H5File::~H5File() {
  if (file_ >= 0) H5Fclose(file_);
}

void H5File::close() {
  if (file_ < 0) return;
  // HDF5 caches writes: a full disk often shows only here, when the caches are flushed.
  errno = 0;
  const herr_t flushed = H5Fflush(file_, H5F_SCOPE_GLOBAL);
  const int err = errno;
  const herr_t closed = H5Fclose(file_);
  file_ = -1;
  if (flushed < 0 || closed < 0)
    throw std::runtime_error("HDF5: cannot write '" + path_ + "'" + system_reason(err) +
                             hdf5_reason());
}

void H5File::create_group(const std::string& name) { ensure_parents(file_, name + "/"); }

std::vector<std::string> H5File::children(const std::string& group) const {
  std::vector<std::string> out;
  if (!exists(group)) return out;
  const hid_t g = H5Gopen2(file_, group.c_str(), H5P_DEFAULT);
  if (g < 0) return out;
  H5G_info_t info;
  H5Gget_info(g, &info);
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    const ssize_t len =
        H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
    std::string name(static_cast<std::size_t>(len), '\0');
    H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    out.push_back(name);
  }
  H5Gclose(g);
  return out;
}

bool H5File::exists(const std::string& name) const {
  // Check each prefix: H5Lexists fails on missing intermediate groups.
  std::size_t pos = 0;
  while (true) {
    pos = name.find('/', pos + 1);
    const std::string prefix = name.substr(0, pos);
    if (prefix.empty() || prefix == "/") {
      if (pos == std::string::npos) return true;
      continue;
    }
    const htri_t e = H5Lexists(file_, prefix.c_str(), H5P_DEFAULT);
    // Negative: the group holding the link cannot be read (a damaged header), not "absent".
    if (e < 0) corrupt(path_, "cannot look up '" + prefix + "'");
    if (e == 0) return false;
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
  const Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                     H5Sclose);
  const hid_t dcpl = checksummed_dcpl(type, dims);
  const Handle set(H5Dcreate2(file_, name.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT),
                   H5Dclose);
  close_dcpl(dcpl);
  check_in(path_, set, "create dataset " + name);
  if (n > 0) {
    if (parallel()) {  // rank 0's data; the others take part in the collective write with none
      const Handle mem(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                       H5Sclose);
      if (rank_ != 0) {
        H5Sselect_none(mem);
        H5Sselect_none(space);
      }
      const Handle xfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
      H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE);
      check_in(path_, H5Dwrite(set, type, mem, space, xfer, data), "write " + name);
    } else {
      check_in(path_, H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write " + name);
    }
  }
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
  if (set < 0) corrupt(path_, "dataset '" + name + "' is missing or unreadable");
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
  if (set < 0) corrupt(path_, "dataset '" + name + "' is missing or unreadable");
  const herr_t st = H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  H5Dclose(set);
  if (st < 0) corrupt(path_, "dataset '" + name + "' fails its checksum or cannot be read");
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
  const Handle o(open_obj(file, obj), H5Oclose);
  if (H5Aexists(o, name.c_str()) > 0) H5Adelete(o, name.c_str());
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  const Handle a(H5Acreate2(o, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(a, "create attribute " + name);
  check(H5Awrite(a, type, value), "write attribute " + name);
}
// An attribute of a file being read: missing or unreadable means the file is not as Tumble wrote
// it (with the 1.8 format an attribute lives in its object's checksummed header).
hid_t open_attr(hid_t file, const std::string& path, const std::string& obj,
                const std::string& name) {
  hid_t o = H5Oopen(file, obj.c_str(), H5P_DEFAULT);
  if (o < 0) corrupt(path, "object '" + obj + "' is missing or unreadable");
  hid_t a = H5Aopen(o, name.c_str(), H5P_DEFAULT);
  H5Oclose(o);
  if (a < 0) corrupt(path, "attribute '" + name + "' of '" + obj + "' is missing or unreadable");
  return a;
}
void read_attr(hid_t file, const std::string& path, const std::string& obj, const std::string& name,
               hid_t type, void* value) {
  hid_t a = open_attr(file, path, obj, name);
  const herr_t st = H5Aread(a, type, value);
  H5Aclose(a);
  if (st < 0) corrupt(path, "attribute '" + name + "' of '" + obj + "' cannot be read");
}
}  // namespace

void H5File::set_attr(const std::string& obj, const std::string& name, const std::string& text) {
  const std::string value = shared(text);  // every rank writes the same bytes
  const Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, value.size() + 1);
  write_attr(file_, obj, name, type, value.c_str());
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
  hid_t a = open_attr(file_, path_, obj, name);
  hid_t ftype = H5Aget_type(a);
  const std::size_t size = ftype < 0 ? 0 : H5Tget_size(ftype);
  if (H5Tget_class(ftype) != H5T_STRING || size == 0 || size > (std::size_t{1} << 30)) {
    if (ftype >= 0) H5Tclose(ftype);
    H5Aclose(a);
    corrupt(path_, "attribute '" + name + "' of '" + obj + "' is not a string");
  }
  // Tumble writes fixed-length, null-terminated strings; other writers (h5py) use variable-length
  // strings or fixed-length null-padded ones that fill every byte, so the memory type keeps one
  // byte more than the file's for the terminator (else HDF5 drops the last character). The
  // character set is the file's: HDF5 converts no string between ASCII and UTF-8 (h5py's).
  std::string out;
  hid_t mtype = H5Tcopy(H5T_C_S1);
  H5Tset_cset(mtype, H5Tget_cset(ftype));
  herr_t st = -1;
  if (H5Tis_variable_str(ftype) > 0) {
    H5Tset_size(mtype, H5T_VARIABLE);
    char* text = nullptr;
    st = H5Aread(a, mtype, &text);
    if (st >= 0 && text) out = text;
    if (st >= 0) H5free_memory(text);
  } else {
    out.assign(size + 1, '\0');
    H5Tset_size(mtype, size + 1);
    st = H5Aread(a, mtype, out.data());
  }
  H5Tclose(mtype);
  H5Tclose(ftype);
  H5Aclose(a);
  if (st < 0) corrupt(path_, "attribute '" + name + "' of '" + obj + "' cannot be read");
  out.resize(out.find('\0') == std::string::npos ? out.size() : out.find('\0'));
  return out;
}
double H5File::attr_double(const std::string& obj, const std::string& name) const {
  double v = 0;
  read_attr(file_, path_, obj, name, H5T_NATIVE_DOUBLE, &v);
  return v;
}
std::int64_t H5File::attr_int64(const std::string& obj, const std::string& name) const {
  std::int64_t v = 0;
  read_attr(file_, path_, obj, name, H5T_NATIVE_INT64, &v);
  return v;
}
bool H5File::has_attr(const std::string& obj, const std::string& name) const {
  hid_t o = H5Oopen(file_, obj.c_str(), H5P_DEFAULT);
  if (o < 0) {
    if (obj != "/" && !exists(obj)) return false;  // exists() throws on a damaged group
    corrupt(path_, "object '" + obj + "' is unreadable");
  }
  const htri_t r = H5Aexists(o, name.c_str());
  H5Oclose(o);
  if (r < 0) corrupt(path_, "attributes of '" + obj + "' are unreadable");
  return r > 0;
}

AtomicH5Writer::AtomicH5Writer(const std::string& final_path)
    : final_path_(final_path), tmp_path_(final_path + ".tmp." + std::to_string(::getpid())) {
  register_temporary(tmp_path_);  // (removed should a signal end the process while it is open)
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
  register_temporary(tmp_path_);
  file_ = new H5File(tmp_path_, H5File::Mode::Truncate, comm_);
}

void AtomicH5Writer::commit() {
  // A write that failed anywhere (flush or close) throws here, before the rename: the final name
  // never holds a damaged file, and the destructor removes the temporary.
  std::string failure;
  try {
    file_->close();
  } catch (const std::exception& e) {
    failure = e.what();
  }
  delete file_;
  file_ = nullptr;
  if (comm_ != MPI_COMM_NULL) {  // every rank learns whether any rank failed
    int bad = failure.empty() ? 0 : 1, any = 0;
    MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, comm_);
    if (any && failure.empty()) failure = "HDF5: another rank could not write '" + tmp_path_ + "'";
  }
  if (!failure.empty()) throw std::runtime_error(failure);
  if (comm_ != MPI_COMM_NULL) MPI_Barrier(comm_);  // every rank has closed (and flushed) first
  // Rank 0 puts the file in place; its error is every rank's, said by rank 0 alone (the final
  // file exists for everyone after this): thrown on rank 0 alone, the others went on stepping and
  // rank 0 waited for them in the next collective call, silent, for ever.
  on_rank_0_agreed(comm_, [&] {
    sync_to_disk(tmp_path_);
    if (std::rename(tmp_path_.c_str(), final_path_.c_str()) != 0)
      throw RunError("cannot rename " + tmp_path_ + " to " + final_path_ + ": " +
                     std::strerror(errno));
  });
  committed_ = true;
  forget_temporary(tmp_path_);
}

AtomicH5Writer::~AtomicH5Writer() {
  delete file_;
  int rank = 0;
  if (comm_ != MPI_COMM_NULL) MPI_Comm_rank(comm_, &rank);
  if (!committed_ && rank == 0) std::remove(tmp_path_.c_str());
  forget_temporary(tmp_path_);
}

}  // namespace tumble::io
