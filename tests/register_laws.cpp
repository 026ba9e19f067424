// Every test program that reads scenes registers the contact laws before its tests run, as
// app/main.cpp does (scene/law_registry.hpp): static initialisation of this file, which each such
// test executable compiles in directly.
#include "contact/laws.hpp"

namespace {
[[maybe_unused]] const bool kLawsRegistered = (tumble::contact::register_laws(), true);
}  // namespace
