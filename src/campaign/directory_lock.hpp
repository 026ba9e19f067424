#pragma once
// One lock per campaign directory that covers every slicing: the slices of one slicing (1/n ..
// n/n, a job array) may run at the same time, but a whole campaign and a slice of it, or two
// slicings with different n, may not: they would compute the same cases twice into the same case
// folders. Each invocation holds a POSIX read lock on byte n of DIR/campaign.lock (its slicing)
// and refuses to start while any other byte is locked by another process. The kernel drops the
// locks of a killed process, so a crash never leaves the directory locked; fcntl locks also work
// on NFS (lockd), where flock may not. (The same slice twice is refused by the manifest's own
// lock, campaign/manifest.hpp.)
#include <string>

namespace tumble::campaign {

class DirectoryLock {
 public:
  // Throws InputError naming the directory if another slicing holds it.
  DirectoryLock(const std::string& dir, int slicing);
  ~DirectoryLock();
  // The process that runs a campaign (any slicing) in `dir` right now: its pid, -1 if the
  // kernel cannot name it (another pid namespace, another NFS client), 0 if none (`--status`).
  static int running_process(const std::string& dir);
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  int fd_ = -1;
};

// Held while a run checks that the directory holds its campaign and writes its case table
// (DIR/campaign.table.lock, an exclusive lock, waited for): two campaigns started at once into an
// empty directory, as slices of the same slicing, both found no table and both ran; now the second
// finds the first's table and is refused.
class CaseTableLock {
 public:
  explicit CaseTableLock(const std::string& dir);
  ~CaseTableLock();
  CaseTableLock(const CaseTableLock&) = delete;
  CaseTableLock& operator=(const CaseTableLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace tumble::campaign
