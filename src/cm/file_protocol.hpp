#pragma once
// Which protocol a CM file was computed for, and the check that a file given as input to another
// command (`tumble cm mcm --islands`, `tumble cm manifolds --orbits`) belongs to the run that
// reads it: islands or periodic points of (57°, 57°) are meaningless for (68°, 68°), and nothing
// in the arrays themselves would show it.
//
// Every file cm_io writes records its protocol as attributes of "/" (docs/cm.md, Sec. 6): kind,
// theta_z_deg, theta_x_deg, eps (the layer depth; 0 for the PWI), model, convention (the sign
// convention of the rotations, compared verbatim) and r (the shell of the search). Tumble has
// written them since its first CM file. A file without them (made elsewhere) cannot be checked:
// it is accepted with a warning, so that islands from another tool can still be used.
#include <optional>
#include <string>
#include <vector>

#include "cm/protocol.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::cm {

// The sign convention and chart every CM file records (docs/cm.md, Sec. 1 and 3).
extern const char* const kFileConvention;

// Writes kind, the protocol, the convention and the Tumble version as attributes of "/".
void write_file_protocol(io::H5File& f, const Protocol& pr, const std::string& kind);

struct FileProtocol {
  std::string kind;  // "orbits", "poincare", ...; empty if not recorded
  // The protocol, when the file records all of it.
  std::optional<double> theta_z_deg, theta_x_deg, eps;
  std::string model, convention;     // empty if not recorded
  std::optional<double> r;           // shell of the search (the file's chart)
  std::vector<std::string> missing;  // protocol attributes the file lacks
};

// Reads the root attributes. Throws InputError (naming `option` and the file) when the file does
// not exist or is no HDF5 file.
FileProtocol read_file_protocol(const std::string& path, const std::string& option);

// "(57°, 57°), eps = 0.15, exact map"-style description, for messages.
std::string describe_protocol(const Protocol& pr);
std::string describe_protocol(const FileProtocol& fp);

// Throws InputError unless `path` is a `tumble cm orbits` file of the protocol `pr` (same
// theta_z, theta_x, layer depth, sign convention; the exact and integrated maps count as one
// flow, the PWI as another). The message names the option, the file and both protocols. Returns
// what the file records; `warning` receives a note when the file lacks protocol attributes (then
// nothing could be compared).
FileProtocol require_orbits_file_of(const std::string& path, const std::string& option,
                                    const Protocol& pr, std::string* warning);

// The shells an orbits file has islands for: its search shell and every KAM-tube shell.
std::vector<double> island_shells(const std::string& path, const FileProtocol& fp);

}  // namespace tumble::cm
