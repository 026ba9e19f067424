#pragma once
// The settled bed a realization starts from: the scene's bed file, else the cached bed of the same
// parameters, else a fresh bed filled and settled under gravity by the engine and saved in the
// cache (fill.bed_cache), keyed by everything that determines it (io/bed_io.hpp).
#include <mpi.h>

#include <functional>
#include <iosfwd>
#include <string>

#include "base/particles.hpp"
#include "scene/scene.hpp"

namespace tumble {

// Settled bed for the scene: fill.bed_file, else the cache, else fill + settle + save to cache.
// With `comm` (collective): settled on all its ranks, the whole bed returned on every rank.
// `between_blocks`, if given, is called every 200 settling steps (a campaign's rank 0 keeps
// dispatching cases to other groups while its own group settles a bed).
Particles settled_bed(const Scene& scene, std::ostream* log, bool* reused = nullptr,
                      MPI_Comm comm = MPI_COMM_NULL,
                      const std::function<void()>& between_blocks = nullptr);
// Fills and settles a bed (no caching); the whole bed on every rank of `comm`.
Particles fill_and_settle(const Scene& scene, std::ostream* log, MPI_Comm comm = MPI_COMM_NULL,
                          const std::function<void()>& between_blocks = nullptr);
// Why a bed cannot be filled without gravity (gravity.g = 0: it never settles), naming the keys:
// said by the fill, and by `tumble run`'s input check before any work.
std::string settling_needs_gravity();
// Rank r of `comm` keeps rows [N r / P, N (r+1) / P) of a bed every rank holds in full.
Particles share_of(const Particles& all, MPI_Comm comm);

}  // namespace tumble
