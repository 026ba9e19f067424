#include "parallel/rcb.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tumble::parallel {

RcbTree RcbTree::build(MPI_Comm comm, const Box& root, const std::vector<Vec3>& x,
                       std::size_t count, const double* weight) {
  const auto w = [weight](std::size_t i) { return weight ? weight[i] : 1.0; };
  int nranks = 1;
  MPI_Comm_size(comm, &nranks);
  RcbTree t;
  t.root_ = root;
  t.nodes_.push_back({-1, 0, 0, nranks, -1, -1, root});
  // Node of every local particle at the current level (all start at the root).
  std::vector<int> node_of(count, 0);
  std::vector<int> level{0};
  while (!level.empty()) {
    std::vector<int> split;  // nodes of this level with more than one rank
    for (int k : level)
      if (t.nodes_[k].r1 - t.nodes_[k].r0 > 1) split.push_back(k);
    if (split.empty()) break;
    const std::size_t m = split.size();
    std::vector<int> slot(t.nodes_.size(), -1);  // node -> position in `split`
    for (std::size_t s = 0; s < m; ++s) slot[split[s]] = static_cast<int>(s);
    // Cut along the longest side of the node's particles (not of its box: a box that reaches
    // into the empty upper half of the tumbler would be sliced into thin slabs along y, with a
    // large surface and many ghosts). An empty node falls back to its box.
    std::vector<double> ext(6 * m, -1e300);  // per node: {-min x, -min y, -min z, max x, ...}
    for (std::size_t i = 0; i < count; ++i) {
      const int sl = slot[node_of[i]];
      if (sl < 0) continue;
      for (int d = 0; d < 3; ++d) {
        ext[6 * sl + d] = std::max(ext[6 * sl + d], -x[i][d]);
        ext[6 * sl + 3 + d] = std::max(ext[6 * sl + 3 + d], x[i][d]);
      }
    }
    MPI_Allreduce(MPI_IN_PLACE, ext.data(), static_cast<int>(6 * m), MPI_DOUBLE, MPI_MAX, comm);
    std::vector<int> dim(m);
    std::vector<double> a(m), b(m), cut(m);
    for (std::size_t s = 0; s < m; ++s) {
      const Box& bx = t.nodes_[split[s]].box;
      Vec3 e = bx.hi - bx.lo;
      if (ext[6 * s + 3] > -1e300)
        e = {ext[6 * s + 3] + ext[6 * s], ext[6 * s + 4] + ext[6 * s + 1],
             ext[6 * s + 5] + ext[6 * s + 2]};
      dim[s] = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
      a[s] = bx.lo[dim[s]];
      b[s] = bx.hi[dim[s]];
    }
    // Totals per node and the target weight below each cut.
    std::vector<double> local(m, 0), total(m);
    for (std::size_t i = 0; i < count; ++i)
      if (slot[node_of[i]] >= 0) local[slot[node_of[i]]] += w(i);
    MPI_Allreduce(local.data(), total.data(), static_cast<int>(m), MPI_DOUBLE, MPI_SUM, comm);
    std::vector<double> target(m);
    for (std::size_t s = 0; s < m; ++s) {
      const Node& nd = t.nodes_[split[s]];
      const int n = nd.r1 - nd.r0;
      target[s] = total[s] * (n / 2) / n;
    }
    // Bisection on the cut coordinate: 60 halvings reach round-off for any box.
    for (int it = 0; it < 60; ++it) {
      for (std::size_t s = 0; s < m; ++s) cut[s] = 0.5 * (a[s] + b[s]);
      std::fill(local.begin(), local.end(), 0.0);
      for (std::size_t i = 0; i < count; ++i) {
        const int s = slot[node_of[i]];
        if (s >= 0 && x[i][dim[s]] < cut[s]) local[s] += w(i);
      }
      MPI_Allreduce(local.data(), total.data(), static_cast<int>(m), MPI_DOUBLE, MPI_SUM, comm);
      for (std::size_t s = 0; s < m; ++s) (total[s] < target[s] ? a[s] : b[s]) = cut[s];
    }
    // The bisection ends on a particle; move each cut to the middle of the gap between the
    // particles on either side, so that a particle sits on no border.
    std::vector<double> edge(2 * m, -1e300);  // {max below, -min above} per node
    for (std::size_t i = 0; i < count; ++i) {
      const int s = slot[node_of[i]];
      if (s < 0) continue;
      const double c = b[s], xd = x[i][dim[s]];  // b: the particles below it are the target
      if (xd < c)
        edge[2 * s] = std::max(edge[2 * s], xd);
      else
        edge[2 * s + 1] = std::max(edge[2 * s + 1], -xd);
    }
    MPI_Allreduce(MPI_IN_PLACE, edge.data(), static_cast<int>(2 * m), MPI_DOUBLE, MPI_MAX, comm);
    std::vector<int> next;
    for (std::size_t s = 0; s < m; ++s) {
      const int k = split[s];
      double c = b[s];
      if (edge[2 * s] > -1e300 && edge[2 * s + 1] > -1e300)
        c = 0.5 * (edge[2 * s] - edge[2 * s + 1]);
      Node lo = t.nodes_[k], hi = t.nodes_[k];
      const int half = (lo.r1 - lo.r0) / 2;
      lo.r1 = lo.r0 + half;
      hi.r0 = lo.r1;
      lo.box.hi[dim[s]] = c;
      hi.box.lo[dim[s]] = c;
      lo.dim = hi.dim = -1;
      lo.lo = lo.hi = hi.lo = hi.hi = -1;
      t.nodes_[k].dim = dim[s];
      t.nodes_[k].cut = c;
      t.nodes_[k].lo = static_cast<int>(t.nodes_.size());
      t.nodes_.push_back(lo);
      t.nodes_[k].hi = static_cast<int>(t.nodes_.size());
      t.nodes_.push_back(hi);
      next.push_back(t.nodes_[k].lo);
      next.push_back(t.nodes_[k].hi);
    }
    for (std::size_t i = 0; i < count; ++i) {
      const Node& nd = t.nodes_[node_of[i]];
      if (nd.dim >= 0) node_of[i] = x[i][nd.dim] < nd.cut ? nd.lo : nd.hi;
    }
    level = std::move(next);
  }
  t.collect_boxes();
  return t;
}

std::vector<double> RcbTree::to_doubles() const {
  std::vector<double> out;
  out.reserve(nodes_.size() * kNodeDoubles);
  for (const Node& nd : nodes_) {
    out.insert(out.end(), {static_cast<double>(nd.dim), nd.cut, static_cast<double>(nd.r0),
                           static_cast<double>(nd.r1), static_cast<double>(nd.lo),
                           static_cast<double>(nd.hi)});
    for (int d = 0; d < 3; ++d) out.push_back(nd.box.lo[d]);
    for (int d = 0; d < 3; ++d) out.push_back(nd.box.hi[d]);
  }
  return out;
}

RcbTree RcbTree::from_doubles(const Box& root, const std::vector<double>& data, int ranks) {
  const std::size_t n = data.size() / kNodeDoubles;
  auto bad = [](const std::string& why) {
    throw std::invalid_argument("the decomposition's tree " + why);
  };
  // build() makes 2 ranks - 1 nodes.
  if (ranks < 1 || data.size() % kNodeDoubles != 0 || n != 2 * static_cast<std::size_t>(ranks) - 1)
    bad("has " + std::to_string(data.size()) + " numbers, not the " +
        std::to_string(2 * ranks - 1) + " nodes of " + std::to_string(ranks) + " ranks");
  auto whole = [](double v, double lo, double hi) {
    return std::isfinite(v) && v == std::floor(v) && v >= lo && v <= hi;
  };
  RcbTree t;
  t.root_ = root;
  const auto last = static_cast<double>(n - 1);
  for (std::size_t k = 0; k < n; ++k) {
    const double* v = &data[k * kNodeDoubles];
    if (!whole(v[0], -1, 2) || !std::isfinite(v[1]) || !whole(v[2], 0, ranks - 1) ||
        !whole(v[3], v[2] + 1, ranks) || !whole(v[4], -1, last) || !whole(v[5], -1, last))
      bad("node " + std::to_string(k) + " is not a node");
    Node nd{static_cast<int>(v[0]),
            v[1],
            static_cast<int>(v[2]),
            static_cast<int>(v[3]),
            static_cast<int>(v[4]),
            static_cast<int>(v[5]),
            {}};
    for (int d = 0; d < 3; ++d) {
      nd.box.lo[d] = v[6 + d];
      nd.box.hi[d] = v[9 + d];
      if (!std::isfinite(nd.box.lo[d]) || !std::isfinite(nd.box.hi[d]) ||
          nd.box.lo[d] > nd.box.hi[d])
        bad("node " + std::to_string(k) + " has no box");
    }
    t.nodes_.push_back(nd);
  }
  // From the root down, as build() splits: every node reached once, an inner node's rank range
  // halved between two children of its own (the lower n/2 ranks low), a leaf one rank.
  std::vector<int> reached(n, 0);
  std::vector<int> todo{0};
  reached[0] = 1;
  const Node& top = t.nodes_[0];
  if (top.r0 != 0 || top.r1 != ranks) bad("does not hold the ranks 0 to " + std::to_string(ranks));
  while (!todo.empty()) {
    const Node& nd = t.nodes_[static_cast<std::size_t>(todo.back())];
    todo.pop_back();
    if (nd.dim < 0) {
      if (nd.r1 != nd.r0 + 1 || nd.lo != -1 || nd.hi != -1) bad("has a leaf of several ranks");
      continue;
    }
    if (nd.lo < 0 || nd.hi < 0 || nd.lo == nd.hi || reached[nd.lo]++ || reached[nd.hi]++)
      bad("has a node that is not one node's child");
    const Node &lo = t.nodes_[nd.lo], &hi = t.nodes_[nd.hi];
    const int half = nd.r0 + (nd.r1 - nd.r0) / 2;
    if (lo.r0 != nd.r0 || lo.r1 != half || hi.r0 != half || hi.r1 != nd.r1)
      bad("does not halve a node's ranks between its children");
    todo.push_back(nd.lo);
    todo.push_back(nd.hi);
  }
  if (std::count(reached.begin(), reached.end(), 1) != static_cast<std::ptrdiff_t>(n))
    bad("has nodes that no path reaches");
  t.collect_boxes();
  return t;
}

void RcbTree::collect_boxes() {
  int n = 0;
  for (const Node& nd : nodes_) n = std::max(n, nd.r1);
  boxes_.assign(n, root_);
  for (const Node& nd : nodes_)
    if (nd.dim < 0) boxes_[nd.r0] = nd.box;
  for (int closed_z = 0; closed_z < 2; ++closed_z) {
    open_[closed_z].clear();
    for (const Node& nd : nodes_) {
      Box b = nd.box;
      for (int d = 0; d < (closed_z ? 2 : 3); ++d) {
        if (b.lo[d] <= root_.lo[d]) b.lo[d] = -1e300;
        if (b.hi[d] >= root_.hi[d]) b.hi[d] = 1e300;
      }
      open_[closed_z].push_back(b);
    }
  }
}

int RcbTree::owner(const Vec3& p) const {
  int k = 0;
  while (nodes_[k].dim >= 0) k = p[nodes_[k].dim] < nodes_[k].cut ? nodes_[k].lo : nodes_[k].hi;
  return nodes_[k].r0;
}

void RcbTree::near(const Vec3& p, double reach2, bool closed_z, std::vector<int>& out) const {
  // Depth first, the low child before the high one (the order the ranks are appended in is the
  // order ghosts are sent in, so it is kept). Each pop pushes at most two nodes and the tree is
  // ceil(log2 P) deep, so the stack never holds more than depth + 1 < 64 entries.
  const std::vector<Box>& open = open_[closed_z ? 1 : 0];
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const int k = stack[--top];
    if (distance2(open[k], p) > reach2) continue;
    const Node& nd = nodes_[k];
    if (nd.dim < 0) {
      if (std::find(out.begin(), out.end(), nd.r0) == out.end()) out.push_back(nd.r0);
      continue;
    }
    stack[top++] = nd.hi;
    stack[top++] = nd.lo;
  }
}

void RcbTree::ranks_near(const Vec3& p, double reach, double period_z,
                         std::vector<int>& out) const {
  const bool periodic = period_z > 0;
  near(p, reach * reach, periodic, out);
  if (periodic) {  // images across the periodic ends
    near(p + Vec3{0, 0, period_z}, reach * reach, true, out);
    near(p - Vec3{0, 0, period_z}, reach * reach, true, out);
  }
}

}  // namespace tumble::parallel
