#pragma once
// The extra per-particle field of the test build (tests/parallel/CMakeLists.txt names this file in
// TUMBLE_EXTRA_PARTICLE_FIELDS_HEADER): one line, as a real field is one line in
// base/particle_fields.hpp. It migrates and is checkpointed (dataset "particles/dummy").
#define TUMBLE_EXTRA_PARTICLE_FIELDS(X) X(double, dummy, field::kState) /* test only */
