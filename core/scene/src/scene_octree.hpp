// Scene keys of an octree geometry (issue 15 item 3) besides its object and cell_size.
#pragma once

#include "json_reader.hpp"
#include "polycut/scene/scene.hpp"

namespace polycut::scene::detail {

/// Reads `surface_cell_size`, `regions`, `max_depth`, `keep`, and `refine_stress` of
/// the geometry object `r` into g.octree.
void parse_octree(ObjectReader& r, Geometry& g);

} // namespace polycut::scene::detail
