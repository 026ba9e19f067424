#pragma once
// The modified continuum model (MCM, Yu 2022 Sec. III B and App. A): tracers standing for
// surface-segregated large particles, kept on the shell r = 0.95, advected by the CM plus, in the
// flowing layer only, an axial velocity w = v_ax(i, j) + c (+/-1) sigma_ax(i, j) from a drift
// grid (drift_grid.hpp).
//
// Scheme. The bulk part is the exact CM (no drift there). In the layer a tracer keeps its CM
// streamline phase s (x = -a cos s, eta = eps a sin s, Eq. L1) and moves axially; staying on the
// shell fixes a^2 + z^2 = q^2 (shell_chart.hpp), which is how "the advection scheme ensures
// that the tracer points stay on this hemispherical shell". Per step dt:
//   z += v_ax dt + c (+/-1) sigma_ax sqrt(dt_ref dt),   then  a = sqrt(q^2 - z^2).
// With dt = dt_ref this is the paper's update w dt with w = v_ax + c (+/-1) sigma_ax; for a
// larger dt the random kick is scaled so the axial diffusivity stays (c sigma)^2 dt_ref, the D
// of the paper's Peclet number, independent of the integration step.
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "cm/drift_grid.hpp"
#include "cm/progress.hpp"
#include "cm/protocol.hpp"

namespace tumble::cm {

struct McmOptions {
  double r = 0.95;
  int tracers = 2000;  // Yu 2022: 2000 tracers ~ the 1980 large particles at f = 0.15
  double c = 1.0;      // diffusion weight (alpha in Sec. III B)
  bool drift = true;   // false: v_ax = 0 (diffusion only, Fig. 9(b))
  double dt = 0.005;   // layer integration step (units of 1/omega)
  // Paper's time step 1.6e-4 s at omega = 3 rpm (ref. [44]); sets the diffusivity.
  double dt_ref = 1.6e-4 * 3.0 * 2 * 3.14159265358979323846 / 60.0;
  std::uint64_t seed = 1;
  int snapshot = 30;  // iteration N of the snapshot (Fig. 9 middle row)
  int cumulative_from = 30, cumulative_to = 45, cumulative_stride = 3;  // Fig. 9 bottom row
};

struct McmResult {
  std::vector<Vec3> initial, snapshot;
  std::vector<Vec3> cumulative;  // positions at each recorded iteration
  std::vector<int> cumulative_iteration;
};

// One phase of duration t for one tracer in the phase frame; q is the shell's footprint radius
// (ShellChart::footprint()). With drift off and c = 0 this is flow_z_exact.
Vec3 mcm_flow_z(const Vec3& p, double t, double eps, double q, const DriftGrid& grid,
                const McmOptions& opt, std::mt19937_64& rng);

// Progress counts tracer-iterations.
McmResult run_mcm(const Protocol& pr, const DriftGrid& grid, const McmOptions& opt,
                  const Progress& progress = {});

// Iterations recorded in McmResult::cumulative (cumulative_from ... cumulative_to, every
// cumulative_stride-th).
int mcm_cumulative_records(const McmOptions& opt);
// Bytes run_mcm and write_mcm hold at their peak: per tracer 72 B (initial, current and snapshot
// positions), and per tracer and recorded iteration 28 B kept (position, iteration) and 60 B of
// the writer's copies (flat positions, chart points, iterations; counted together, as the
// allocator need not give one back to the system before the next).
double mcm_memory_bytes(const McmOptions& opt);

// Peclet number of Yu 2022 Sec. III B: Pe = L <|v_ax|> / ((c <sigma_ax>)^2 dt_ref). It is +inf
// with drift but no diffusion (c = 0 or sigma = 0), 0 with diffusion but no drift, and NaN
// ("none") with neither: 0/0, no transport to compare.
double mcm_peclet(const DriftGrid& grid, const McmOptions& opt, double island_length);
// Pe as printed and stored in text: "none" (NaN), "infinite" (+inf), else %.4g.
std::string peclet_text(double peclet);

}  // namespace tumble::cm
