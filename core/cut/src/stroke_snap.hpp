// Rest-space snapping rules for mapped sweep triangles (issue 12 item 2, docs/decisions/0005 and
// 0007): blades in planes of faces, and blade edges onto nodes and chords of the uncut mesh.
#pragma once
#include "polycut/mesh/mesh.hpp"

#include <array>
#include <vector>

namespace polycut::cut::detail {

/// The snapping rule for blades in planes of faces (issue 12 item 2): a blade meant to run in a
/// plane of mesh faces (a grid plane, an earlier cut's face) arrives a few micrometres off it
/// after the world-to-rest fit of a deforming body, and cutting there would leave sheets of
/// cells microns thick (they explode in the next step) or, for face snapping, no crossings at
/// all. When every corner of rest triangle `r` lies within `tol` [m] of the plane of a face of
/// the cells `near`, the corners not yet fixed by earlier triangles (`known` false) are
/// projected onto the closest such plane, provided the fixed ones already lie in it (within
/// `exact` [m]). One outcome per configuration, no jitter and no retry.
///
/// The re-cut rule (docs/decisions/0054): the faces an earlier cut made (tag Cut) attract from
/// farther, `recut_tol` [m], when the triangle is within 10 degrees of parallel to them and its
/// plane meets theirs within `reach` [m] (the tissue's size): it crosses them, or converges on
/// them at a shallow angle. A
/// second stroke along the first one maps to rest space through the opened, deformed body and
/// arrives at a slightly different plane, 0.05-0.5 mm from the first cut and a fraction of a
/// degree off it; cut there, it carved wedges a few micrometres to a tenth of a millimetre thick
/// between the two cuts, whose stiffness stalled the solver and exploded. Within `recut_tol` the
/// blade follows the existing cut instead (cutting where it is already cut does nothing) and
/// extends it where it goes beyond. A blade parallel to an earlier cut, a slice (000 Fig. 9),
/// keeps its plane however thin the slice. Pass recut_tol = 0 to disable the rule (it applies to
/// a stroke's first triangle; later ones follow it by the stroke-plane rule). Returns true when
/// the triangle went onto the plane of a Cut face (by either rule).
bool snap_to_face_plane(const mesh::Mesh& m, const std::vector<Index>& near, std::array<Vec3, 3>& r,
    const std::array<bool, 3>& known, double tol, double exact, double recut_tol, double reach);

/// The snapping rule for the blade's edges (issue 12 item 2, docs/decisions/0007): a new corner
/// `x` of a rest sweep triangle with unit normal `n` and offset `d0` that lies within `tol` [m]
/// of a node of the uncut mesh `m` in the triangle's plane goes onto that node; otherwise,
/// within `tol` of the chord the plane cuts from a face of the uncut mesh (an edge when the
/// edge lies in the plane), onto that chord. The triangle's
/// plane does not change. A blade meant to run along grid edges or through grid nodes (its tip,
/// the start and the end of a stroke) arrives ~0.2 mm beside them after the affine fit of a
/// sagging body; cut there, it left strips of faces and nodes that close whose cells had
/// near-zero-energy modes. `cells`: the cells of `m` near x; `in_plane` [m]: how close to the
/// plane a node counts as in it. Only the uncut mesh's features attract: the nodes the stroke
/// itself made would pull each new corner back onto the previous crack front.
void snap_corner_to_features(const mesh::Mesh& m, const std::vector<Index>& cells, Vec3& x,
    const Vec3& n, double d0, double tol, double in_plane);

} // namespace polycut::cut::detail
