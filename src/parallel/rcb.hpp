#pragma once
// Recursive coordinate bisection of a box over the ranks of a communicator, weighted by particle
// count (or by a work weight per particle): a half-full tumbler is far from uniform, so equal
// boxes would leave ranks idle. Every node splits its rank range [r0, r1) into halves n/2 and
// n - n/2 (any rank count works, 3 too) along the longest side of its particles' bounding box, at
// the coordinate that puts the same fraction of the node's weight below the cut. Each cut is found
// by bisection on the coordinate with one Allreduce per trial for a whole tree level at once, so
// building the tree costs ~60 log2(P) reductions whatever P is.
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "base/vec3.hpp"

namespace tumble::parallel {

struct Box {
  Vec3 lo, hi;
};

class RcbTree {
 public:
  RcbTree() = default;
  // One leaf (rank 0) covering `root`.
  explicit RcbTree(const Box& root) : root_(root) {
    nodes_.push_back({-1, 0, 0, 1, -1, -1, root});
    collect_boxes();
  }

  // Collective over `comm`: builds the tree for its size from every rank's local positions.
  // `weight`: each particle's share of the work (nullptr: 1 each, the particle count).
  static RcbTree build(MPI_Comm comm, const Box& root, const std::vector<Vec3>& x,
                       std::size_t count, const double* weight = nullptr);

  // The tree as numbers (kNodeDoubles per node), and back, for checkpoints: a decomposed run
  // that restarts on as many ranks goes on in the same boxes (a tree built afresh where the bed
  // is at the restart would cut elsewhere, and the run would differ from the uninterrupted one
  // in round-off). from_doubles() throws std::invalid_argument for numbers that are not a tree
  // of `ranks` leaves.
  static constexpr int kNodeDoubles = 12;
  std::vector<double> to_doubles() const;
  static RcbTree from_doubles(const Box& root, const std::vector<double>& data, int ranks);

  // Owner rank of a point (points outside the root box go to the nearest leaf along each cut).
  int owner(const Vec3& p) const;
  // Ranks whose box lies within `reach` of p (periodic in z with `period_z` > 0); p's own owner
  // included. Appends to `out` (no duplicates).
  void ranks_near(const Vec3& p, double reach, double period_z, std::vector<int>& out) const;
  const Box& box(int rank) const { return boxes_[rank]; }
  int ranks() const { return static_cast<int>(boxes_.size()); }

 private:
  struct Node {
    int dim;     // cut dimension (-1: leaf)
    double cut;  // points with p[dim] < cut go low
    int r0, r1;  // rank range
    int lo, hi;  // children (node indices)
    Box box;
  };
  void near(const Vec3& p, double reach2, bool closed_z, std::vector<int>& out) const;
  void collect_boxes();
  Box root_;
  std::vector<Node> nodes_;
  std::vector<Box> boxes_;  // leaf box of each rank
  // Each node's box with the faces it shares with the root pushed to infinity (the root's outer
  // faces are open: strays belong to the nearest leaf), [0] in x, y and z, [1] in x and y only
  // (a periodic z, whose images are tested explicitly). Made once per tree: ranks_near runs for
  // every border particle at every rebuild, ~3 queries each (issue 16: 26% of what 16 ranks add
  // to one's instructions when each query rebuilt them node by node).
  std::vector<Box> open_[2];
};

// Squared distance from a point to a box (0 inside). Inline: the tree's queries call it for
// every node they visit.
inline double distance2(const Box& b, const Vec3& p) {
  double d2 = 0;
  for (int d = 0; d < 3; ++d) {
    const double e = std::max(std::max(b.lo[d] - p[d], 0.0), p[d] - b.hi[d]);
    d2 += e * e;
  }
  return d2;
}

}  // namespace tumble::parallel
