#pragma once
#include <stdexcept>
#include <string>

namespace tumble {
// Bad user input (scene keys, values, files). Raised before any work starts; the message names the
// key and the allowed range so the user can fix it without reading code.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// A run that went wrong physically (NaN, escaped particle): the campaign records it as failed.
struct RunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
}  // namespace tumble
