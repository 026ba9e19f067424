#pragma once
// HDF5 form of the cylinder measures (group `cylinder/` of results.h5 and of checkpoints).
#include <string>

#include "analysis/cylinder_segregation.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::io {

void write_cylinder_series(H5File& f, const analysis::CylinderSeries& s);
// Reads the group if present (else leaves `s` empty).
void read_cylinder_series(const H5File& f, analysis::CylinderSeries& s);

}  // namespace tumble::io
