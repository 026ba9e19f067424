#pragma once
// Settled beds: saved once per (geometry, particles, contact, seed) and reused as the start of any
// number of runs. HDF5 (Tumble's own) or the text format of the LIGGGHTS reference bed (id type
// diameter x y z, gravity along -z, which is rotated to Tumble's y-up lab frame).
#include <string>

#include "base/particles.hpp"
#include "scene/scene.hpp"

namespace tumble::io {

void write_bed(const std::string& path, const Particles& p, const Scene& scene);
// Reads a bed and checks it against the scene (diameters, tumbler radius); sets masses from the
// scene.
Particles read_bed(const std::string& path, const Scene& scene);
// Version of the code that fills and settles a bed (scene/fill*.cpp, the settling loop in
// run/realization.cpp): bump it when a change there changes the bed a scene settles to, so that
// cached beds of the old code are not reused silently. Version 1 adds nothing to the key (the
// caches written before the version existed keep their names).
inline constexpr int kBedCodeVersion = 1;
// Canonical key of everything that determines a settled bed; its hash names the cached file.
std::string bed_key(const Scene& scene, int code_version = kBedCodeVersion);
std::string bed_cache_path(const Scene& scene);

}  // namespace tumble::io
