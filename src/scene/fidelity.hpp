#pragma once
// Fidelity tiers (docs/accuracy.md): named presets that trade accuracy for speed by
// changing a sphere scene's stiffness (t_c), δt/t_c, neighbour skin, tumbler-to-particle size
// ratio, rotation speed within the rolling regime, and iterations. A scene file is written at the
// `standard` tier (its own values); the other tiers are derived from it, so the same preset means
// the same trade for every scene:
//
//   tier       t_c          δt/t_c   skin (d_s)  R/d_large     Froude ω²R/g     iterations
//   reference  scene / 2    ≤ 1/100  scene       scene         scene            scene
//   standard   scene        scene    scene       scene         scene            scene
//   fast       scene × 2    1/30     0.2         ≤ 8.75        ≥ 3e-3           ≤ 10
//   preview    scene × 4    1/20     0.3         ≤ 5           ≥ 1e-2           ≤ 3
//
// (Particles grow, size ratio kept, where R/d_large is capped; the rotation speeds up where the
// Froude number is floored: the rolling regime holds to Fr ~ 1e-2; fill.settle_max_time grows with
// t_c in the softer tiers.) The continuum model
// (`tumble cm`) is the cheapest tier of all: it locates the islands but predicts no concentration.
// Keys given with --set (a campaign's sweep parameters) win over the tier's values.
#include <map>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace tumble {

const std::vector<std::string>& fidelity_tiers();  // standard first

// The scene keys a tier sets for `scene` (the scene at its standard values), as text values.
// Empty for `standard`. Throws InputError for a tier that does not apply (cylinder scenes).
std::map<std::string, std::string> tier_values(Tier tier, const Scene& scene);

}  // namespace tumble
