// Scene keys of issue 15: `obstacles`, `tools`, `contact` and `embedded`.
#pragma once

#include "json_reader.hpp"
#include "polycut/scene/scene.hpp"

namespace polycut::scene::detail {

/// Reads the optional `obstacles`, `tools`, `contact` and `embedded` keys of the scene object
/// `r` into `s`.
void parse_contact(ObjectReader& r, Scene& s);

} // namespace polycut::scene::detail
