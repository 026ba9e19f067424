#include "base/agreed_input.hpp"

#include <algorithm>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>

#include "base/comm.hpp"
#include "base/error.hpp"

namespace tumble {
namespace {
enum Kind : int { kFine = 0, kInput = 1, kCorrupt = 2, kOther = 3, kRun = 4 };

// The kind and message of the exception being handled (called in a catch block).
Kind caught(std::string& message) {
  try {
    throw;
  } catch (const CorruptInputError& e) {  // (before InputError, its base)
    message = e.what();
    return kCorrupt;
  } catch (const InputError& e) {
    message = e.what();
    return kInput;
  } catch (const RunError& e) {  // (a campaign retries a case that failed so)
    message = e.what();
    return kRun;
  } catch (const std::exception& e) {
    message = e.what();
    return kOther;
  } catch (...) {  // (this rank leaving alone would leave the others in the next collective)
    message = "an error of no standard type";
    return kOther;
  }
}

[[noreturn]] void throw_kind(int kind, const std::string& message) {
  if (kind == kCorrupt) throw CorruptInputError(message);
  if (kind == kInput) throw InputError(message);
  if (kind == kRun) throw RunError(message);
  throw std::runtime_error(message);
}

// Rank 0 alone says the error every rank is about to throw: silences std::cerr on the others.
void said_by_rank_0(MPI_Comm comm) {
  int mpi = 0;
  MPI_Initialized(&mpi);  // (`run --check` starts no MPI: one process, it says its own errors)
  if (mpi != 0 && rank_in(comm) != 0) std::cerr.setstate(std::ios::badbit);
}

// Rank 0's `text` on every rank of `comm` (collective).
std::string from_rank_0(MPI_Comm comm, std::string text) {
  int size = static_cast<int>(text.size());
  MPI_Bcast(&size, 1, MPI_INT, 0, comm);
  text.resize(static_cast<std::size_t>(size));
  MPI_Bcast(text.data(), size, MPI_CHAR, 0, comm);
  return text;
}
}  // namespace

void agreed_input(MPI_Comm comm, const std::function<void()>& check) {
  int mpi = 0;
  MPI_Initialized(&mpi);
  if (mpi == 0 || size_of(comm) == 1) {
    check();
    return;
  }
  int kind = kFine;
  std::string message;
  try {
    check();
  } catch (...) {
    kind = caught(message);
  }
  const int rank = rank_in(comm), ranks = size_of(comm);  // (MPI is on here)
  int first = kind == kFine ? std::numeric_limits<int>::max() : rank;
  int failed = kind == kFine ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == std::numeric_limits<int>::max()) return;
  MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_SUM, comm);
  int head[2] = {kind, static_cast<int>(message.size())};
  MPI_Bcast(head, 2, MPI_INT, first, comm);
  message.resize(static_cast<std::size_t>(head[1]));
  MPI_Bcast(message.data(), head[1], MPI_CHAR, first, comm);
  if (failed < ranks) {
    // (At the end of the message's first line: a second one is a hint, CLI11's "Run with --help")
    const std::size_t eol = std::min(message.find('\n'), message.size());
    message.insert(eol, " (on rank " + std::to_string(first) + "; " +
                            std::to_string(ranks - failed) + " of the " + std::to_string(ranks) +
                            " ranks passed these checks)");
  }
  said_by_rank_0(comm);
  throw_kind(head[0], message);
}

void on_rank_0_agreed(MPI_Comm comm, const std::function<void()>& work,
                      const std::function<void()>& meet) {
  if (size_of(comm) == 1) {  // (a serial run, MPI_COMM_NULL among them: nothing to agree)
    work();
    if (meet) meet();
    return;
  }
  int kind = kFine;
  std::string message;
  if (rank_in(comm) == 0) {
    try {
      work();
    } catch (...) {
      kind = caught(message);
    }
  }
  if (meet) meet();
  MPI_Bcast(&kind, 1, MPI_INT, 0, comm);
  if (kind == kFine) return;
  message = from_rank_0(comm, message);
  said_by_rank_0(comm);
  throw_kind(kind, message);
}

void thrown_together(MPI_Comm comm, const std::function<void()>& work) {
  // Only the errors the contract covers: one of one rank alone (memory, std::bad_alloc) is still
  // said by the rank that has it.
  try {
    work();
  } catch (const InputError&) {  // (CorruptInputError among them)
    said_by_rank_0(comm);
    throw;
  } catch (const RunError&) {
    said_by_rank_0(comm);
    throw;
  }
}

void error_said() { std::cerr.clear(); }

}  // namespace tumble
