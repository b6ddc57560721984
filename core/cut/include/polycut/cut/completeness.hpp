// How complete a cut is (issue 12 item 4): the rest-space area of the Cut faces against twice the
// area the blade swept inside the tissue (each swept square metre opens two lips). 1 for a cut
// that separates exactly what the blade swept; face snapping reaches less where the blade runs
// between mesh faces (docs/scenes.md states the bound).
#pragma once

#include "polycut/cut/cut_options.hpp"
#include "polycut/mesh/mesh.hpp"

#include <span>

namespace polycut::cut {

/// Area [m^2] of the part of the rest-space triangle `t` inside the cells `cells` of `mesh`
/// (convex cells, e.g. the uncut mesh: the triangle is clipped by each cell's face planes). Pass
/// at least every cell whose bounds meet the triangle's (e.g. from a cut::WorldToRest over the
/// rest positions); others add nothing. A triangle lying in an interior face is counted once
/// (for the face's owner), one lying in a skin face not at all.
double area_inside(const mesh::Mesh& mesh, std::span<const Index> cells, const Triangle& t);

/// The same over all cells of `mesh`, O(cells).
double area_inside(const mesh::Mesh& mesh, const Triangle& t);

/// Area [m^2] of the rest-space triangle `t` covered by faces an earlier cut made: the boundary
/// faces tagged Cut of the cells `cells` whose nodes all lie within `tol` [m] of the plane of
/// `t`, projected onto that plane (the cutter's node snapping distance for cell splitting; for
/// face snapping, whose cut runs along mesh faces beside the blade, a fraction of a cell), each
/// covered point counted once, not once per lip. The part of a re-cut's sweep that was cut
/// already (docs/decisions/0054): the swept area of a stroke is its area inside the tissue minus
/// this.
double area_on_cut_faces(
    const mesh::Mesh& mesh, std::span<const Index> cells, const Triangle& t, double tol);

/// Rest-space area of the boundary faces tagged Cut [m^2]: both lips of every cut.
double cut_face_area(const mesh::Mesh& mesh);

} // namespace polycut::cut
