#pragma once
// The biaxial protocol (theta_z, theta_x) of the CM: rotate about z by theta_z, then about x by
// theta_x; one iteration (period) is F = F_x o F_z. Positions are in the lab frame, where the free
// surface is fixed (y = 0) and the Poincare sections and Lambert views are taken.
//
// Sign convention (docs/cm.md): the z phase is the field of flow_field.hpp, Omega_z = -z_hat.
// The x phase is that field conjugated by the proper rotation Q = R_y(-90 deg), which takes the
// z axis to -x: u_x(p) = Q u_z(Q^T p), so Omega_x = Q Omega_z = +x_hat. In the x phase's own
// frame (streamwise, normal, axial) = (z, y, -x): surface flow runs towards +z and the axial
// drift direction of the MCM is -x. Because the z field is mirror-symmetric in z, this equals
// exchanging x and z, so F_x = S F_z S with S the mirror x <-> z and F = (S F_z)^2 (the A and B
// island groups of Yu 2022 Sec. II C are mirror images half an iteration apart). The other
// choice, Omega_x = -x_hat, gives the mirror image z -> -z of every result.
#include "cm/exact_map.hpp"

namespace tumble::cm {

enum class Axis { Z, X };
enum class FlowModel { Exact, Integrated, Pwi };
const char* to_string(FlowModel m);  // "exact", "integrated", "pwi" (the --model names)

struct Protocol {
  double theta_z = 0, theta_x = 0;  // radians; a rotation by theta lasts t = theta
  double eps = 0.15;                // flowing-layer depth (App. A)
  FlowModel model = FlowModel::Exact;
  static Protocol degrees(double theta_z_deg, double theta_x_deg, double eps = 0.15,
                          FlowModel model = FlowModel::Exact);
  double theta(Axis a) const { return a == Axis::Z ? theta_z : theta_x; }
  // Layer depth of the model: the PWI has none (shell charts and layer tests use this).
  double layer_eps() const { return model == FlowModel::Pwi ? 0.0 : eps; }
};

// Lab coordinates <-> the phase's own frame (streamwise, normal, axial).
inline Vec3 to_frame(Axis a, const Vec3& lab) {
  return a == Axis::Z ? lab : Vec3(lab.z(), lab.y(), -lab.x());
}
inline Vec3 to_lab(Axis a, const Vec3& f) { return a == Axis::Z ? f : Vec3(-f.z(), f.y(), f.x()); }

// Flow of one phase for time t in [0, theta] (lab in, lab out).
Vec3 flow_phase(const Protocol& pr, Axis a, const Vec3& p, double t,
                Crossings* crossings = nullptr);
// The whole phase (t = theta of that axis), and its inverse. The inverse uses the time-reversal
// symmetry of each single-axis field: u(M p) = -M u(p) with M the mirror of the streamwise
// coordinate, hence F_t^-1 = M F_t M.
Vec3 phase_map(const Protocol& pr, Axis a, const Vec3& p, Crossings* crossings = nullptr);
Vec3 inverse_phase_map(const Protocol& pr, Axis a, const Vec3& p);

// One iteration F = F_x o F_z, its inverse, and F^n (n >= 0).
Vec3 period_map(const Protocol& pr, const Vec3& p, Crossings* crossings = nullptr);
Vec3 inverse_period_map(const Protocol& pr, const Vec3& p);
Vec3 iterate(const Protocol& pr, const Vec3& p, int n);

}  // namespace tumble::cm
