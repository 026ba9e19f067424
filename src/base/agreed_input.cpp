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
enum Kind : int { kFine = 0, kInput = 1, kCorrupt = 2, kOther = 3 };
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
  } catch (const CorruptInputError& e) {  // (before InputError, its base)
    kind = kCorrupt, message = e.what();
  } catch (const InputError& e) {
    kind = kInput, message = e.what();
  } catch (const std::exception& e) {
    kind = kOther, message = e.what();
  } catch (...) {  // (this rank leaving alone would leave the others in the Allreduce below)
    kind = kOther, message = "an error of no standard type";
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
  if (head[0] == kCorrupt) throw CorruptInputError(message);
  if (head[0] == kInput) throw InputError(message);
  throw std::runtime_error(message);
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

void said_by_rank_0(MPI_Comm comm) {
  int mpi = 0;
  MPI_Initialized(&mpi);  // (`run --check` starts no MPI: one process, it says its own errors)
  if (mpi != 0 && rank_in(comm) != 0) std::cerr.setstate(std::ios::badbit);
}

std::string from_rank_0(MPI_Comm comm, std::string text) {
  int size = static_cast<int>(text.size());
  MPI_Bcast(&size, 1, MPI_INT, 0, comm);
  text.resize(static_cast<std::size_t>(size));
  MPI_Bcast(text.data(), size, MPI_CHAR, 0, comm);
  return text;
}

}  // namespace tumble
