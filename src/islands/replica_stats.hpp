#pragma once
// Mean and 95% confidence half-width of a scalar over replicas (Student t, as ensemble.h5 does
// for the fields), for the scalar analyses of `tumble analyze campaign`.
#include <vector>

namespace tumble::analysis {

struct MeanCI {
  double mean = 0;
  double ci95 = 0;  // t(0.975, n - 1) s / sqrt(n); NaN for n < 2
  int n = 0;        // finite values used
};

// NaN values (e.g. enrichment of a protocol without islands) are left out.
MeanCI mean_ci95(const std::vector<double>& values);

}  // namespace tumble::analysis
