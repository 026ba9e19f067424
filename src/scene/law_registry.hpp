#pragma once
// What the scene layer knows of a contact law: its name, the scene keys it owns, and the checks a
// scene of that law must pass (time-step bound, static overlap under the bed's weight, its own
// cross-key rules). The laws themselves live in src/contact/, a layer above this one (a law's
// coefficients are made from a Scene), so the scene layer cannot include them: instead each law
// describes itself with a ContactLawSpec of function pointers, and contact::register_laws()
// (src/contact/laws.hpp, the one list of laws) registers every law here once at start-up, before
// the first scene is read. The registry is read-only afterwards.
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace tumble {

// How to make a law's contacts stiffer, for the message that refuses too soft a scene:
// "use <key> <relation> <value>".
struct StifferHint {
  std::string key;
  std::string relation;  // " >= " or " <= "
  double value = 0;
};

struct ContactLawSpec {
  std::string name;  // the value of contact.law
  // The keys this law owns (numbers, "contact.*"); KeySpec::law names this law.
  std::vector<KeySpec> keys;
  // Provenance texts written before a later law was added list this law's keys for every scene;
  // they must stay byte-identical, so these keys are written whatever the law (rapaport2007).
  // Otherwise a law's keys are written only for scenes of that law.
  bool keys_in_every_text = false;
  // The law reads each particle's own radius (particles.size_spread > 0 allowed); the others
  // tabulate two particle sizes.
  bool size_spread = false;
  // time.dt_fraction scales contact.collision_time into the time step in a meaningful way (the
  // message of the time-step bound offers it).
  bool time_from_collision_time = false;
  // Largest stable time step of this law's stiffest contact (see damped_time_step_bound).
  double (*time_step_bound)(const Scene&) = nullptr;
  // Static overlap [m] of a small-small contact pressed by `force` [N].
  double (*static_overlap)(const Scene&, double force) = nullptr;
  // The change of this law's keys that brings the weight overlap `overlap` (a fraction of d_small,
  // weight_overlap_fraction) down to kMaxWeightOverlap.
  StifferHint (*stiffer)(const Scene&, double overlap) = nullptr;
  // The law's own cross-key checks; throws InputError naming the key. May be null.
  void (*check)(const Scene&) = nullptr;
};

// Adds a law (contact::register_laws does this for every law). Registering a name twice replaces
// the entry, so registration is idempotent.
void register_contact_law(const ContactLawSpec& spec);
// Every registered law, in registration order.
const std::vector<ContactLawSpec>& contact_laws();
// The law named `name`; throws InputError naming contact.law when there is none (with a hint when
// no law was registered at all: a program that reads scenes calls contact::register_laws()).
const ContactLawSpec& contact_law(const std::string& name);

// Velocity Verlet with the dashpot evaluated at the half-step velocity (equivalently leapfrog)
// integrates x'' = -Ω² x - C x' stably iff Ω² δt² + 2 C δt < 4. The stiffest mode of a packing is
// estimated by a particle between two of its stiffest contacts (a 1D chain, alternating mode),
// which doubles both the spring and the damping seen by one contact: Ω² = 4 ω0², C = 4 γ, with ω0²
// = max k/m over every pair and wall contact (m the lighter partner) and γ = c / 2m the damping
// rate of that contact. Hence
//   δt <= (sqrt(4 γ² + ω0²) - 2 γ) / ω0²,
// which is 1/ω0 without damping (≈ t_c/π for the Yu law) and shrinks as damping grows (e = 0.05:
// 0.075 t_c). Measured in tests/test_extremes.cpp: the former undamped bound let a bed with
// e = 0.05 gain energy. Each law supplies its own ω0² and γ.
double damped_time_step_bound(double w0_squared, double gamma);

}  // namespace tumble
