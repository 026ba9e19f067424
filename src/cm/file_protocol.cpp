#include "cm/file_protocol.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

#include "base/error.hpp"
#include "base/version.hpp"

namespace tumble::cm {

const char* const kFileConvention =
    "lab frame, R = 1, time 1/omega; y up, free surface y = 0; z phase u_b = (y,-x,0) "
    "(Omega_z = -z), x phase = z field conjugated by R_y(-90 deg) (Omega_x = +x); "
    "chart: Lambert viewed from below (X,Z) = (x,z)/sqrt(1-y) of bulk directions, layer cap "
    "in the ring rim < |v| < outer (docs/cm.md)";

void write_file_protocol(io::H5File& f, const Protocol& pr, const std::string& kind) {
  f.set_attr("/", "kind", kind);
  f.set_attr("/", "theta_z_deg", pr.theta_z * 180.0 / kPi);
  f.set_attr("/", "theta_x_deg", pr.theta_x * 180.0 / kPi);
  f.set_attr("/", "eps", pr.layer_eps());
  f.set_attr("/", "model", std::string(to_string(pr.model)));
  f.set_attr("/", "convention", std::string(kFileConvention));
  f.set_attr("/", "tumble_version", std::string(kVersion));
  f.set_attr("/", "git_hash", std::string(kGitHash));
}

FileProtocol read_file_protocol(const std::string& path, const std::string& option) {
  namespace fs = std::filesystem;
  if (!fs::exists(path)) throw InputError(option + " '" + path + "': no such file");
  if (!fs::is_regular_file(path))
    throw InputError(option + " '" + path + "' is not a file (a directory?)");
  // A file that does not open as HDF5 was not written by Tumble: the wrong file was given (exit 2),
  // not a damaged one (the wrapper's CorruptInputError, exit 3, is for files Tumble wrote).
  std::unique_ptr<io::H5File> file;
  try {
    file = std::make_unique<io::H5File>(path, io::H5File::Mode::Read);
  } catch (const std::exception& e) {
    throw InputError(option + " '" + path + "' cannot be read as HDF5: " + e.what());
  }
  const io::H5File& f = *file;
  FileProtocol fp;
  const auto number = [&](const char* name, std::optional<double>& out) {
    if (f.has_attr("/", name))
      out = f.attr_double("/", name);
    else
      fp.missing.push_back(name);
  };
  const auto text = [&](const char* name, std::string& out) {
    if (f.has_attr("/", name))
      out = f.attr_string("/", name);
    else
      fp.missing.push_back(name);
  };
  if (f.has_attr("/", "kind")) fp.kind = f.attr_string("/", "kind");
  number("theta_z_deg", fp.theta_z_deg);
  number("theta_x_deg", fp.theta_x_deg);
  number("eps", fp.eps);
  text("model", fp.model);
  text("convention", fp.convention);
  if (f.has_attr("/", "r")) fp.r = f.attr_double("/", "r");
  return fp;
}

namespace {

std::string degrees_pair(double tz, double tx) {
  std::ostringstream s;
  s << "(" << tz << "°, " << tx << "°)";
  return s.str();
}

}  // namespace

std::string describe_protocol(const Protocol& pr) {
  std::ostringstream s;
  s << degrees_pair(pr.theta_z * 180.0 / kPi, pr.theta_x * 180.0 / kPi)
    << ", eps = " << pr.layer_eps() << ", " << to_string(pr.model) << " map";
  return s.str();
}

std::string describe_protocol(const FileProtocol& fp) {
  std::ostringstream s;
  if (fp.theta_z_deg && fp.theta_x_deg)
    s << degrees_pair(*fp.theta_z_deg, *fp.theta_x_deg);
  else
    s << "(theta not recorded)";
  if (fp.eps) s << ", eps = " << *fp.eps;
  if (!fp.model.empty()) s << ", " << fp.model << " map";
  return s.str();
}

FileProtocol require_orbits_file_of(const std::string& path, const std::string& option,
                                    const Protocol& pr, std::string* warning) {
  FileProtocol fp = read_file_protocol(path, option);
  const std::string file = option + " '" + path + "'";
  if (!fp.kind.empty() && fp.kind != "orbits")
    throw InputError(file + " is a '" + fp.kind +
                     "' file; it needs the orbits file of `tumble cm orbits`");
  if (!fp.missing.empty()) {
    // Not a file Tumble wrote (all of them record these): nothing to compare, so it is used as
    // given, and said so.
    if (warning) {
      std::string names;
      for (const auto& m : fp.missing) names += (names.empty() ? "" : ", ") + m;
      *warning = file + " does not record its protocol (" + names +
                 " missing); it is taken to be of " + describe_protocol(pr) + " unchecked";
    }
    return fp;
  }
  const auto same = [](double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(b));
  };
  const double tz = pr.theta_z * 180.0 / kPi, tx = pr.theta_x * 180.0 / kPi;
  // The exact map and the integrated field are one flow (they agree to 1e-6, docs/cm.md Sec. 2);
  // the PWI is another (its recorded eps is 0, so the eps comparison tells them apart too).
  const bool pwi = pr.model == FlowModel::Pwi, file_pwi = fp.model == "pwi";
  std::string differs;
  if (!same(*fp.theta_z_deg, tz) || !same(*fp.theta_x_deg, tx))
    differs = "the rotation angles differ";
  else if (!same(*fp.eps, pr.layer_eps()) || pwi != file_pwi)
    differs = "the flowing layer (eps, model) differs";
  else if (fp.convention != kFileConvention)
    differs = "its sign convention differs from this build's (file: '" + fp.convention + "')";
  if (!differs.empty())
    throw InputError(file + " was computed for the protocol " + describe_protocol(fp) +
                     ", this run is " + describe_protocol(pr) + ": " + differs +
                     ". Compute the orbits of this run's protocol with `tumble cm orbits` (the "
                     "same --theta-z, --theta-x, --eps) and give that file");
  return fp;
}

std::vector<double> island_shells(const std::string& path, const FileProtocol& fp) {
  std::vector<double> shells;
  if (fp.r) shells.push_back(*fp.r);
  io::H5File f(path, io::H5File::Mode::Read);
  if (f.exists("/islands/r"))
    for (double r : f.read_double("/islands/r"))
      if (std::none_of(shells.begin(), shells.end(),
                       [r](double s) { return std::abs(s - r) < 1e-9; }))
        shells.push_back(r);
  std::sort(shells.begin(), shells.end());
  return shells;
}

}  // namespace tumble::cm
