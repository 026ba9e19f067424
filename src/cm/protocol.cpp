#include "cm/protocol.hpp"

#include "cm/integrator.hpp"
#include "cm/pwi.hpp"

namespace tumble::cm {

const char* to_string(FlowModel m) {
  switch (m) {
    case FlowModel::Exact:
      return "exact";
    case FlowModel::Integrated:
      return "integrated";
    case FlowModel::Pwi:
      return "pwi";
  }
  return "?";
}

Protocol Protocol::degrees(double theta_z_deg, double theta_x_deg, double eps, FlowModel model) {
  return {theta_z_deg * kPi / 180.0, theta_x_deg * kPi / 180.0, eps, model};
}

Vec3 flow_phase(const Protocol& pr, Axis a, const Vec3& p, double t, Crossings* crossings) {
  const Vec3 f = to_frame(a, p);
  Vec3 g;
  switch (pr.model) {
    case FlowModel::Exact:
      g = flow_z_exact(f, t, pr.eps, crossings);
      break;
    case FlowModel::Integrated:
      g = flow_z_integrated(f, t, pr.eps);
      break;
    case FlowModel::Pwi:
      g = flow_z_pwi(f, t);
      break;
  }
  return to_lab(a, g);
}

Vec3 phase_map(const Protocol& pr, Axis a, const Vec3& p, Crossings* crossings) {
  return flow_phase(pr, a, p, pr.theta(a), crossings);
}

Vec3 inverse_phase_map(const Protocol& pr, Axis a, const Vec3& p) {
  const auto mirror = [a](Vec3 q) {
    Vec3 f = to_frame(a, q);
    f.x() = -f.x();
    return to_lab(a, f);
  };
  return mirror(phase_map(pr, a, mirror(p)));
}

Vec3 period_map(const Protocol& pr, const Vec3& p, Crossings* crossings) {
  return phase_map(pr, Axis::X, phase_map(pr, Axis::Z, p, crossings), crossings);
}

Vec3 inverse_period_map(const Protocol& pr, const Vec3& p) {
  return inverse_phase_map(pr, Axis::Z, inverse_phase_map(pr, Axis::X, p));
}

Vec3 iterate(const Protocol& pr, const Vec3& p, int n) {
  Vec3 q = p;
  for (int k = 0; k < n; ++k) q = period_map(pr, q);
  return q;
}

}  // namespace tumble::cm
