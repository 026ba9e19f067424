#include "campaign/merge.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <ostream>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "base/exit_codes.hpp"
#include "base/usable_directory.hpp"
#include "base/version.hpp"
#include "campaign/campaign_run.hpp"
#include "campaign/ensemble.hpp"
#include "campaign/manifest.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::campaign {
namespace fs = std::filesystem;

namespace {
// A partial holding a case that the directory's case table does not list is another campaign's
// (left by a run with --force, or copied in): folded in, its points would enter this campaign's
// ensemble and the merge call it complete. Refused, named.
void check_cases_listed(const Ensemble& part, const std::string& file,
                        const std::set<std::string>& table, const std::string& dir) {
  if (table.empty()) return;  // (no case table: a campaign directory from before it)
  for (const auto& [pid, p] : part.points)
    for (const std::string& id : p.case_ids())
      if (!table.count(id))
        throw InputError("merge: " + file + " holds case " + id + " (point " + pid + "), which " +
                         dir +
                         "/cases.tsv does not list: it is another campaign's partial result "
                         "(left by a run with --force, or copied in); remove it, or rerun its "
                         "slice");
}
// The case ids a partial accounts for: folded in, failed (excluded) or listed without result.
std::set<std::string> accounted_cases(const Ensemble& e) {
  std::set<std::string> ids;
  for (const auto& [pid, p] : e.points) {
    const std::set<std::string> mine = p.case_ids();
    ids.insert(mine.begin(), mine.end());
  }
  return ids;
}

// Cases of the directory's table that no partial accounts for (a slice not run yet, or one whose
// partial predates a sweep that grew the campaign) are listed as without result, in their points
// (declared here if no partial has them), so that the merge does not call an incomplete
// ensemble complete. Returns how many there were.
std::size_t add_unaccounted(Ensemble& total, const std::vector<CaseTableRow>& table) {
  const std::set<std::string> seen = accounted_cases(total);
  // A point no partial holds takes the campaign-wide settings of any point that one does.
  const PointStats* any = total.points.empty() ? nullptr : &total.points.begin()->second;
  std::size_t added = 0;
  for (const CaseTableRow& row : table) {
    if (seen.count(row.id)) continue;
    PointStats& p = total.points[row.point];
    if (p.id.empty()) {
      p.id = row.point;
      p.params_text = row.params;
      // (The table shows the parameters as the sweep gave them; their values read the same.)
      p.params_canonical = row.params;
      if (any) {
        p.tier = any->tier;
        p.frame = any->frame;
        p.grid_n = any->grid_n;
      }
    }
    p.missing.push_back(row.id);
    ++added;
  }
  for (auto& [pid, p] : total.points) std::sort(p.missing.begin(), p.missing.end());
  return added;
}
}  // namespace

int merge_campaign(const std::string& dir, int slices, std::ostream& out) {
  const fs::path pdir = fs::path(dir) / "partials";
  if (fs::exists(pdir) && !fs::is_directory(pdir))
    throw InputError("merge: '" + pdir.string() + "' is a file, not the folder of partial results");
  if (!fs::is_directory(pdir))
    throw InputError("merge: '" + pdir.string() +
                     "' does not exist: run the campaign (or its slices) into " + dir + " first");
  // Where the ensemble goes, asked before any partial is folded: a folder that takes no file
  // failed in PETSc's HDF5 viewer, with its error stack, and a folder in the file's place after
  // the whole fold.
  const std::string path = dir + "/ensemble.h5";
  if (fs::is_directory(path))
    throw InputError("merge: '" + path + "' is a folder; the ensemble file goes there: remove it");
  if (const std::string why = cannot_make_directory(dir); !why.empty())
    throw InputError("merge: '" + dir + "' cannot take ensemble.h5: " + why);
  std::map<int, std::map<int, std::string>> found;  // n -> i -> file
  const std::regex name(R"(slice_(\d+)_of_(\d+)\.h5)");
  for (const auto& entry : fs::directory_iterator(pdir)) {
    std::smatch m;
    const std::string f = entry.path().filename().string();
    if (!std::regex_match(f, m, name)) continue;
    // (A name no slicing writes, slice_3_of_2.h5 or numbers past any int, is a stray file: named,
    // not read as a slice of something, nor left to std::stoi to reject with "stoi".)
    const std::string i = m[1], n = m[2];
    if (i.size() > 7 || n.size() > 7 || std::stoi(n) > 1000000 || std::stoi(i) < 1 ||
        std::stoi(i) > std::stoi(n))
      throw InputError("merge: " + entry.path().string() +
                       " is no slice's partial result (slice_I_of_N.h5 with 1 <= I <= N <= "
                       "1000000): remove it");
    found[std::stoi(n)][std::stoi(i)] = entry.path().string();
  }
  if (found.empty()) throw InputError("merge: no partial results in " + pdir.string());
  if (slices == 0) {
    if (found.size() > 1) {
      std::string ns;
      for (const auto& [n, files] : found) ns += (ns.empty() ? "" : ", ") + std::to_string(n);
      throw InputError("merge: " + pdir.string() +
                       " holds partial results of several slicings (n = " + ns +
                       "); choose one with --slices N or remove the stale files");
    }
    slices = found.begin()->first;
  }
  if (!found.count(slices))
    throw InputError("merge: no partial results of " + std::to_string(slices) + " slices in " +
                     pdir.string());
  const auto& files = found.at(slices);

  const std::vector<CaseTableRow> rows = case_table(dir);
  const std::set<std::string> table = case_table_ids(dir);
  PetscScope petsc;
  Ensemble total;
  std::string sources, missing_slices, campaign;
  std::map<std::string, std::string> holder;  // case id -> the partial that holds it
  for (int i = 1; i <= slices; ++i) {         // fixed order: the merge is reproducible bit for bit
    auto it = files.find(i);
    if (it == files.end()) {
      missing_slices += (missing_slices.empty() ? "" : ",") + std::to_string(i);
      continue;
    }
    Ensemble part;
    try {
      part = Ensemble::read(it->second);
    } catch (const CorruptInputError& e) {
      // (The way out named: the slice is folded again from its cases' fields files.)
      throw CorruptInputError(std::string(e.what()) + "; remove " + it->second +
                              " and rerun slice " + std::to_string(i) + "/" +
                              std::to_string(slices) + " (it folds its finished cases again)");
    }
    check_cases_listed(part, it->second, table, dir);
    // A case in two partials: one of them is stale (written before the campaign grew and its
    // cases were dealt to the slices anew, or before a slicing changed). Named, both files.
    for (const std::string& id : accounted_cases(part))
      if (auto [at, fresh] = holder.emplace(id, it->second); !fresh)
        throw InputError("merge: case " + id + " is in two partial results, " + at->second +
                         " and " + it->second +
                         ": one of them is stale; rerun the slice whose file is older (tumble "
                         "campaign FILE --slice I/N) to write it again");
    total.merge(part);
    sources += (sources.empty() ? "" : ",") + fs::path(it->second).filename().string();
    io::H5File f(it->second, io::H5File::Mode::Read);
    if (campaign.empty() && f.has_attr("/", "campaign")) campaign = f.attr_string("/", "campaign");
  }
  const std::size_t unaccounted = add_unaccounted(total, rows);
  total.notes["campaign"] = campaign;
  total.notes["slice"] = "merged " + std::to_string(files.size()) + " of " + std::to_string(slices);
  total.notes["sources"] = sources;
  total.notes["missing_slices"] = missing_slices;
  total.notes["written_utc"] = utc_now();
  total.notes["tumble_version"] = kVersion;
  total.notes["git_hash"] = kGitHash;
  total.write(path);
  out << "merge: " << files.size() << " of " << slices << " slices -> " << path << ": "
      << total.points.size() << " points, " << total.member_count() << " cases, "
      << total.failed_count() << " failed (excluded), " << total.missing_count()
      << " without result\n";
  for (const auto& [id, p] : total.points)
    for (const auto& f : p.failed) out << "merge:   excluded " << f << "\n";
  if (!missing_slices.empty())
    out << "merge: slices not run yet: " << missing_slices << " (their cases are not included)\n";
  if (unaccounted > 0)
    out << "merge: " << unaccounted << " case" << (unaccounted == 1 ? "" : "s") << " of " << dir
        << "/cases.tsv in no partial result (a slice not run yet, or run before the campaign "
           "grew: rerun its slice), counted without result\n";
  if (!missing_slices.empty() || total.missing_count() > 0) return exit_code::kWorkLeft;
  // (as the campaign that ends with failed cases: a job script's `merge && report` stops alike)
  if (total.failed_count() > 0) {
    out << "merge: " << total.failed_count() << " case" << (total.failed_count() == 1 ? "" : "s")
        << " failed and excluded from the ensemble (rerun their slices with --retry-failed to "
           "try them again); exit code 4\n";
    return exit_code::kFailedCases;
  }
  return exit_code::kOk;
}

}  // namespace tumble::campaign
