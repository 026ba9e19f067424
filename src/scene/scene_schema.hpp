#pragma once
// The key table's internals shared by the parser (scene.cpp) and the table (scene_schema.cpp).
#include <string>

#include "scene/scene.hpp"

namespace tumble {

// Sets key `spec`'s value, already checked against the spec (range, integer, choices): `num` for
// numbers, `text` for text and enum names.
void set_key(Scene& s, const KeySpec& spec, const std::string& text, double num);

// `text` as a TOML basic string: quoted, with its backslashes and quotes escaped (scene_to_text
// writes every text value so; a path holding a quote made a checkpoint's scene unreadable).
std::string toml_quoted(const std::string& text);

}  // namespace tumble
