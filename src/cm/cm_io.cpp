#include "cm/cm_io.hpp"

#include <Eigen/LU>
#include <cmath>

#include "base/error.hpp"
#include "cm/file_protocol.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::cm {
namespace {

using io::H5File;

template <int N>
std::vector<double> flat(const std::vector<Eigen::Matrix<double, N, 1>>& v) {
  std::vector<double> out;
  out.reserve(v.size() * N);
  for (const auto& x : v)
    for (int k = 0; k < N; ++k) out.push_back(x[k]);
  return out;
}

template <int N>
std::vector<Eigen::Matrix<double, N, 1>> unflat(const std::vector<double>& d) {
  std::vector<Eigen::Matrix<double, N, 1>> out(d.size() / N);
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int k = 0; k < N; ++k) out[i][k] = d[i * N + k];
  return out;
}

template <int N>
void write_vecs(H5File& f, const std::string& name,
                const std::vector<Eigen::Matrix<double, N, 1>>& v) {
  f.write(name, flat<N>(v), {static_cast<hsize_t>(v.size()), static_cast<hsize_t>(N)});
}

// A table read back from an orbits file must have the rows the others say, or an index past its
// end would be read: a damaged or hand-edited file is refused with the dataset named.
void require_rows(const std::string& path, const std::string& name, std::size_t rows,
                  std::size_t want) {
  if (rows != want)
    throw CorruptInputError("'" + path + "': " + name + " has " + std::to_string(rows) +
                            " rows where the other tables of its group say " +
                            std::to_string(want));
}

void write_chart_attrs(H5File& f, const ShellChart& chart) {
  f.set_attr("/", "r", chart.r());
  f.set_attr("/", "chart_rim", chart.rim());
  f.set_attr("/", "chart_outer", chart.outer());
}

}  // namespace

void write_poincare(const std::string& path, const Protocol& pr, const PoincareOptions& opt,
                    const std::vector<PoincareSet>& sets) {
  io::AtomicH5Writer w(path);
  H5File& f = w.file();
  write_file_protocol(f, pr, "poincare");
  write_chart_attrs(f, ShellChart(opt.r, pr.layer_eps()));
  f.set_attr("/", "periods", static_cast<std::int64_t>(opt.periods));
  f.set_attr("/", "seeding", std::string(opt.seeding == Seeding::Shell ? "shell" : "interface"));
  for (const auto& s : sets) {
    const std::string g = "/" + s.name;
    f.create_group(g);
    f.set_attr(g, "seeded_at",
               std::string(s.name == "first" ? "start of the first rotation"
                                             : "start of the second rotation"));
    write_vecs<3>(f, g + "/seeds", s.seeds);
    write_vecs<2>(f, g + "/bulk", s.bulk);
    f.write(g + "/bulk_seed", s.bulk_seed);
    f.write(g + "/bulk_period", s.bulk_period);
    write_vecs<3>(f, g + "/layer", s.layer);
    write_vecs<2>(f, g + "/layer_chart", s.layer_chart);
    f.write(g + "/layer_seed", s.layer_seed);
    f.write(g + "/layer_period", s.layer_period);
  }
  w.commit();
}

void write_orbits(const std::string& path, const Protocol& pr, double r,
                  const std::vector<PeriodicPoint>& points, const std::vector<Island>& islands) {
  io::AtomicH5Writer w(path);
  H5File& f = w.file();
  write_file_protocol(f, pr, "orbits");
  write_chart_attrs(f, ShellChart(r, pr.layer_eps()));

  std::vector<Vec2> chart, unstable, stable;
  std::vector<Vec3> xyz;
  std::vector<std::int32_t> period, type, orbit;
  std::vector<double> trace, rotation, lambda, jac;
  for (const auto& p : points) {
    chart.push_back(p.v);
    xyz.push_back(p.p);
    period.push_back(p.period);
    type.push_back(static_cast<std::int32_t>(p.type));
    orbit.push_back(p.orbit);
    trace.push_back(p.trace);
    rotation.push_back(p.type == Stability::Elliptic ? p.rotation : NAN);
    lambda.push_back(p.type == Stability::Hyperbolic ? p.lambda : NAN);
    unstable.push_back(p.unstable);
    stable.push_back(p.stable);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) jac.push_back(p.jacobian(i, j));
  }
  f.create_group("/points");
  f.set_attr("/points", "type_codes", std::string("0 elliptic, 1 hyperbolic, 2 parabolic"));
  write_vecs<2>(f, "/points/chart", chart);
  write_vecs<3>(f, "/points/xyz", xyz);
  f.write("/points/period", period);
  f.write("/points/type", type);
  f.write("/points/orbit", orbit);
  f.write("/points/trace", trace);
  f.write("/points/rotation", rotation);
  f.write("/points/lambda", lambda);
  f.write("/points/jacobian", jac, {static_cast<hsize_t>(points.size()), 2, 2});
  write_vecs<2>(f, "/points/unstable", unstable);
  write_vecs<2>(f, "/points/stable", stable);

  std::vector<Vec2> vertices, center, launch;
  std::vector<std::int64_t> offsets{0};
  std::vector<double> rr, area;
  std::vector<std::int32_t> iperiod, iorbit, ipoint, iparent;
  for (const auto& isl : islands) {
    vertices.insert(vertices.end(), isl.boundary.vertices.begin(), isl.boundary.vertices.end());
    offsets.push_back(static_cast<std::int64_t>(vertices.size()));
    center.push_back(isl.center);
    launch.push_back(isl.launch);
    rr.push_back(isl.r);
    area.push_back(isl.boundary.area());
    iperiod.push_back(isl.period);
    iorbit.push_back(isl.orbit);
    ipoint.push_back(isl.point);
    iparent.push_back(isl.parent_orbit);
  }
  f.create_group("/islands");
  f.set_attr(
      "/islands", "layout",
      std::string("island k has vertices[offsets[k]:offsets[k+1]] (chart coordinates of "
                  "its shell r[k]); point = row in /points (the r = /@r point it continues; -1 "
                  "for a secondary chain's island); parent_orbit = orbit of the island a "
                  "secondary chain surrounds, -1 for a primary island"));
  write_vecs<2>(f, "/islands/vertices", vertices);
  f.write("/islands/offsets", offsets);
  write_vecs<2>(f, "/islands/center", center);
  write_vecs<2>(f, "/islands/launch", launch);
  f.write("/islands/r", rr);
  f.write("/islands/area", area);
  f.write("/islands/period", iperiod);
  f.write("/islands/orbit", iorbit);
  f.write("/islands/point", ipoint);
  f.write("/islands/parent_orbit", iparent);
  w.commit();
}

std::vector<PeriodicPoint> read_periodic_points(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  const auto chart = unflat<2>(f.read_double("/points/chart"));
  const auto xyz = unflat<3>(f.read_double("/points/xyz"));
  const auto period = f.read_int32("/points/period");
  const auto type = f.read_int32("/points/type");
  const auto orbit = f.read_int32("/points/orbit");
  const auto trace = f.read_double("/points/trace");
  const auto rotation = f.read_double("/points/rotation");
  const auto lambda = f.read_double("/points/lambda");
  const auto jac = f.read_double("/points/jacobian");
  const auto unstable = unflat<2>(f.read_double("/points/unstable"));
  const auto stable = unflat<2>(f.read_double("/points/stable"));
  const std::size_t n = chart.size();
  require_rows(path, "/points/xyz", xyz.size(), n);
  require_rows(path, "/points/period", period.size(), n);
  require_rows(path, "/points/type", type.size(), n);
  require_rows(path, "/points/orbit", orbit.size(), n);
  require_rows(path, "/points/trace", trace.size(), n);
  require_rows(path, "/points/rotation", rotation.size(), n);
  require_rows(path, "/points/lambda", lambda.size(), n);
  require_rows(path, "/points/jacobian", jac.size() / 4, n);
  require_rows(path, "/points/unstable", unstable.size(), n);
  require_rows(path, "/points/stable", stable.size(), n);
  for (std::size_t i = 0; i < n; ++i)
    if (type[i] < 0 || type[i] > 2 || period[i] < 1)
      throw CorruptInputError("'" + path + "': periodic point " + std::to_string(i) + " has type " +
                              std::to_string(type[i]) + " and period " + std::to_string(period[i]) +
                              " (types are 0, 1, 2; periods >= 1)");
  std::vector<PeriodicPoint> out(n);
  for (std::size_t i = 0; i < out.size(); ++i) {
    auto& p = out[i];
    p.v = chart[i];
    p.p = xyz[i];
    p.period = period[i];
    p.type = static_cast<Stability>(type[i]);
    p.orbit = orbit[i];
    p.trace = trace[i];
    p.rotation = rotation[i];
    p.lambda = lambda[i];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) p.jacobian(a, b) = jac[i * 4 + a * 2 + b];
    p.det = p.jacobian.determinant();
    p.unstable = unstable[i];
    p.stable = stable[i];
  }
  return out;
}

std::vector<Island> read_islands(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  const auto vertices = unflat<2>(f.read_double("/islands/vertices"));
  const auto offsets = f.read_int64("/islands/offsets");
  const auto center = unflat<2>(f.read_double("/islands/center"));
  const auto launch = unflat<2>(f.read_double("/islands/launch"));
  const auto r = f.read_double("/islands/r");
  const auto period = f.read_int32("/islands/period");
  const auto orbit = f.read_int32("/islands/orbit");
  const auto point = f.read_int32("/islands/point");
  const std::size_t n = r.size();
  // Files written before secondary chains were searched hold primary islands only.
  const auto parent = f.exists("/islands/parent_orbit") ? f.read_int32("/islands/parent_orbit")
                                                        : std::vector<std::int32_t>(n, -1);
  require_rows(path, "/islands/parent_orbit", parent.size(), n);
  require_rows(path, "/islands/offsets", offsets.size(), n + 1);
  require_rows(path, "/islands/center", center.size(), n);
  require_rows(path, "/islands/launch", launch.size(), n);
  require_rows(path, "/islands/period", period.size(), n);
  require_rows(path, "/islands/orbit", orbit.size(), n);
  require_rows(path, "/islands/point", point.size(), n);
  for (std::size_t k = 0; k <= n; ++k) {
    const std::int64_t lo = k ? offsets[k - 1] : 0;
    if (offsets[k] < lo || offsets[k] > static_cast<std::int64_t>(vertices.size()))
      throw CorruptInputError("'" + path + "': /islands/offsets[" + std::to_string(k) +
                              "] = " + std::to_string(offsets[k]) +
                              " is not in order within the vertices (0 .. " +
                              std::to_string(vertices.size()) + ")");
  }
  // A NaN vertex or centre made no point inside its island, silently (every test against it is
  // false); a radius outside the ball or a period < 1 is no island Tumble writes.
  auto finite = [](const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); };
  for (std::size_t k = 0; k < vertices.size(); ++k)
    if (!finite(vertices[k]))
      throw CorruptInputError("'" + path + "': /islands/vertices[" + std::to_string(k) +
                              "] is not finite");
  for (std::size_t k = 0; k < n; ++k) {
    std::string bad;
    if (!finite(center[k]))
      bad = "its centre is not finite";
    else if (!finite(launch[k]))
      bad = "its launch point is not finite";
    else if (!(r[k] > 0 && r[k] <= 1))
      bad = "r = " + std::to_string(r[k]) + " is not in (0, 1]";
    else if (period[k] < 1)
      bad = "period " + std::to_string(period[k]) + " is not >= 1";
    if (!bad.empty())
      throw CorruptInputError("'" + path + "': island " + std::to_string(k) + ": " + bad);
  }
  std::vector<Island> out(n);
  for (std::size_t k = 0; k < out.size(); ++k) {
    auto& isl = out[k];
    isl.boundary.vertices.assign(vertices.begin() + offsets[k], vertices.begin() + offsets[k + 1]);
    isl.center = center[k];
    isl.launch = launch[k];
    isl.extent = (launch[k] - center[k]).norm();
    isl.r = r[k];
    isl.period = period[k];
    isl.orbit = orbit[k];
    isl.point = point[k];
    isl.parent_orbit = parent[k];
  }
  return out;
}

std::vector<Island> islands_on_shell(const std::vector<Island>& all, double r) {
  std::vector<Island> out;
  for (const auto& isl : all)
    if (std::abs(isl.r - r) < 1e-9) out.push_back(isl);
  return out;
}

ManifoldsWriter::ManifoldsWriter(const std::string& path, const Protocol& pr, double r,
                                 const std::vector<PeriodicPoint>& points)
    : writer_(path) {
  H5File& f = writer_.file();
  write_file_protocol(f, pr, "manifolds");
  write_chart_attrs(f, ShellChart(r, pr.layer_eps()));
  std::vector<Vec2> pts;
  for (const auto& p : points) {
    pts.push_back(p.v);
    periods_.push_back(p.period);
  }
  write_vecs<2>(f, "/points/chart", pts);
  f.create_group("/manifolds");  // (there even when no point is hyperbolic: the layout is kept)
}

void ManifoldsWriter::add(const Manifold& m) {
  H5File& f = writer_.file();
  const std::string g = "/manifolds/" + std::to_string(next_++);
  f.create_group(g);
  f.set_attr(g, "point", static_cast<std::int64_t>(m.point));
  f.set_attr(g, "kind", std::string(m.unstable ? "unstable" : "stable"));
  f.set_attr(g, "period", static_cast<std::int64_t>(periods_.at(m.point)));
  f.set_attr(g, "iterations_done", static_cast<std::int64_t>(m.iterations_done));
  f.set_attr(g, "truncated", static_cast<std::int64_t>(m.truncated));
  write_vecs<3>(f, g + "/xyz", m.xyz);
  write_vecs<2>(f, g + "/chart", m.chart);
  std::vector<std::int32_t> it(m.iteration.begin(), m.iteration.end());
  f.write(g + "/iteration", it);
  f.write(g + "/param", m.param);
}

void ManifoldsWriter::commit() { writer_.commit(); }

void write_manifolds(const std::string& path, const Protocol& pr, double r,
                     const std::vector<PeriodicPoint>& points, const std::vector<Manifold>& ms) {
  ManifoldsWriter w(path, pr, r, points);
  for (const auto& m : ms) w.add(m);
  w.commit();
}

void write_mcm(const std::string& path, const Protocol& pr, const McmOptions& opt,
               const DriftGrid& grid, const McmResult& res, const McmSummary& s) {
  io::AtomicH5Writer w(path);
  H5File& f = w.file();
  write_file_protocol(f, pr, "mcm");
  const ShellChart chart(opt.r, pr.layer_eps());
  write_chart_attrs(f, chart);
  f.set_attr("/", "c", opt.c);
  f.set_attr("/", "drift", static_cast<std::int64_t>(opt.drift));
  f.set_attr("/", "drift_source", grid.source);
  f.set_attr("/", "dt", opt.dt);
  f.set_attr("/", "dt_ref", opt.dt_ref);
  f.set_attr("/", "seed", static_cast<std::int64_t>(opt.seed));
  f.set_attr("/", "tracers", static_cast<std::int64_t>(opt.tracers));
  f.set_attr("/", "snapshot_iteration", static_cast<std::int64_t>(opt.snapshot));
  // NaN ("none": neither drift nor diffusion) and +inf (drift without diffusion) are stored as
  // such, IEEE values HDF5 keeps; the text says which, for readers that print it.
  f.set_attr("/", "peclet", s.peclet);
  f.set_attr("/", "peclet_text", peclet_text(s.peclet));
  f.set_attr("/", "island_length", s.island_length);
  f.set_attr("/", "island_bulk_area_fraction", s.bulk_area_fraction);
  f.set_attr("/", "island_area_fraction", s.area_fraction);
  f.set_attr("/", "bulk_inside_fraction", s.bulk_inside_fraction);
  f.set_attr("/", "inside_fraction", s.inside_fraction);
  f.set_attr("/", "cumulative_bulk_inside_fraction", s.cumulative_bulk_inside_fraction);
  f.set_attr("/", "initial_bulk_inside_fraction", s.initial_bulk_inside_fraction);
  const auto chart_of = [&chart](const std::vector<Vec3>& ps) {
    std::vector<Vec2> out;
    out.reserve(ps.size());
    for (const auto& p : ps) out.push_back(chart.to_chart(p));
    return out;
  };
  write_vecs<3>(f, "/initial/xyz", res.initial);
  write_vecs<2>(f, "/initial/chart", chart_of(res.initial));
  write_vecs<3>(f, "/snapshot/xyz", res.snapshot);
  write_vecs<2>(f, "/snapshot/chart", chart_of(res.snapshot));
  write_vecs<3>(f, "/cumulative/xyz", res.cumulative);
  write_vecs<2>(f, "/cumulative/chart", chart_of(res.cumulative));
  std::vector<std::int32_t> it(res.cumulative_iteration.begin(), res.cumulative_iteration.end());
  f.write("/cumulative/iteration", it);
  w.commit();
}

}  // namespace tumble::cm
