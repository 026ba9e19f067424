#pragma once
// `tumble merge DIR`: folds the partial statistics of every slice of a campaign
// (DIR/partials/slice_I_of_N.h5) into DIR/ensemble.h5 with Chan's pairwise formula.
#include <iosfwd>
#include <string>

namespace tumble::campaign {

// `slices` = 0: the only slicing present (an error if several are); otherwise that N. Returns the
// exit code: 0, 10 when slices or cases are still missing (the ensemble is written anyway), else 4
// when cases failed and are excluded (as the campaign itself).
int merge_campaign(const std::string& dir, int slices, std::ostream& out);

}  // namespace tumble::campaign
