#include "io/snapshot.hpp"

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <numeric>

#include "base/version.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::io {

void write_provenance(H5File& f, const Scene& scene) {
  f.set_attr("/", "tumble_version", std::string(kVersion));
  f.set_attr("/", "git_hash", std::string(kGitHash));
  f.set_attr("/", "scene", scene_to_text(scene));
  f.set_attr("/", "seed", static_cast<std::int64_t>(scene.seed));
  char date[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  f.set_attr("/", "written_utc", std::string(date));
}

void write_snapshot(const std::string& path, const Simulation& sim, const Scene& scene) {
  // Rows sorted by id. Domain-decomposed: each rank first collects one contiguous block of ids,
  // then all write their blocks into one file collectively.
  const parallel::Domain* dom = sim.domain();
  Particles block;
  if (dom) block = dom->id_block(sim.particles(), sim.local_count(), sim.global_count());
  const Particles& p = dom ? block : sim.particles();
  const std::size_t n = p.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  if (!dom)
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  const Mat3 q = sim.protocol().orientation(sim.time());
  std::vector<std::int64_t> id(n);
  std::vector<std::int32_t> species(n);
  std::vector<double> radius(n), x(3 * n), xt(3 * n), v(3 * n), w(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = order[k];
    id[k] = p.id[i];
    species[k] = p.species[i];
    radius[k] = p.radius[i];
    const Vec3 body = q.tmul(p.x[i]);  // tumbler frame
    for (int d = 0; d < 3; ++d) {
      x[3 * k + d] = p.x[i][d];
      xt[3 * k + d] = body[d];
      v[3 * k + d] = p.v[i][d];
      w[3 * k + d] = p.w[i][d];
    }
  }
  AtomicH5Writer out(path, dom ? dom->comm() : MPI_COMM_NULL);
  H5File& f = out.file();
  f.write_rows("id", id);
  f.write_rows("species", species);
  f.write_rows("radius", radius);
  f.write_rows("x", x, 3);
  f.write_rows("x_tumbler", xt, 3);
  f.write_rows("v", v, 3);
  f.write_rows("w", w, 3);
  std::vector<double> orient(9);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) orient[3 * a + b] = q.a[a][b];
  f.write("orientation", orient, {3, 3});
  f.set_attr("/", "time", sim.time());
  f.set_attr("/", "step", static_cast<std::int64_t>(sim.step_count()));
  f.set_attr("/", "iteration", sim.protocol().iteration(sim.time()));
  write_provenance(f, scene);
  out.commit();
}

void write_xdmf(const std::string& dir, const std::vector<SnapshotEntry>& entries) {
  const std::string path = dir + "/snapshots.xdmf";
  const std::string tmp = path + ".tmp";
  {
    std::ofstream o(tmp);
    o << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
      << "<Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto& e : entries) {
      const std::size_t n = e.count;
      o << "<Grid Name=\"t\" GridType=\"Uniform\">\n<Time Value=\"" << e.time << "\"/>\n"
        << "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\"/>\n"
        << "<Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"" << n
        << " 3\" NumberType=\"Float\" "
        << "Precision=\"8\" Format=\"HDF\">" << e.file << ":/x</DataItem></Geometry>\n";
      auto attr = [&](const char* name, const char* type, const char* dims, const char* nt,
                      int prec) {
        o << "<Attribute Name=\"" << name << "\" AttributeType=\"" << type << "\" Center=\"Node\">"
          << "<DataItem Dimensions=\"" << n << dims << "\" NumberType=\"" << nt << "\" Precision=\""
          << prec << "\" Format=\"HDF\">" << e.file << ":/" << name << "</DataItem></Attribute>\n";
      };
      attr("id", "Scalar", "", "Int", 8);
      attr("species", "Scalar", "", "Int", 4);
      attr("radius", "Scalar", "", "Float", 8);
      attr("v", "Vector", " 3", "Float", 8);
      attr("w", "Vector", " 3", "Float", 8);
      attr("x_tumbler", "Vector", " 3", "Float", 8);
      o << "</Grid>\n";
    }
    o << "</Grid>\n</Domain>\n</Xdmf>\n";
    o.close();
    // An index cut short (a full disk) would show ParaView part of the run: the previous index
    // stays, and the next snapshot writes it again. (Rank 0 alone writes it: no throw, which
    // would leave the other ranks of the run waiting.)
    if (o.fail()) {
      std::remove(tmp.c_str());
      return;
    }
  }
  std::rename(tmp.c_str(), path.c_str());
}

}  // namespace tumble::io
