#pragma once
#include <stdexcept>
#include <string>

namespace tumble {
// Bad user input (scene keys, values, files). Raised before any work starts; the message names the
// key and the allowed range so the user can fix it without reading code.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// A file Tumble wrote itself (checkpoint, cached bed, case fields, collector state, partial or
// ensemble) reads back damaged: a checksum mismatch, unreadable HDF5 metadata, or contents that
// cannot have been written by Tumble (ids out of range, species beyond the scene's, lengths that
// disagree). A type of its own so the CLI can exit with exit_code::kCorruptInput (3): the fix is
// to delete or regenerate the file, not to edit the scene. The message names file and dataset.
struct CorruptInputError : InputError {
  using InputError::InputError;
};
// A run that went wrong physically (NaN, escaped particle): the campaign records it as failed.
struct RunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
}  // namespace tumble
