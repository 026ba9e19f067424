#pragma once
// Which world ranks are free, and where a case of k ranks goes: the lowest free block of k
// consecutive ranks starting at a multiple of k (the groups MPI_Comm_split(rank / k) would make,
// so a campaign of one group size keeps fixed groups and P mod k trailing ranks stay idle), else
// the lowest run of k consecutive free ranks (campaigns that mix group sizes). Consecutive ranks
// are, under every usual mapping, on the same node as far as possible.
#include <string>
#include <vector>

namespace tumble::campaign {

class RankPool {
 public:
  explicit RankPool(int size) : busy_(static_cast<std::size_t>(size), false) {}
  int size() const { return static_cast<int>(busy_.size()); }
  // The ranks for a case of k, or empty if no such block is free now.
  std::vector<int> place(int k) const;
  void take(const std::vector<int>& ranks);
  void release(const std::vector<int>& ranks);
  bool free(int rank) const { return !busy_[static_cast<std::size_t>(rank)]; }

 private:
  bool block_free(int first, int k) const;
  std::vector<bool> busy_;
};

// "4-7" for consecutive ranks, else "1,3,4".
std::string rank_list_text(const std::vector<int>& ranks);

}  // namespace tumble::campaign
