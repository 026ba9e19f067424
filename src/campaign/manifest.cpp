#include "campaign/manifest.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "base/error.hpp"
#include "campaign/json_line.hpp"

namespace tumble::campaign {
namespace fs = std::filesystem;

std::string utc_now() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  char buf[64], out[80];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", std::gmtime(&t));
  std::snprintf(out, sizeof out, "%s.%03dZ", buf, static_cast<int>(ms));
  return out;
}

double unix_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string to_json(const CaseRecord& r) {
  JsonWriter w;
  w.add("case", r.case_id).add("point", r.point_id).add("status", r.status);
  w.add("attempt", r.attempt).add("replica", r.replica).add("seed", r.seed);
  w.add("params", r.params).add("tier", r.tier);
  w.add("group", r.group).add("rank", r.rank).add("ranks", r.ranks).add("host", r.host);
  w.add("hosts", r.hosts).add("output", r.output);
  w.add("start", r.start);
  if (!r.end.empty()) w.add("end", r.end).add("wall", r.wall);
  if (r.resumed_from_step > 0) w.add("resumed_from_step", r.resumed_from_step);
  if (!r.checksum.empty()) w.add("checksum", r.checksum);
  if (r.status == "failed")
    w.add("failure", r.failure).add("diagnostic", r.diagnostic).add("final", r.final_failure);
  if (r.status == "stopped") w.add("diagnostic", r.diagnostic);
  w.add("slice", r.slice).add("t", r.t);
  return w.str();
}

bool from_json(const std::string& line, CaseRecord& r) {
  JsonObject o;
  if (!parse_json_line(line, o)) return false;
  auto text = [&](const char* k) { return o.count(k) ? o[k].text : std::string(); };
  auto num = [&](const char* k) { return o.count(k) ? o[k].number : 0.0; };
  r = CaseRecord{};
  r.case_id = text("case");
  r.point_id = text("point");
  r.status = text("status");
  if (r.case_id.empty() || r.status.empty()) return false;
  r.params = text("params");
  r.tier = text("tier");
  r.attempt = static_cast<int>(num("attempt"));
  r.replica = static_cast<int>(num("replica"));
  r.seed = static_cast<long long>(num("seed"));
  r.group = static_cast<int>(num("group"));
  r.rank = static_cast<int>(num("rank"));
  r.ranks = text("ranks");
  r.host = text("host");
  r.hosts = text("hosts");
  r.output = text("output");
  r.start = text("start");
  r.end = text("end");
  r.wall = num("wall");
  r.resumed_from_step = static_cast<long long>(num("resumed_from_step"));
  r.checksum = text("checksum");
  r.failure = text("failure");
  r.diagnostic = text("diagnostic");
  r.final_failure = num("final") != 0;
  r.slice = text("slice");
  r.t = num("t");
  return true;
}

ManifestWriter::ManifestWriter(const std::string& path) : path_(path) {
  if (const char* hook = std::getenv("TUMBLE_TEST_MANIFEST_FULL")) {
    if (std::sscanf(hook, "%lld:%lld", &full_from_, &full_count_) != 2 || full_from_ < 1 ||
        full_count_ < 0)
      throw InputError("TUMBLE_TEST_MANIFEST_FULL='" + std::string(hook) +
                       "': want <first>:<count>, first >= 1, count >= 0");
  }
  fs::create_directories(fs::path(path).parent_path());
  // Read-write (pread below), appending.
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw std::runtime_error("cannot open manifest '" + path + "': " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw InputError("campaign error: '" + path +
                     "' is locked: this slice of the campaign is already running");
  }
  // A machine crash may have left the last line torn, without its newline: this invocation's
  // first line would be glued to it and both read as one torn line. The torn piece is ended here,
  // so that it stays a line of its own (skipped and counted by the reader).
  const off_t size = ::lseek(fd_, 0, SEEK_END);
  char last = '\n';
  if (size > 0 && ::pread(fd_, &last, 1, size - 1) == 1 && last != '\n' &&
      ::write(fd_, "\n", 1) != 1) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    throw RunError("cannot end the torn last line of the manifest '" + path +
                   "': " + std::strerror(err));
  }
}

ManifestWriter::~ManifestWriter() {
  if (fd_ >= 0) {
    ::fsync(fd_);
    ::close(fd_);  // releases the lock
  }
}

void ManifestWriter::append(const CaseRecord& r) {
  const std::string line = to_json(r) + "\n";
  // One write(2) per line: O_APPEND places it atomically at the end, so a kill never interleaves
  // or truncates a line in the page cache. A short write (a full disk) is finished or undone:
  // the file is cut back to where the line began, so a rerun never reads half a line as a record.
  ++appends_;
  if (full_from_ > 0 && appends_ >= full_from_ && appends_ < full_from_ + full_count_)
    throw RunError("cannot append to the manifest '" + path_ + "': " + std::strerror(ENOSPC) +
                   " (errno " + std::to_string(ENOSPC) +
                   "; TUMBLE_TEST_MANIFEST_FULL); the line "
                   "was not written");
  const off_t begin = ::lseek(fd_, 0, SEEK_END);
  std::size_t done = 0;
  while (done < line.size()) {
    const ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    const int err = n < 0 ? errno : ENOSPC;  // write(2) returning 0 on a file: no room
    if (begin >= 0 && ::ftruncate(fd_, begin) != 0) {
      // Could not undo: the reader skips a line that does not parse (counted as torn).
    }
    throw RunError("cannot append to the manifest '" + path_ + "': " + std::strerror(err) +
                   " (errno " + std::to_string(err) + "); the line was not written");
  }
}

void ManifestWriter::sync() { ::fsync(fd_); }

ManifestState read_manifests(const std::string& dir) {
  ManifestState st;
  const fs::path mdir = fs::path(dir) / "manifest";
  if (!fs::is_directory(mdir)) return st;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(mdir))
    if (e.path().extension() == ".jsonl") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<CaseRecord> all;
  for (const auto& f : files) {
    std::ifstream in(f);
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      CaseRecord r;
      if (from_json(line, r))
        all.push_back(std::move(r));
      else
        ++st.torn_lines;
    }
  }
  // Lines from several files are ordered by their time stamp; within one file the order of
  // appends is kept (stable sort), which settles equal stamps.
  std::stable_sort(all.begin(), all.end(),
                   [](const CaseRecord& a, const CaseRecord& b) { return a.t < b.t; });
  for (auto& r : all) {
    st.attempts[r.case_id] = std::max(st.attempts[r.case_id], r.attempt);
    st.history[r.case_id].push_back(r);
    st.latest[r.case_id] = r;
  }
  return st;
}

}  // namespace tumble::campaign
