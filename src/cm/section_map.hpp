#pragma once
// The period map read in a shell chart: v -> chart(F^n(chart^-1(v))), an area-preserving map of
// the chart's disc. The section-level tools (periodic points, islands, manifolds) are written
// against this one function.
#include "cm/protocol.hpp"
#include "cm/shell_chart.hpp"

namespace tumble::cm {

class SectionMap {
 public:
  SectionMap(const Protocol& protocol, const ShellChart& chart) : pr_(protocol), chart_(chart) {}
  const Protocol& protocol() const { return pr_; }
  const ShellChart& chart() const { return chart_; }
  Vec2 operator()(const Vec2& v, int n = 1) const {
    return chart_.to_chart(iterate(pr_, chart_.from_chart(v), n));
  }

 private:
  Protocol pr_;
  ShellChart chart_;
};

}  // namespace tumble::cm
