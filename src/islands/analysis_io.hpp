#pragma once
// HDF5 files of the snapshot analyses of `tumble analyze` (layouts in docs/report.md). Each is
// written atomically (io::AtomicH5Writer: temporary file + rename) and names its inputs.
#include <string>
#include <vector>

#include "islands/cross_section.hpp"
#include "islands/enrichment.hpp"
#include "islands/fates.hpp"
#include "islands/replica_stats.hpp"

namespace tumble::analysis {

void write_fates(const std::string& path, const SnapshotData& start, const SnapshotData& end,
                 const FateResult& r);

void write_section(const std::string& path, const std::vector<std::string>& inputs,
                   const SectionMap& map, const SectionPlane& plane, double half_width,
                   const std::vector<TubeCrossing>& tubes, int island_a, int island_b);

void write_light(const std::string& path, const std::vector<std::string>& inputs,
                 const std::vector<double>& light, int n, int light_species, double inner);

void write_enrichment(const std::string& path, const std::vector<std::string>& inputs,
                      const std::vector<Enrichment>& values, const MeanCI& stat, double inner);

}  // namespace tumble::analysis
