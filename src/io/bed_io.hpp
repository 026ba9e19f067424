#pragma once
// Settled beds: saved once per (geometry, particles, contact, seed) and reused as the start of any
// number of runs. HDF5 (Tumble's own) or the text format of the LIGGGHTS reference bed (id type
// diameter x y z, gravity along -z, which is rotated to Tumble's y-up lab frame).
#include <string>

#include "base/particles.hpp"
#include "scene/scene.hpp"

namespace tumble::io {

// `settled_on_ranks`: the ranks the bed settled on, kept with it (attribute settled_on_ranks). A
// bed settles to other positions in round-off on another rank count (the order of the force sums
// differs), and the cache's name does not hold the count: the first run to settle a bed settles
// it for every later run (docs/guarantees.md, "Reproducible").
void write_bed(const std::string& path, const Particles& p, const Scene& scene,
               int settled_on_ranks);
// The ranks a bed of Tumble's says it settled on; 0 where it does not say (written before the
// count was kept, or made elsewhere). Throws as read_bed on a file it cannot open.
int bed_settled_on_ranks(const std::string& path);
// Where a bed comes from: a file the user named (fill.bed_file; a bad one is an InputError, exit 2)
// or Tumble's own cache (a bad one is damaged: CorruptInputError, exit 3).
enum class BedSource { User, Cache };
// Reads a bed and refuses it, naming the line (text) or row (HDF5), unless: it holds particles;
// its arrays have one length; ids are unique (HDF5: 0..N-1; text: numbering from 0 or 1, replaced
// by the line order); species are 0 and 1 (text types 1 and 2); positions and radii are finite;
// each radius is its species' diameter; every particle is inside the tumbler; and no two
// particles overlap by more than half the smaller diameter. Sets masses from the scene.
Particles read_bed(const std::string& path, const Scene& scene, BedSource source = BedSource::User);
// Version of the code that fills and settles a bed (scene/fill*.cpp, the settling loop in
// run/realization.cpp): bump it when a change there changes the bed a scene settles to, so that
// cached beds of the old code are not reused silently. Version 1 adds nothing to the key (the
// caches written before the version existed keep their names).
inline constexpr int kBedCodeVersion = 1;
// Canonical key of everything that determines a settled bed; its hash names the cached file.
std::string bed_key(const Scene& scene, int code_version = kBedCodeVersion);
std::string bed_cache_path(const Scene& scene);

}  // namespace tumble::io
