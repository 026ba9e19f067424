#include "campaign/rank_pool.hpp"

namespace tumble::campaign {

bool RankPool::block_free(int first, int k) const {
  if (first < 0 || first + k > size()) return false;
  for (int r = first; r < first + k; ++r)
    if (busy_[static_cast<std::size_t>(r)]) return false;
  return true;
}

std::vector<int> RankPool::place(int k) const {
  if (k < 1 || k > size()) return {};
  int first = -1;
  for (int r = 0; r + k <= size() && first < 0; r += k)
    if (block_free(r, k)) first = r;
  for (int r = 0; r + k <= size() && first < 0; ++r)
    if (block_free(r, k)) first = r;
  if (first < 0) return {};
  std::vector<int> out;
  for (int r = first; r < first + k; ++r) out.push_back(r);
  return out;
}

void RankPool::take(const std::vector<int>& ranks) {
  for (int r : ranks) busy_[static_cast<std::size_t>(r)] = true;
}

void RankPool::release(const std::vector<int>& ranks) {
  for (int r : ranks) busy_[static_cast<std::size_t>(r)] = false;
}

std::string rank_list_text(const std::vector<int>& ranks) {
  if (ranks.empty()) return "";
  bool consecutive = true;
  for (std::size_t i = 1; i < ranks.size(); ++i) consecutive &= ranks[i] == ranks[i - 1] + 1;
  if (consecutive)
    return ranks.size() == 1 ? std::to_string(ranks[0])
                             : std::to_string(ranks.front()) + "-" + std::to_string(ranks.back());
  std::string s;
  for (int r : ranks) s += (s.empty() ? "" : ",") + std::to_string(r);
  return s;
}

}  // namespace tumble::campaign
