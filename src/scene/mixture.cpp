#include "scene/mixture.hpp"

#include <cmath>
#include <sstream>

namespace tumble {

const char* Mixture::kind_name() const {
  switch (kind) {
    case MixtureKind::size:
      return "size-bidisperse";
    case MixtureKind::density:
      return "density-bidisperse";
    case MixtureKind::mono:
      break;
  }
  return "one kind of particle";
}

std::string Mixture::describe() const {
  std::ostringstream os;
  os.precision(3);
  os << kind_name() << ": ";
  for (int k = 0; k < 2; ++k) {
    os << (k ? "; " : "") << name[k] << " (species " << k << ", " << 100 * fraction[k]
       << " vol %";
    if (k == minority) os << ", minority";
    if (k == mapped) os << ", mapped";
    os << ")";
  }
  return os.str();
}

Mixture mixture_of(const Scene& s) {
  Mixture m;
  m.fraction[0] = 1 - s.large_fraction;
  m.fraction[1] = s.large_fraction;
  m.diameter[0] = s.d_small;
  m.diameter[1] = s.d_large;
  m.minority = m.fraction[0] < m.fraction[1] ? 0 : 1;
  if (std::abs(s.d_large - s.d_small) > 1e-9 * s.d_large) {
    m.kind = MixtureKind::size;
    m.name[0] = "small";
    m.name[1] = "large";
    m.mapped = 1;
  } else if (s.density_ratio != 1) {
    m.kind = MixtureKind::density;
    const int light = s.density_ratio > 1 ? 0 : 1;
    m.name[light] = "light";
    m.name[1 - light] = "heavy";
    m.mapped = light;
  } else {
    m.name[0] = "species 0";
    m.name[1] = "species 1";
    m.mapped = 1;
  }
  return m;
}

}  // namespace tumble
