#include "campaign/ensemble.hpp"

#include <hdf5.h>
#include <petscviewerhdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "base/error.hpp"
#include "base/hash.hpp"
#include "base/student_t.hpp"
#include "base/sync_to_disk.hpp"
#include "base/temporary_files.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::campaign {
namespace {

void check(PetscErrorCode ierr, const char* what) {
  if (ierr)
    throw std::runtime_error(std::string("PETSc: ") + what + " failed (error " +
                             std::to_string(static_cast<int>(ierr)) + ")");
}

Vec make_vec(PetscInt n, const std::vector<double>* values = nullptr) {
  Vec v;
  check(VecCreateSeq(PETSC_COMM_SELF, n, &v), "VecCreateSeq");
  if (values) {
    PetscScalar* a;
    check(VecGetArray(v, &a), "VecGetArray");
    for (PetscInt i = 0; i < n; ++i) a[i] = (*values)[i];
    check(VecRestoreArray(v, &a), "VecRestoreArray");
  } else {
    check(VecSet(v, 0.0), "VecSet");
  }
  return v;
}

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
  return out;
}
std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  if (s.empty()) return out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) out.push_back(item);
  return out;
}

constexpr const char* kStatNames[] = {"count", "mean", "m2", "variance", "ci95"};

}  // namespace

PetscScope::PetscScope() {
  PetscBool init = PETSC_FALSE;
  check(PetscInitialized(&init), "PetscInitialized");
  if (init) return;
  PETSC_COMM_WORLD = MPI_COMM_SELF;
  // PETSc's signal handler would claim every crash of the engine as a PETSc error.
  static char arg0[] = "tumble", arg1[] = "-no_signal_handler";
  static char* args[] = {arg0, arg1, nullptr};
  static int argc = 2;
  static char** argv = args;
  check(PetscInitialize(&argc, &argv, nullptr, nullptr), "PetscInitialize");
  owner_ = true;
}

PetscScope::~PetscScope() {
  if (owner_) PetscFinalize();
}

FieldStats::FieldStats(PetscInt n) : n_(n) {
  if (n <= 0) return;
  count_ = make_vec(n);
  mean_ = make_vec(n);
  m2_ = make_vec(n);
}
FieldStats::~FieldStats() { destroy(); }
void FieldStats::destroy() {
  if (count_) VecDestroy(&count_);
  if (mean_) VecDestroy(&mean_);
  if (m2_) VecDestroy(&m2_);
}
FieldStats::FieldStats(FieldStats&& o) noexcept
    : n_(o.n_), count_(o.count_), mean_(o.mean_), m2_(o.m2_) {
  o.count_ = o.mean_ = o.m2_ = nullptr;
  o.n_ = 0;
}
FieldStats& FieldStats::operator=(FieldStats&& o) noexcept {
  if (this != &o) {
    destroy();
    n_ = o.n_;
    count_ = o.count_;
    mean_ = o.mean_;
    m2_ = o.m2_;
    o.count_ = o.mean_ = o.m2_ = nullptr;
    o.n_ = 0;
  }
  return *this;
}

std::vector<double> FieldStats::values(Vec v) {
  PetscInt n;
  check(VecGetLocalSize(v, &n), "VecGetLocalSize");
  const PetscScalar* a;
  check(VecGetArrayRead(v, &a), "VecGetArrayRead");
  std::vector<double> out(a, a + n);
  check(VecRestoreArrayRead(v, &a), "VecRestoreArrayRead");
  return out;
}

void FieldStats::add(const std::vector<double>& x) {
  if (static_cast<PetscInt>(x.size()) != n_)
    throw std::runtime_error("ensemble: a case's field has " + std::to_string(x.size()) +
                             " values, the others " + std::to_string(n_));
  PetscScalar *n, *mean, *m2;
  check(VecGetArray(count_, &n), "VecGetArray");
  check(VecGetArray(mean_, &mean), "VecGetArray");
  check(VecGetArray(m2_, &m2), "VecGetArray");
  for (PetscInt i = 0; i < n_; ++i) {
    if (std::isnan(x[i])) continue;  // missing for this case (an empty cell)
    if (n[i] == 0) {  // Welford's first step, exactly; also ignores what a read file left there
      n[i] = 1;
      mean[i] = x[i];
      m2[i] = 0;
      continue;
    }
    n[i] += 1;
    const double delta = x[i] - mean[i];
    mean[i] += delta / n[i];
    m2[i] += delta * (x[i] - mean[i]);
  }
  check(VecRestoreArray(m2_, &m2), "VecRestoreArray");
  check(VecRestoreArray(mean_, &mean), "VecRestoreArray");
  check(VecRestoreArray(count_, &n), "VecRestoreArray");
}

void FieldStats::merge(const FieldStats& o) {
  if (o.n_ != n_) throw std::runtime_error("ensemble: merging fields of different sizes");
  const std::vector<double> nb = o.count(), mb = o.mean(), m2b = o.m2();
  PetscScalar *n, *mean, *m2;
  check(VecGetArray(count_, &n), "VecGetArray");
  check(VecGetArray(mean_, &mean), "VecGetArray");
  check(VecGetArray(m2_, &m2), "VecGetArray");
  for (PetscInt i = 0; i < n_; ++i) {
    if (nb[i] == 0) continue;
    if (n[i] == 0) {  // copy exactly: the formula would round mean_b * nb / nb
      n[i] = nb[i];
      mean[i] = mb[i];
      m2[i] = m2b[i];
      continue;
    }
    const double na = n[i], total = na + nb[i];
    const double delta = mb[i] - mean[i];
    mean[i] += delta * nb[i] / total;
    m2[i] += m2b[i] + delta * delta * na * nb[i] / total;
    n[i] = total;
  }
  check(VecRestoreArray(m2_, &m2), "VecRestoreArray");
  check(VecRestoreArray(mean_, &mean), "VecRestoreArray");
  check(VecRestoreArray(count_, &n), "VecRestoreArray");
}

void FieldStats::set(const std::vector<double>& count, const std::vector<double>& mean,
                     const std::vector<double>& m2) {
  *this = FieldStats(static_cast<PetscInt>(count.size()));
  if (n_ == 0) return;
  for (auto [vec, src] : {std::pair{count_, &count}, {mean_, &mean}, {m2_, &m2}}) {
    PetscScalar* a;
    check(VecGetArray(vec, &a), "VecGetArray");
    for (PetscInt i = 0; i < n_; ++i) a[i] = (*src)[i];
    check(VecRestoreArray(vec, &a), "VecRestoreArray");
  }
}

std::vector<double> FieldStats::mean() const {
  std::vector<double> m = values(mean_);
  const std::vector<double> n = count();
  for (std::size_t i = 0; i < m.size(); ++i)
    if (n[i] == 0) m[i] = std::numeric_limits<double>::quiet_NaN();  // no value: no mean
  return m;
}

std::vector<double> FieldStats::variance() const {
  const auto n = count(), m2v = m2();
  std::vector<double> out(n.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < n.size(); ++i)
    if (n[i] >= 2) out[i] = m2v[i] / (n[i] - 1);
  return out;
}

std::vector<double> FieldStats::ci95() const {
  const auto n = count(), var = variance();
  std::vector<double> out(n.size(), std::numeric_limits<double>::quiet_NaN());
  std::map<double, double> t;  // quantile per count, computed once
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (n[i] < 2) continue;
    auto it = t.find(n[i]);
    if (it == t.end()) it = t.emplace(n[i], student_t_quantile(0.975, n[i] - 1)).first;
    out[i] = it->second * std::sqrt(var[i] / n[i]);
  }
  return out;
}

std::set<std::string> PointStats::failed_ids() const {
  std::set<std::string> ids;
  for (const std::string& f : failed) ids.insert(f.substr(0, f.find(':')));
  return ids;
}

std::set<std::string> PointStats::case_ids() const {
  std::set<std::string> ids = failed_ids();
  ids.insert(members.begin(), members.end());
  ids.insert(missing.begin(), missing.end());
  return ids;
}

PointStats& Ensemble::point(const Point& p, const CampaignSpec& spec) {
  PointStats& ps = points[p.id];
  if (ps.id.empty()) {
    ps.id = p.id;
    ps.params_text = p.params_text;
    for (const auto& cp : p.params)
      ps.params_canonical +=
          (ps.params_canonical.empty() ? "" : ";") + cp.name + "=" + cp.value.text;
    ps.tier = spec.tier;
    ps.frame = spec.collect.frame;
    ps.grid_n = spec.collect.grid;
  }
  return ps;
}

void Ensemble::add_case(const std::string& point_id, const std::string& case_id,
                        const std::string& fields_file, const std::vector<std::string>& names) {
  PointStats& ps = points.at(point_id);
  io::H5File f(fields_file, io::H5File::Mode::Read);
  for (const auto& name : names) {
    const std::vector<double> x = f.read_double(name);
    auto it = ps.fields.find(name);
    if (it == ps.fields.end())
      it = ps.fields.emplace(name, FieldStats(static_cast<PetscInt>(x.size()))).first;
    it->second.add(x);
  }
  if (f.exists("series/time")) {
    const auto t = f.read_double("series/time");
    const auto it = f.read_double("series/iteration");
    if (ps.series_time.empty() && ps.members.empty()) {
      ps.series_time = t;
      ps.series_iteration = it;
    } else if (t.size() != ps.series_time.size()) {
      throw std::runtime_error("ensemble: case " + case_id + " has " + std::to_string(t.size()) +
                               " series samples, the other cases of its point " +
                               std::to_string(ps.series_time.size()));
    }
  }
  ps.members.push_back(case_id);
  std::sort(ps.members.begin(), ps.members.end());
}

void Ensemble::merge(const Ensemble& other) {
  for (const auto& [id, op] : other.points) {
    auto found = points.find(id);
    if (found == points.end()) {
      PointStats& ps = points[id];
      ps.id = op.id;
      ps.params_text = op.params_text;
      ps.params_canonical = op.params_canonical;
      ps.tier = op.tier;
      ps.frame = op.frame;
      ps.grid_n = op.grid_n;
      ps.members = op.members;
      ps.failed = op.failed;
      ps.missing = op.missing;
      ps.series_time = op.series_time;
      ps.series_iteration = op.series_iteration;
      for (const auto& [name, fs] : op.fields) {
        FieldStats copy;
        copy.set(fs.count(), fs.mean(), fs.m2());
        ps.fields.emplace(name, std::move(copy));
      }
      continue;
    }
    PointStats& ps = found->second;
    const std::set<std::string> mine(ps.members.begin(), ps.members.end());
    for (const auto& m : op.members)
      if (mine.count(m))
        throw InputError("merge: case " + m + " is in two partial results (point " + id +
                         "); remove the stale partial file");
    for (const auto& [name, fs] : op.fields) {
      auto it = ps.fields.find(name);
      if (it == ps.fields.end()) {
        FieldStats copy;
        copy.set(fs.count(), fs.mean(), fs.m2());
        ps.fields.emplace(name, std::move(copy));
      } else {
        it->second.merge(fs);
      }
    }
    if (ps.series_time.empty()) {
      ps.series_time = op.series_time;
      ps.series_iteration = op.series_iteration;
    }
    ps.members.insert(ps.members.end(), op.members.begin(), op.members.end());
    std::sort(ps.members.begin(), ps.members.end());
    ps.failed.insert(ps.failed.end(), op.failed.begin(), op.failed.end());
    ps.missing.insert(ps.missing.end(), op.missing.begin(), op.missing.end());
  }
}

std::size_t Ensemble::member_count() const {
  std::size_t n = 0;
  for (const auto& [id, p] : points) n += p.members.size();
  return n;
}
std::size_t Ensemble::failed_count() const {
  std::size_t n = 0;
  for (const auto& [id, p] : points) n += p.failed.size();
  return n;
}
std::size_t Ensemble::missing_count() const {
  std::size_t n = 0;
  for (const auto& [id, p] : points) n += p.missing.size();
  return n;
}

namespace {
void attr(PetscViewer v, const std::string& obj, const char* name, const std::string& value) {
  check(PetscViewerHDF5WriteAttribute(v, obj.c_str(), name, PETSC_STRING, value.c_str()),
        "PetscViewerHDF5WriteAttribute");
}
void attr(PetscViewer v, const std::string& obj, const char* name, double value) {
  PetscReal r = value;
  check(PetscViewerHDF5WriteAttribute(v, obj.c_str(), name, PETSC_REAL, &r),
        "PetscViewerHDF5WriteAttribute");
}
void attr_int(PetscViewer v, const std::string& obj, const char* name, std::size_t value) {
  PetscInt i = static_cast<PetscInt>(value);
  check(PetscViewerHDF5WriteAttribute(v, obj.c_str(), name, PETSC_INT, &i),
        "PetscViewerHDF5WriteAttribute");
}
// A rows x cols table as one Vec of block size `cols`: an HDF5 dataset of shape (rows, cols).
// PETSc's viewer writes the datasets of ensembles and partial results, so H5File's Fletcher32
// filter does not reach them: their checksums are FNV-1a 64 of the values as read back (row-major
// doubles), listed one "<object> <hex>" per line in the root attribute "checksums". Point groups
// are listed with a digest of the attributes read() uses (point_digest).
std::string value_digest(const std::vector<double>& values) {
  return hex16(fnv1a64(values.data(), values.size() * sizeof(double)));
}
std::string point_digest(std::int64_t row, const std::vector<std::string>& texts,
                         std::int64_t grid_n, std::int64_t series_length) {
  std::string all = std::to_string(row) + '\x1f' + std::to_string(grid_n) + '\x1f' +
                    std::to_string(series_length);
  for (const auto& t : texts) all += '\x1f' + t;
  return hex16(fnv1a64(all));
}

void view_table(PetscViewer v, const char* name, const std::vector<double>& values, PetscInt cols,
                const std::string& group, std::string& checksums) {
  checksums += group + "/" + name + " " + value_digest(values) + "\n";
  Vec x;
  check(VecCreate(PETSC_COMM_SELF, &x), "VecCreate");
  struct Destroy {  // (also when a check throws: a full disk fails VecView)
    Vec* x;
    ~Destroy() { VecDestroy(x); }
  } destroy{&x};
  check(VecSetSizes(x, static_cast<PetscInt>(values.size()), PETSC_DECIDE), "VecSetSizes");
  check(VecSetBlockSize(x, cols), "VecSetBlockSize");
  check(VecSetType(x, VECSEQ), "VecSetType");
  PetscScalar* a;
  check(VecGetArray(x, &a), "VecGetArray");
  std::copy(values.begin(), values.end(), a);
  check(VecRestoreArray(x, &a), "VecRestoreArray");
  check(PetscObjectSetName(reinterpret_cast<PetscObject>(x), name), "PetscObjectSetName");
  check(VecView(x, v), "VecView");
}
bool is_series(const std::string& field) { return field.rfind("series/", 0) == 0; }

// The temporary file of a write that did not reach its rename (a full disk, a final name that
// cannot be replaced): closed and removed, so that no part-written ensemble is left beside the
// final name, whose old file, if any, stays whole.
struct UnfinishedWrite {
  PetscViewer* viewer;
  std::string tmp;
  bool renamed = false;
  UnfinishedWrite(PetscViewer* v, std::string path) : viewer(v), tmp(std::move(path)) {
    register_temporary(tmp);  // (removed should a signal end the process while it is open)
  }
  UnfinishedWrite(const UnfinishedWrite&) = delete;
  UnfinishedWrite& operator=(const UnfinishedWrite&) = delete;
  ~UnfinishedWrite() {
    forget_temporary(tmp);
    if (renamed) return;
    if (*viewer) PetscViewerDestroy(viewer);
    std::remove(tmp.c_str());
  }
};
}  // namespace

// Layout: one table per field and statistic, /fields/<field>/<stat> of shape (points, components),
// row r belonging to the point whose group /points/<id> has attribute row = r. A table per field
// rather than a Vec per point and field keeps the file at a few dozen datasets for any number of
// points: PETSc flushes the file after every VecView, and with parallel HDF5 each flush walks the
// whole metadata cache, so thousands of small Vecs would make writing quadratic. Rows of points
// without a field hold count 0 and NaN; series rows are padded with NaN to the longest series.
void Ensemble::write(const std::string& path) const {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  PetscViewer v = nullptr;
  UnfinishedWrite unfinished(&v, tmp);
  check(PetscViewerHDF5Open(PETSC_COMM_SELF, tmp.c_str(), FILE_MODE_WRITE, &v),
        "PetscViewerHDF5Open");
  std::vector<const PointStats*> rows;
  std::map<std::string, PetscInt> width;  // components per field (the longest, for series)
  std::size_t series_width = 0;
  for (const auto& [id, p] : points) {
    rows.push_back(&p);
    for (const auto& [name, fs] : p.fields) width[name] = std::max(width[name], fs.size());
    series_width = std::max(series_width, p.series_time.size());
  }
  const std::size_t n = rows.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::string checksums;  // "<object> <hex>" lines (value_digest, point_digest)
  for (const auto& [name, cols] : width) {
    check(PetscViewerHDF5PushGroup(v, ("/fields/" + name).c_str()), "PushGroup");
    std::vector<double> table[5];
    const double fill[5] = {0, nan, 0, nan, nan};
    for (int k = 0; k < 5; ++k) table[k].assign(n * cols, fill[k]);
    for (std::size_t r = 0; r < n; ++r) {
      auto it = rows[r]->fields.find(name);
      if (it == rows[r]->fields.end()) continue;
      const FieldStats& fs = it->second;
      const std::vector<double> stats[5] = {fs.count(), fs.mean(), fs.m2(), fs.variance(),
                                            fs.ci95()};
      for (int k = 0; k < 5; ++k) std::copy(stats[k].begin(), stats[k].end(), &table[k][r * cols]);
    }
    for (int k = 0; k < 5; ++k)
      view_table(v, kStatNames[k], table[k], cols, "/fields/" + name, checksums);
    check(PetscViewerHDF5PopGroup(v), "PopGroup");
  }
  if (series_width > 0) {
    check(PetscViewerHDF5PushGroup(v, "/series"), "PushGroup");
    std::vector<double> t(n * series_width, nan), it(n * series_width, nan);
    for (std::size_t r = 0; r < n; ++r) {
      std::copy(rows[r]->series_time.begin(), rows[r]->series_time.end(), &t[r * series_width]);
      std::copy(rows[r]->series_iteration.begin(), rows[r]->series_iteration.end(),
                &it[r * series_width]);
    }
    view_table(v, "time", t, static_cast<PetscInt>(series_width), "/series", checksums);
    view_table(v, "iteration", it, static_cast<PetscInt>(series_width), "/series", checksums);
    check(PetscViewerHDF5PopGroup(v), "PopGroup");
  }

  attr(v, "/", "kind", std::string("tumble ensemble"));
  for (const auto& [k, val] : notes) attr(v, "/", k.c_str(), val);
  attr_int(v, "/", "n_points", points.size());
  attr_int(v, "/", "n_members", member_count());
  attr_int(v, "/", "n_failed", failed_count());
  attr_int(v, "/", "n_missing", missing_count());
  std::vector<std::string> names;
  for (const auto& [name, cols] : width) names.push_back(name);
  attr(v, "/", "fields", join(names, ","));
  attr(v, "/", "layout",
       std::string("/fields/<field>/<stat>: one row per point (attribute 'row' of "
                   "/points/<id>), one column per component (cells of the N x N grid, i * N + j, "
                   "or series samples); /series/time and /series/iteration likewise"));
  attr(v, "/", "statistics",
       std::string("per component: count, mean and m2 (Welford; Chan et al. to merge partial "
                   "results); variance = m2/(count-1); ci95 = t(0.975, count-1) "
                   "sqrt(variance/count); NaN components of a case are missing for it"));
  check(PetscViewerHDF5WriteGroup(v, "/points"), "PetscViewerHDF5WriteGroup");
  for (std::size_t r = 0; r < n; ++r) {
    const PointStats& p = *rows[r];
    const std::string base = "/points/" + p.id;
    check(PetscViewerHDF5WriteGroup(v, base.c_str()), "PetscViewerHDF5WriteGroup");
    attr_int(v, base, "row", r);
    attr(v, base, "params", p.params_text);
    attr(v, base, "params_canonical", p.params_canonical);
    for (const auto& item : split(p.params_canonical, ';')) {
      const auto eq = item.find('=');
      const std::string key = item.substr(0, eq), val = item.substr(eq + 1);
      char* end = nullptr;
      const double d = std::strtod(val.c_str(), &end);
      if (!val.empty() && end && *end == '\0')
        attr(v, base, key.c_str(), d);
      else
        attr(v, base, key.c_str(), val);
    }
    attr(v, base, "tier", p.tier);
    attr(v, base, "frame", p.frame);
    attr_int(v, base, "grid_n", static_cast<std::size_t>(p.grid_n));
    std::vector<std::string> mine;
    for (const auto& [name, fs] : p.fields) mine.push_back(name);
    attr(v, base, "fields", join(mine, ","));
    attr_int(v, base, "series_length", p.series_time.size());
    attr_int(v, base, "n_members", p.members.size());
    attr(v, base, "members", join(p.members, ","));
    attr_int(v, base, "n_failed", p.failed.size());
    attr(v, base, "failed", join(p.failed, "\n"));
    attr_int(v, base, "n_missing", p.missing.size());
    attr(v, base, "missing", join(p.missing, ","));
    checksums += base + " " +
                 point_digest(static_cast<std::int64_t>(r),
                              {p.params_text, p.params_canonical, p.tier, p.frame, join(mine, ","),
                               join(p.members, ","), join(p.failed, "\n"), join(p.missing, ",")},
                              p.grid_n, static_cast<std::int64_t>(p.series_time.size())) +
                 "\n";
  }
  checksums += "/ " + hex16(fnv1a64(join(names, ","))) + "\n";  // the root's "fields"
  attr(v, "/", "checksums", checksums);
  check(PetscViewerDestroy(&v), "PetscViewerDestroy");
  sync_to_disk(tmp);
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot rename " + tmp + " to " + path);
  unfinished.renamed = true;
}

namespace {
// Row r, first `len` columns, of a (rows, cols) dataset read whole.
std::vector<double> row_of(const std::vector<double>& table, std::size_t cols, std::size_t r,
                           std::size_t len) {
  return std::vector<double>(table.begin() + r * cols, table.begin() + r * cols + len);
}
}  // namespace

Ensemble Ensemble::read(const std::string& path, bool fields_wanted) {
  io::H5File f(path, io::H5File::Mode::Read);
  if (!f.has_attr("/", "kind") || f.attr_string("/", "kind") != "tumble ensemble")
    throw InputError("'" + path + "' is not a Tumble ensemble file");
  auto corrupt = [&](const std::string& what) {
    throw CorruptInputError("ensemble '" + path + "': " + what +
                            "; the file is damaged or was not written by Tumble");
  };
  // The digests written with the file (files written before they existed have none: read as they
  // are). Every object read below must then have one, and it must match.
  std::map<std::string, std::string> sums;
  const bool summed = f.has_attr("/", "checksums");
  if (summed)
    for (const auto& line : split(f.attr_string("/", "checksums"), '\n')) {
      const auto sp = line.find(' ');
      if (sp == std::string::npos) corrupt("its checksum list is damaged");
      sums[line.substr(0, sp)] = line.substr(sp + 1);
    }
  auto verify = [&](const std::string& object, const std::string& digest) {
    if (!summed) return;
    const auto it = sums.find(object);
    if (it == sums.end()) corrupt("'" + object + "' has no checksum");
    if (it->second != digest) corrupt("'" + object + "' fails its checksum");
  };
  auto read_summed = [&](const std::string& name) {
    std::vector<double> x = f.read_double(name);
    verify(name, value_digest(x));
    return x;
  };
  const std::string field_list = f.attr_string("/", "fields");
  verify("/", hex16(fnv1a64(field_list)));
  struct Table {
    std::vector<double> data[3];  // count, mean, m2
    std::size_t cols = 0;
  };
  std::map<std::string, Table> tables;
  std::size_t table_rows = 0;  // rows of every table: one per point
  bool have_rows = false;
  auto rows_of = [&](const std::vector<double>& data, std::size_t cols, const std::string& name) {
    const std::size_t rows = cols ? data.size() / cols : 0;
    if (cols == 0 || rows * cols != data.size() || (have_rows && rows != table_rows))
      corrupt("'" + name + "' does not have one row of " + std::to_string(cols) + " per point");
    table_rows = rows;
    have_rows = true;
  };
  for (const auto& name : split(field_list, ',')) {
    Table& t = tables[name];
    const std::string g = "/fields/" + name + "/";
    for (int k = 0; k < 3; ++k) t.data[k] = read_summed(g + kStatNames[k]);
    const auto shape = f.shape(g + "count");
    t.cols = shape.size() == 2 ? shape[1] : 1;
    for (int k = 0; k < 3; ++k) rows_of(t.data[k], t.cols, g + kStatNames[k]);
    for (double c : t.data[0])
      if (!(c >= 0) || c != std::floor(c)) corrupt("'" + g + "count' holds " + std::to_string(c));
  }
  std::vector<double> times, iterations;
  std::size_t series_cols = 0;
  if (f.exists("/series/time")) {
    times = read_summed("/series/time");
    iterations = read_summed("/series/iteration");
    const auto shape = f.shape("/series/time");
    series_cols = shape.size() == 2 ? shape[1] : 1;
    rows_of(times, series_cols, "/series/time");
    rows_of(iterations, series_cols, "/series/iteration");
  }
  Ensemble e;
  for (const auto& id : f.children("/points")) {
    const std::string base = "/points/" + id;
    PointStats& p = e.points[id];
    p.id = id;
    const std::int64_t row = f.attr_int64(base, "row");
    p.params_text = f.attr_string(base, "params");
    p.params_canonical = f.attr_string(base, "params_canonical");
    p.tier = f.attr_string(base, "tier");
    p.frame = f.attr_string(base, "frame");
    const std::int64_t grid_n = f.attr_int64(base, "grid_n");
    p.grid_n = static_cast<int>(grid_n);
    const std::string fields = f.attr_string(base, "fields"),
                      members = f.attr_string(base, "members"),
                      failed = f.attr_string(base, "failed"),
                      missing = f.attr_string(base, "missing");
    p.members = split(members, ',');
    p.failed = split(failed, '\n');
    p.missing = split(missing, ',');
    const std::int64_t length = f.attr_int64(base, "series_length");
    verify(base, point_digest(row,
                              {p.params_text, p.params_canonical, p.tier, p.frame, fields, members,
                               failed, missing},
                              grid_n, length));
    // Indices into the tables: checked, so that no attribute can make a read run off them.
    if (row < 0 || (have_rows && static_cast<std::size_t>(row) >= table_rows))
      corrupt("'" + base + "' has row " + std::to_string(row) + " of " +
              std::to_string(table_rows));
    if (length < 0 || static_cast<std::size_t>(length) > series_cols)
      corrupt("'" + base + "' has series_length " + std::to_string(length) + ", the series " +
              std::to_string(series_cols) + " columns");
    const auto r = static_cast<std::size_t>(row);
    const auto len = static_cast<std::size_t>(length);
    if (len > 0) {
      p.series_time = row_of(times, series_cols, r, len);
      p.series_iteration = row_of(iterations, series_cols, r, len);
    }
    for (const auto& name : split(fields, ',')) {
      const auto found = tables.find(name);
      if (found == tables.end()) corrupt("'" + base + "' names a field '" + name + "' it lacks");
      const Table& t = found->second;
      const std::size_t n = is_series(name) ? len : t.cols;
      if (n > t.cols) corrupt("'" + base + "' has more series samples than '" + name + "'");
      if (!fields_wanted) continue;
      FieldStats fs;
      fs.set(row_of(t.data[0], t.cols, r, n), row_of(t.data[1], t.cols, r, n),
             row_of(t.data[2], t.cols, r, n));
      p.fields.emplace(name, std::move(fs));
    }
  }
  return e;
}

}  // namespace tumble::campaign
