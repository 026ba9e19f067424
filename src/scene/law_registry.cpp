#include "scene/law_registry.hpp"

#include <cmath>

#include "base/error.hpp"

namespace tumble {

namespace {
std::vector<ContactLawSpec>& registry() {
  static std::vector<ContactLawSpec> laws;
  return laws;
}
}  // namespace

void register_contact_law(const ContactLawSpec& spec) {
  for (auto& law : registry())
    if (law.name == spec.name) {
      law = spec;
      return;
    }
  registry().push_back(spec);
}

const std::vector<ContactLawSpec>& contact_laws() { return registry(); }

const ContactLawSpec& contact_law(const std::string& name) {
  for (const auto& law : registry())
    if (law.name == name) return law;
  if (registry().empty())
    throw std::logic_error(
        "no contact law is registered: call tumble::contact::register_laws() "
        "(contact/laws.hpp) before reading a scene");
  std::string names;
  for (const auto& law : registry()) names += (names.empty() ? "" : ", ") + law.name;
  throw InputError("scene error: key 'contact.law' = '" + name + "' is not one of: " + names);
}

double damped_time_step_bound(double w0_squared, double gamma) {
  return (std::sqrt(4 * gamma * gamma + w0_squared) - 2 * gamma) / w0_squared;
}

}  // namespace tumble
