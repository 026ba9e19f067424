#pragma once
// Growing arrays that are rebuilt often (neighbour lists, the lane kernels' scratch) without
// std::vector::resize's doubling: a list that grows by a few pairs would otherwise keep twice the
// memory it needs for the rest of the run (measured: 1.0 kB per particle on the shared R35 bed,
// half of it such slack).
#include <cstddef>
#include <vector>

namespace tumble {

// v.resize(n), reserving 1/8 more than n when it must grow.
template <class T>
void resize_with_headroom(std::vector<T>& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(n + n / 8);
  v.resize(n);
}

// The same for an array whose contents are about to be overwritten: when it must grow, its old
// memory is freed before the new is taken, so the process never holds both (a rebuild's peak
// would otherwise hold the list's springs twice: docs/performance.md, "Memory").
template <class T>
void resize_discarding(std::vector<T>& v, std::size_t n) {
  if (n > v.capacity()) {
    std::vector<T>().swap(v);
    v.reserve(n + n / 8);
  }
  v.resize(n);
}

}  // namespace tumble
