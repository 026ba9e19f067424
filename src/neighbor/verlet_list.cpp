#include "neighbor/verlet_list.hpp"

#include <algorithm>

namespace tumble::neighbor {

void VerletList::save_history(const Particles& p, ContactHistory& out) const {
  out.clear();
  const std::size_t n = start.empty() ? 0 : start.size() - 1;
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = start[i]; k < start[i + 1]; ++k)
      out.save(p.id[i], p.id[nbr[k]], spring[k]);
  out.finalize();
}

bool VerletList::needs_rebuild(const Particles& p) const {
  if (x_ref_.size() != p.size()) return true;
  const double lim2 = 0.25 * skin_ * skin_;
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i)
    if (norm2(p.x[i] - x_ref_[i]) > lim2) return true;
  return false;
}

void VerletList::rebuild(Particles& p, const ContactHistory* history) {
  ContactHistory own;
  if (!history) {
    save_history(p, own);
    history = &own;
  }
  const std::size_t n = p.size();
  grid_.sort(p.x, perm_, cell_start_);
  p.permute(perm_);

  start.assign(n + 1, 0);
  nbr.clear();
  for (std::size_t i = 0; i < n; ++i) {
    start[i] = static_cast<std::uint32_t>(nbr.size());
    int ci, cj, ck;
    grid_.coords(grid_.cell_of(p.x[i]), ci, cj, ck);
    const Vec3 xi = p.x[i];
    const double ri = p.radius[i] + skin_;
    for (int a = std::max(ci - 1, 0); a <= std::min(ci + 1, grid_.nx() - 1); ++a)
      for (int b = std::max(cj - 1, 0); b <= std::min(cj + 1, grid_.ny() - 1); ++b)
        for (int c = std::max(ck - 1, 0); c <= std::min(ck + 1, grid_.nz() - 1); ++c) {
          const std::uint32_t cell = grid_.index(a, b, c);
          for (std::uint32_t j = std::max<std::uint32_t>(cell_start_[cell], i + 1);
               j < cell_start_[cell + 1]; ++j) {
            const double cut = ri + p.radius[j];
            if (norm2(xi - p.x[j]) < cut * cut) nbr.push_back(j);
          }
        }
  }
  start[n] = static_cast<std::uint32_t>(nbr.size());
  // Partners in increasing index order: deterministic and friendlier to the cache.
  for (std::size_t i = 0; i < n; ++i) std::sort(nbr.begin() + start[i], nbr.begin() + start[i + 1]);

  spring.assign(nbr.size(), Vec3{});
  if (!history->records().empty())
    for (std::size_t i = 0; i < n; ++i)
      for (std::uint32_t k = start[i]; k < start[i + 1]; ++k)
        spring[k] = history->lookup(p.id[i], p.id[nbr[k]]);
  x_ref_ = p.x;
  ++builds;
}

}  // namespace tumble::neighbor
