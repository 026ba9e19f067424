#pragma once
// The integrator's two passes over every owned particle on AVX2 lanes, four particles at a time
// (engine/integrator_avx2.cpp): the first kick and drift with the largest displacement since the
// last neighbour rebuild, and the second kick. Each lane does the scalar loop's operations
// (Simulation::kick_drift_rows, half_kick_rows) in its order, without fused multiply-adds, so the
// two agree bitwise on a generic build (tests/test_lane_kernels.cpp runs whole trajectories both
// ways). Call only where lanes_available() (base/cpu_lanes.hpp) says so.
#include <cstddef>

namespace tumble::engine {

// Particles 0..n-1, n a multiple of 4 (the caller's scalar loop takes the rest); Vec3 arrays as
// doubles (x, y, z per particle).
struct IntegratorInput {
  std::size_t n = 0;
  double* x = nullptr;
  double* v = nullptr;
  double* w = nullptr;
  double* f = nullptr;  // forces and torques: read, then cleared by kick_drift
  double* t = nullptr;
  const double* inv_mass = nullptr;
  const double* inv_inertia = nullptr;
  const double* x_ref = nullptr;  // positions at the last rebuild
  bool has_ref = false;           // x_ref holds them (else kick_drift returns 1e300)
  double kick = 0;                // the velocity update's time: δt, or δt/2 for a half kick
  double dt = 0;                  // the drift's
  double gravity[3] = {0, 0, 0};
};

// v += kick (f/m + g); w += kick t/I (rotation); x += dt v; f = t = 0. Returns the largest
// |x - x_ref|² (0 with no particle; NaN displacements are passed over, as std::max does).
double kick_drift_avx2(const IntegratorInput& in, bool rotation);
// v += kick (f/m + g); w += kick t/I (rotation).
void half_kick_avx2(const IntegratorInput& in, bool rotation);

}  // namespace tumble::engine
