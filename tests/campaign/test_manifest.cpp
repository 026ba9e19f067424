// The manifest: records survive a round trip, a torn last line (crash mid-write) is ignored, the
// latest line of a case wins across files, a slice cannot be run twice at once, and a full disk
// is reported as such.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "base/error.hpp"
#include "campaign/json_line.hpp"
#include "campaign/manifest.hpp"

namespace tumble::campaign {
namespace {
namespace fs = std::filesystem;

std::string scratch(const std::string& name) {
  const std::string d = std::string(TUMBLE_TEST_SCRATCH) + "/" + name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(JsonLine, EscapesRoundTrip) {
  const std::string nasty = "quote \" backslash \\ newline \n tab \t ctrl \x01 utf8 β";
  JsonWriter w;
  w.add("s", nasty).add("n", 1.0 / 3.0).add("i", 1234567890123456LL).add("b", true);
  JsonObject o;
  ASSERT_TRUE(parse_json_line(w.str(), o));
  EXPECT_EQ(o["s"].text, nasty);
  EXPECT_EQ(o["n"].number, 1.0 / 3.0);
  EXPECT_EQ(o["i"].text, "1234567890123456");
  EXPECT_EQ(o["b"].number, 1);
  const std::string line = w.str();
  for (std::size_t cut = 0; cut < line.size(); ++cut)  // every torn prefix is rejected
    EXPECT_FALSE(parse_json_line(line.substr(0, cut), o)) << line.substr(0, cut);
}

TEST(Manifest, LatestLineWinsAndTornLinesAreIgnored) {
  const std::string dir = scratch("manifest");
  CaseRecord r;
  r.case_id = "aaaa";
  r.point_id = "p";
  r.params = "theta_z=57";
  r.attempt = 1;
  r.seed = 8999999999999999LL;
  r.diagnostic = "line one\nline \"two\"";
  {
    ManifestWriter w(dir + "/manifest/slice_1_of_2.jsonl");
    r.status = "running";
    r.t = 10;
    w.append(r);
    r.status = "failed";
    r.failure = "run";
    r.final_failure = false;
    r.t = 11;
    w.append(r);
  }
  {
    ManifestWriter w(dir + "/manifest/slice_2_of_2.jsonl");
    r.status = "done";
    r.attempt = 2;
    r.checksum = "fnv1a64:0123";
    r.t = 12;
    w.append(r);
  }
  // A crash in the middle of a line.
  std::ofstream(dir + "/manifest/slice_1_of_2.jsonl", std::ios::app) << "{\"case\":\"bbbb\",\"sta";
  const ManifestState st = read_manifests(dir);
  EXPECT_EQ(st.torn_lines, 1);
  ASSERT_EQ(st.latest.count("aaaa"), 1u);
  const CaseRecord& last = st.latest.at("aaaa");
  EXPECT_EQ(last.status, "done");
  EXPECT_EQ(last.attempt, 2);
  EXPECT_EQ(last.seed, 8999999999999999LL);
  EXPECT_EQ(st.history.at("aaaa")[1].diagnostic, "line one\nline \"two\"");
  EXPECT_EQ(last.checksum, "fnv1a64:0123");
  EXPECT_EQ(st.attempts.at("aaaa"), 2);
  EXPECT_EQ(st.history.at("aaaa").size(), 3u);
  EXPECT_EQ(st.latest.count("bbbb"), 0u);
}

// The next invocation after such a crash: its first line is not glued to the torn one (which
// swallowed it: both read as one torn line, and the rerun's "running" record was lost).
TEST(Manifest, AFirstLineAfterATornOneIsKept) {
  const std::string dir = scratch("manifest_torn");
  const std::string file = dir + "/manifest/slice_1_of_1.jsonl";
  fs::create_directories(dir + "/manifest");
  std::ofstream(file) << "{\"case\":\"33d2\",\"status\":\"run";
  CaseRecord r;
  r.case_id = "33d2";
  r.point_id = "p";
  r.status = "running";
  r.attempt = 1;
  r.t = 20;
  {
    ManifestWriter w(file);
    w.append(r);
  }
  const ManifestState st = read_manifests(dir);
  EXPECT_EQ(st.torn_lines, 1);
  ASSERT_EQ(st.latest.count("33d2"), 1u);
  EXPECT_EQ(st.latest.at("33d2").status, "running");
  // A file that ends in its newline is left as it is: no empty line added.
  {
    ManifestWriter w(file);
    r.status = "done";
    r.t = 21;
    w.append(r);
  }
  std::ifstream in(file);
  std::string line;
  int lines = 0;
  while (std::getline(in, line)) {
    EXPECT_FALSE(line.empty());
    ++lines;
  }
  EXPECT_EQ(lines, 3);
  EXPECT_EQ(read_manifests(dir).latest.at("33d2").status, "done");
}

TEST(Manifest, ASliceCannotRunTwiceAtOnce) {
  const std::string dir = scratch("manifest_lock");
  ManifestWriter first(dir + "/m.jsonl");
  EXPECT_THROW(ManifestWriter second(dir + "/m.jsonl"), InputError);
}

}  // namespace
}  // namespace tumble::campaign

namespace tumble::campaign {
namespace {

// A full disk (/dev/full answers every write with ENOSPC): the append fails with the file and
// the cause named, not with an unrelated errno.
TEST(Manifest, AFullDiskIsNamedWithItsCause) {
  ASSERT_TRUE(fs::exists("/dev/full")) << "Linux provides /dev/full";
  ManifestWriter w("/dev/full");
  CaseRecord r;
  r.case_id = "abc";
  r.status = "done";
  try {
    w.append(r);
    FAIL() << "an append to /dev/full succeeded";
  } catch (const RunError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("/dev/full"), std::string::npos) << m;
    EXPECT_NE(m.find("No space left on device"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace tumble::campaign
