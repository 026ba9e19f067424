#pragma once
// HDF5 form of a realization's time series (group `series/` of results.h5 and of checkpoints,
// plus the cylinder group): one writer and one reader for both files.
#include "analysis/radial_segregation.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::io {

void write_series(H5File& f, const analysis::Series& s);
// Reads what the file holds (series written before a field existed leave it empty).
void read_series(const H5File& f, analysis::Series& s);

}  // namespace tumble::io
