#pragma once
// The one list of per-particle fields. Adding a field is one line here: Particles
// (base/particles.hpp) declares a column for every entry, and everything that handles whole
// particles is generated from the list - resize and permute, the rows of doubles that carry
// particles between ranks (parallel/particle_pack.hpp) and the checkpoint's datasets
// (io/checkpoint.cpp). Snapshots are an output format, not state: io/snapshot.cpp picks its
// columns by hand.
//
// X(type, name, flags): `type` is Vec3, double, std::int32_t or std::int64_t (the types
// parallel/particle_pack.hpp and io/checkpoint.cpp know how to carry and store); `flags` says
// where the field goes (field::k* below). The order of the list is the order of the checkpoint's
// datasets and of the columns of a row: keep existing entries in place (checkpoint files are
// compared bitwise) and append new ones.
#include <cstdint>

#include "base/vec3.hpp"

namespace tumble::field {

// Travels with its particle: migration to another rank, ghost copies at a neighbour rebuild and
// the gathers of the whole bed (analyses, snapshots). A field without it arrives value-initialised.
constexpr unsigned kMigrate = 1u << 0;
// Also sent to the ghosts every step: only what the force loops read of a neighbour and what
// changes every step (the integrator moves it).
constexpr unsigned kGhostRefresh = 1u << 1;
// Written to checkpoints as dataset "particles/<name>" (one row per particle) and read back on
// restart. Everything a bitwise restart needs must have it.
constexpr unsigned kCheckpoint = 1u << 2;

// A checkpoint written before the field existed still restarts: the field then starts
// value-initialised (its zero must be what every particle of such a run had).
constexpr unsigned kOptionalOnRead = 1u << 3;

// Only a run with the rigid bulk (fidelity.bulk = "rigid") keeps the column: a dynamic run's
// Particles leaves it empty (Particles::rigid_columns), which saves its memory (52 B per particle
// for the three of today). Rows between ranks and checkpoints then carry zeros for it, so a
// dynamic run's files are as before and a rigid run can restart from them.
constexpr unsigned kRigidOnly = 1u << 4;

constexpr unsigned kAny = 0;  // as a mask (base/particles.hpp): every field

constexpr unsigned kState = kMigrate | kCheckpoint;   // the usual per-particle state
constexpr unsigned kMotion = kState | kGhostRefresh;  // ... that neighbours read every step

}  // namespace tumble::field

// clang-format off
#define TUMBLE_PARTICLE_FIELDS(X)                                                               \
  X(Vec3, x, field::kMotion)                /* position (lab frame) */                          \
  X(Vec3, v, field::kMotion)                /* velocity */                                      \
  X(Vec3, w, field::kMotion)                /* angular velocity */                              \
  X(Vec3, f, field::kState)                 /* force accumulator (a restart reuses it) */       \
  X(Vec3, t, field::kState)                 /* torque accumulator */                            \
  X(Vec3, wall_spring, field::kState)       /* spring of its (one) wall contact, else zero */   \
  X(double, radius, field::kState)                                                              \
  X(double, inv_mass, field::kState)                                                            \
  X(double, inv_inertia, field::kState)     /* 1 / (2/5 m r^2) */                               \
  X(std::int32_t, species, field::kState)                                                       \
  X(std::int64_t, id, field::kState)        /* global id, stable for the whole run (< 2^53) */ \
  X(std::int32_t, bulk_state,               /* fidelity.bulk = "rigid" (engine/rigid_bulk.cpp): */ \
    field::kState | field::kOptionalOnRead | field::kRigidOnly)                                  \
                                            /* 0 moving, > 0 steps calm, -1 frozen, -2 thawing */ \
  X(Vec3, bulk_anchor,                      /* rigid bulk: tumbler-frame position where its */   \
    field::kState | field::kOptionalOnRead | field::kRigidOnly)                                  \
                                            /* stay began (calm while it moves less from it) */  \
  X(Vec3, bulk_gravity,                     /* rigid bulk, frozen: gravity's direction in the */ \
    field::kState | field::kOptionalOnRead | field::kRigidOnly)                                  \
                                            /* tumbler's frame when it froze */
// clang-format on

// A build may append fields of its own: define TUMBLE_EXTRA_PARTICLE_FIELDS_HEADER as a header
// that defines TUMBLE_EXTRA_PARTICLE_FIELDS(X) in the same form. The test of this mechanism uses
// it (tests/parallel/dummy_field.hpp); every source of such a build must see the same definition
// (base/particles.hpp puts Particles in its own namespace there, so a mix does not link).
#ifdef TUMBLE_EXTRA_PARTICLE_FIELDS_HEADER
#include TUMBLE_EXTRA_PARTICLE_FIELDS_HEADER
#define TUMBLE_ALL_PARTICLE_FIELDS(X) TUMBLE_PARTICLE_FIELDS(X) TUMBLE_EXTRA_PARTICLE_FIELDS(X)
#else
#define TUMBLE_ALL_PARTICLE_FIELDS(X) TUMBLE_PARTICLE_FIELDS(X)
#endif
