// The agreed errors of base/agreed_input.hpp on the world's ranks (2 and 3 under ctest): an error
// thrown on one rank is thrown on every rank, with its type and the failing rank's message; rank 0
// alone says it (std::cerr silenced on the others) until error_said() gives the others their
// voice back. Every test here is collective.
#include <gtest/gtest.h>
#include <mpi.h>

#include <iostream>
#include <stdexcept>
#include <string>

#include "base/agreed_input.hpp"
#include "base/error.hpp"
#include "parallel_helpers.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {

// What every rank caught from `call`: "" when it threw nothing, else "<type>: <message>".
template <class Call>
std::string caught_by(Call call) {
  try {
    call();
  } catch (const CorruptInputError& e) {
    return std::string("CorruptInputError: ") + e.what();
  } catch (const InputError& e) {
    return std::string("InputError: ") + e.what();
  } catch (const RunError& e) {
    return std::string("RunError: ") + e.what();
  } catch (const std::exception& e) {
    return std::string("other: ") + e.what();
  }
  return "";
}

// Whether std::cerr would print on this rank.
bool speaks() { return std::cerr.good(); }

}  // namespace

TEST(AgreedInput, NothingThrownWhenEveryRankPasses) {
  EXPECT_EQ(caught_by([] { agreed_input(MPI_COMM_WORLD, [] {}); }), "");
  EXPECT_TRUE(speaks());
}

TEST(AgreedInput, OneRankFailingEndsEveryRankWithItsMessageAndRank) {
  const int last = size_of(MPI_COMM_WORLD) - 1;
  const std::string got = caught_by([&] {
    agreed_input(MPI_COMM_WORLD, [&] {
      if (world_rank() == last) throw InputError("scene missing on this node");
    });
  });
  const int ranks = size_of(MPI_COMM_WORLD);
  EXPECT_EQ(got, "InputError: scene missing on this node (on rank " + std::to_string(last) + "; " +
                     std::to_string(ranks - 1) + " of the " + std::to_string(ranks) +
                     " ranks passed these checks)");
  EXPECT_EQ(speaks(), world_rank() == 0);  // rank 0 alone says it
  error_said();
  EXPECT_TRUE(speaks());
}

TEST(AgreedInput, TheLowestFailingRankIsTheOneSaidAndItsTypeKept) {
  // Every rank fails, each with its own message: rank 0's is the one thrown, with no rank note
  // (all failed alike), and a corrupt file stays a corrupt file (exit 3, not 2).
  const std::string got = caught_by([] {
    agreed_input(MPI_COMM_WORLD, [] {
      throw CorruptInputError("damaged on rank " + std::to_string(world_rank()));
    });
  });
  EXPECT_EQ(got, "CorruptInputError: damaged on rank 0");
  error_said();
}

TEST(OnRank0Agreed, WorkRunsOnRank0AloneAndItsErrorReachesEveryRank) {
  int ran = 0;
  const std::string got = caught_by([&] {
    on_rank_0_agreed(MPI_COMM_WORLD, [&] {
      ++ran;
      throw RunError("cannot write the beta cache");
    });
  });
  EXPECT_EQ(ran, world_rank() == 0 ? 1 : 0);
  EXPECT_EQ(got, "RunError: cannot write the beta cache");  // retryable in a campaign: kept
  EXPECT_EQ(speaks(), world_rank() == 0);
  error_said();
  EXPECT_TRUE(speaks());
}

TEST(OnRank0Agreed, MeetRunsOnEveryRankAndNoErrorMeansNoThrow) {
  int met = 0;
  EXPECT_EQ(caught_by([&] {
              on_rank_0_agreed(
                  MPI_COMM_WORLD, [] {}, [&] { ++met; });
            }),
            "");
  EXPECT_EQ(met, 1);
  EXPECT_TRUE(speaks());
}

TEST(OnRank0Agreed, AnErrorOfNoTumbleTypeArrivesAsAPlainOne) {
  const std::string got = caught_by(
      [] { on_rank_0_agreed(MPI_COMM_WORLD, [] { throw std::out_of_range("index 7"); }); });
  EXPECT_EQ(got, "other: index 7");
  error_said();
}

TEST(ThrownTogether, ATumbleErrorThrownOnEveryRankIsSaidByRank0Alone) {
  const std::string got = caught_by([] {
    thrown_together(MPI_COMM_WORLD, [] { throw InputError("checkpoint of another scene"); });
  });
  EXPECT_EQ(got, "InputError: checkpoint of another scene");
  EXPECT_EQ(speaks(), world_rank() == 0);
  error_said();
  // An error outside the contract (this rank's own, e.g. memory) is said by the rank that has it.
  const std::string own =
      caught_by([] { thrown_together(MPI_COMM_WORLD, [] { throw std::bad_alloc(); }); });
  EXPECT_FALSE(own.empty());
  EXPECT_TRUE(speaks());
}
