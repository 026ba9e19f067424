#pragma once
// Ensemble statistics in PETSc (docs/architecture.md, "Campaigns"): for every parameter point and
// every collected field, Vecs of count, mean and M2, component by component. Cases are folded in
// with Welford's update; partial results (slices of a job array, other directories) are combined
// with the pairwise formula of Chan, Golub & LeVeque (1979). A NaN component (a cell nobody
// visited) is missing for that case: the count is per component. Written with PetscViewerHDF5
// together with the variance, the 95% confidence half-width, the parameters and the member cases.
#include <petscvec.h>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "campaign/expand.hpp"

namespace tumble::campaign {

// PETSc on this rank only (PETSC_COMM_WORLD = MPI_COMM_SELF): only world rank 0 writes
// ensembles, so the workers never wait on PETSc. Initialises PETSc unless it already is, and
// finalises only what it initialised.
class PetscScope {
 public:
  PetscScope();
  ~PetscScope();
  PetscScope(const PetscScope&) = delete;
  PetscScope& operator=(const PetscScope&) = delete;

 private:
  bool owner_ = false;
};

class FieldStats {
 public:
  explicit FieldStats(PetscInt n = 0);
  ~FieldStats();
  FieldStats(FieldStats&& o) noexcept;
  FieldStats& operator=(FieldStats&& o) noexcept;
  FieldStats(const FieldStats&) = delete;
  FieldStats& operator=(const FieldStats&) = delete;

  PetscInt size() const { return n_; }
  // Welford: count += 1, delta = x - mean, mean += delta / count, M2 += delta (x - mean).
  void add(const std::vector<double>& x);
  // Chan et al.: n = na + nb, delta = mean_b - mean_a, mean = mean_a + delta nb / n,
  // M2 = M2_a + M2_b + delta^2 na nb / n.
  void merge(const FieldStats& other);
  void set(const std::vector<double>& count, const std::vector<double>& mean,
           const std::vector<double>& m2);

  std::vector<double> count() const { return values(count_); }
  std::vector<double> mean() const;  // NaN where the count is 0
  std::vector<double> m2() const { return values(m2_); }
  std::vector<double> variance() const;  // M2 / (n - 1); NaN for n < 2
  std::vector<double> ci95() const;      // t(0.975, n - 1) sqrt(variance / n); NaN for n < 2

  Vec count_vec() const { return count_; }
  Vec mean_vec() const { return mean_; }
  Vec m2_vec() const { return m2_; }

 private:
  static std::vector<double> values(Vec v);
  void destroy();
  PetscInt n_ = 0;
  Vec count_ = nullptr, mean_ = nullptr, m2_ = nullptr;
};

struct PointStats {
  std::string id, params_text, params_canonical, tier, frame;
  int grid_n = 0;
  std::vector<std::string> members;  // case ids folded in, sorted
  std::vector<std::string> failed;   // "case_id: diagnostic" of excluded failed cases
  std::vector<std::string> missing;  // case ids with no result yet (not run, or running)
  // The ids of the failed cases ("case_id: diagnostic" entries).
  std::set<std::string> failed_ids() const;
  // Every case the point accounts for: folded in, failed or without result.
  std::set<std::string> case_ids() const;
  std::vector<double> series_time, series_iteration;
  std::map<std::string, FieldStats> fields;
};

class Ensemble {
 public:
  std::map<std::string, PointStats> points;
  std::map<std::string, std::string> notes;  // root attributes (campaign, slice, sources)

  // Declares a point (parameters) so that it appears even if no case of it succeeded.
  PointStats& point(const Point& p, const CampaignSpec& spec);
  // Folds in one case's fields file (Welford). Names: field_names(spec).
  void add_case(const std::string& point_id, const std::string& case_id,
                const std::string& fields_file, const std::vector<std::string>& names);
  // Chan merge of a partial ensemble with disjoint members (throws if a case is in both).
  void merge(const Ensemble& other);

  // Writes through a temporary file renamed into place (PetscViewerHDF5).
  void write(const std::string& path) const;
  // Every table and attribute is read and checked against its checksum either way; without
  // `fields` the points hold their ids and series but no field statistics, and no PETSc object is
  // made, so PETSc (and through it MPI) need not be running: `campaign --status` reads a slice's
  // statistics this way in a job script, outside the MPI launcher.
  static Ensemble read(const std::string& path, bool fields = true);

  std::size_t member_count() const;
  std::size_t failed_count() const;
  std::size_t missing_count() const;
};

}  // namespace tumble::campaign
