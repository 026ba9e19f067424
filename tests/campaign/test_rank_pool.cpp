// Where a case's rank group goes: fixed aligned blocks for one group size (the trailing P mod k
// ranks idle), the lowest free consecutive run for mixed sizes, nothing when no block is free.
#include <gtest/gtest.h>

#include "campaign/rank_pool.hpp"

namespace tumble::campaign {
namespace {

using Ranks = std::vector<int>;

TEST(RankPool, OneGroupSizeMakesAlignedBlocksAndLeavesTheRemainderIdle) {
  RankPool pool(5);
  const Ranks a = pool.place(2);
  EXPECT_EQ(a, (Ranks{0, 1}));
  pool.take(a);
  const Ranks b = pool.place(2);
  EXPECT_EQ(b, (Ranks{2, 3}));
  pool.take(b);
  EXPECT_TRUE(pool.place(2).empty()) << "rank 4 alone cannot host a group of 2";
  pool.release(a);
  EXPECT_EQ(pool.place(2), (Ranks{0, 1}));
}

TEST(RankPool, MixedSizesTakeTheLowestFreeRun) {
  RankPool pool(4);
  pool.take({0});  // a 1-rank case on rank 0
  EXPECT_EQ(pool.place(2), (Ranks{2, 3})) << "the aligned block {2, 3} comes first";
  pool.take({2, 3});
  EXPECT_TRUE(pool.place(2).empty());
  EXPECT_EQ(pool.place(1), (Ranks{1}));
  pool.release({2, 3});
  pool.take({1});
  EXPECT_EQ(pool.place(3), (Ranks{}));  // ranks 1-3 are not free, nor 0-2
  pool.release({0});
  pool.take({3});
  EXPECT_TRUE(pool.place(3).empty());
  pool.release({1});
  EXPECT_EQ(pool.place(3), (Ranks{0, 1, 2})) << "rank 3 busy: the block at 0";
}

TEST(RankPool, GroupsLargerThanTheWorldOrEmptyAreNeverPlaced) {
  RankPool pool(2);
  EXPECT_TRUE(pool.place(3).empty());
  EXPECT_TRUE(pool.place(0).empty());
  EXPECT_EQ(pool.place(2), (Ranks{0, 1}));
}

TEST(RankPool, RankListsReadAsRanges) {
  EXPECT_EQ(rank_list_text({4, 5, 6, 7}), "4-7");
  EXPECT_EQ(rank_list_text({3}), "3");
  EXPECT_EQ(rank_list_text({1, 3, 4}), "1,3,4");
}

}  // namespace
}  // namespace tumble::campaign
