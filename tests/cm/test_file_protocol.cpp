// A CM file records its protocol, and an orbits file given to another run (`mcm --islands`,
// `manifolds --orbits`) must be of that run's protocol (cm/file_protocol.hpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "base/error.hpp"
#include "cm/cm_io.hpp"
#include "cm/file_protocol.hpp"
#include "h5/hdf5_file.hpp"

namespace {
using namespace tumble::cm;
namespace fs = std::filesystem;

std::string temp(const std::string& name) { return (fs::temp_directory_path() / name).string(); }

// An orbits file of (57°, 57°) without islands (period 1 has none): enough to carry the protocol.
std::string orbits_file(const Protocol& pr, const std::string& name) {
  const SectionMap map(pr, ShellChart(0.95, pr.layer_eps()));
  PeriodicSearch ps;
  ps.max_period = 1;
  ps.grid = 6;
  const std::string path = temp(name);
  write_orbits(path, pr, 0.95, find_periodic_points(map, ps), {});
  return path;
}

std::string refusal(const std::string& path, const Protocol& pr) {
  try {
    require_orbits_file_of(path, "--islands", pr, nullptr);
  } catch (const tumble::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FileProtocol, OrbitsOfAnotherProtocolAreRefusedNamingBoth) {
  const std::string path = orbits_file(Protocol::degrees(68, 68), "tumble_fp_68.h5");
  const std::string msg = refusal(path, Protocol::degrees(57, 57));
  EXPECT_NE(msg.find("(68°, 68°)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("(57°, 57°)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--islands"), std::string::npos) << msg;
  // Only one angle differing is another protocol too.
  EXPECT_NE(refusal(path, Protocol::degrees(68, 57)), "");
  EXPECT_NE(refusal(path, Protocol::degrees(57, 68)), "");
  // eps, and the PWI (eps -> 0 limit) against the exact map.
  EXPECT_NE(refusal(path, Protocol::degrees(68, 68, 0.1)), "");
  EXPECT_NE(refusal(path, Protocol::degrees(68, 68, 0.15, FlowModel::Pwi)), "");
  // The same protocol passes, with the exact map or its integrated check.
  EXPECT_EQ(refusal(path, Protocol::degrees(68, 68)), "");
  EXPECT_EQ(refusal(path, Protocol::degrees(68, 68, 0.15, FlowModel::Integrated)), "");
  const FileProtocol fp = read_file_protocol(path, "--islands");
  EXPECT_EQ(fp.kind, "orbits");
  EXPECT_DOUBLE_EQ(*fp.r, 0.95);
  EXPECT_TRUE(fp.missing.empty());
  EXPECT_EQ(island_shells(path, fp), std::vector<double>{0.95});
  fs::remove(path);
}

// A file without protocol attributes (not written by Tumble) is used with a warning that says
// what is missing; a file of another kind, a missing file and a file that is no HDF5 are refused.
TEST(FileProtocol, UnrecordedProtocolWarnsOtherFilesAreRefused) {
  const std::string bare = temp("tumble_fp_bare.h5");
  {
    tumble::io::H5File f(bare, tumble::io::H5File::Mode::Truncate);
    f.write("/islands/r", std::vector<double>{});
  }
  std::string warning;
  const FileProtocol fp =
      require_orbits_file_of(bare, "--islands", Protocol::degrees(57, 57), &warning);
  EXPECT_EQ(fp.missing.size(), 5u);
  EXPECT_NE(warning.find("theta_z_deg"), std::string::npos) << warning;
  EXPECT_NE(warning.find("unchecked"), std::string::npos) << warning;

  const std::string other = temp("tumble_fp_drift.h5");
  {
    tumble::io::H5File f(other, tumble::io::H5File::Mode::Truncate);
    write_file_protocol(f, Protocol::degrees(57, 57), "mcm");
  }
  EXPECT_NE(refusal(other, Protocol::degrees(57, 57)).find("'mcm' file"), std::string::npos);
  EXPECT_NE(refusal(temp("tumble_fp_nowhere.h5"), Protocol::degrees(57, 57)).find("no such file"),
            std::string::npos);
  const std::string text = temp("tumble_fp_text.h5");
  { std::ofstream(text) << "not HDF5\n"; }
  EXPECT_NE(refusal(text, Protocol::degrees(57, 57)).find("cannot be read as HDF5"),
            std::string::npos);
  for (const auto& p : {bare, other, text}) fs::remove(p);
}

// An islands table whose offsets point past its vertices is refused as damaged (exit 3), not
// read out of bounds.
TEST(FileProtocol, DamagedIslandTablesAreRefused) {
  const std::string path = temp("tumble_fp_damaged.h5");
  {
    tumble::io::H5File f(path, tumble::io::H5File::Mode::Truncate);
    f.write("/islands/vertices", std::vector<double>{0, 0, 0.1, 0, 0, 0.1}, {3, 2});
    f.write("/islands/offsets", std::vector<std::int64_t>{0, 30});
    f.write("/islands/center", std::vector<double>{0, 0}, {1, 2});
    f.write("/islands/launch", std::vector<double>{0.1, 0}, {1, 2});
    f.write("/islands/r", std::vector<double>{0.95});
    f.write("/islands/period", std::vector<std::int32_t>{3});
    f.write("/islands/orbit", std::vector<std::int32_t>{0});
    f.write("/islands/point", std::vector<std::int32_t>{0});
  }
  EXPECT_THROW(read_islands(path), tumble::CorruptInputError);
  fs::remove(path);
}

}  // namespace
