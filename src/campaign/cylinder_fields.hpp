#pragma once
// The fields file of a cylinder case: the run's S_a, S_r and band-count series against
// revolutions (series/iteration holds the revolutions), with the same attributes as a sphere
// case's fields file so that the manifest, the ensemble and `tumble merge` treat both alike.
#include <string>

#include "analysis/cylinder_segregation.hpp"
#include "campaign/field_collector.hpp"

namespace tumble::campaign {

void write_cylinder_fields(const std::string& path, const FieldsMeta& meta, const CollectSpec& spec,
                           const analysis::CylinderSeries& series);

}  // namespace tumble::campaign
