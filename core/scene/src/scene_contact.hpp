// Scene keys of penalty contact (issue 15 item 1): `obstacles` and `contact`.
#pragma once

#include "json_reader.hpp"
#include "polycut/scene/scene.hpp"

namespace polycut::scene::detail {

/// Reads the optional `obstacles` array and `contact` object of the scene object `r` into `s`.
void parse_contact(ObjectReader& r, Scene& s);

} // namespace polycut::scene::detail
