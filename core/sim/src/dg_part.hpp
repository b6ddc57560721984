// The DG side of sim::Simulation (method "dg", seed 003, docs/decisions/0021): the DG model the
// integrator steps (its state rows are polynomial coefficients, not nodes), the stitching that
// turns them into nodal positions for the surface, picking and the VTU output, the scene's
// loads as coefficient loads, and the MLS embedding of points that are not nodes.
#pragma once

#include "polycut/cut/cut_report.hpp"
#include "polycut/dg/dg_model.hpp"
#include "polycut/dg/embedding.hpp"
#include "polycut/scene/scene.hpp"

#include <memory>

namespace polycut::sim {

struct DgPart {
    std::unique_ptr<dg::DgModel> model;
    std::vector<int> level; ///< per cell: times its lineage was split (adaptivity)
    std::unique_ptr<dg::Stitching> stitching;
    VecX scene_load; ///< (3#coeffs) the scene's constant loads [N]
    VecX load; ///< (3#coeffs) work vector [N]
};

/// The DG options of a scene (basis.degree, dg.flux, dg.penalty, dg.lambda_penalty).
dg::DgOptions dg_options(const scene::Scene& s);

/// Boundary faces of the scene's fixed sets (all nodes selected), where u = 0 is imposed
/// weakly (Nitsche), with the fixed components of each (bit a = component a). Throws
/// SceneError for a set fixing a single node (DG DOFs are not nodal) and for a set that
/// selects no boundary face.
struct DgDirichlet {
    std::vector<Index> faces;
    std::vector<std::uint8_t> axes;
};
DgDirichlet dg_dirichlet_faces(const scene::Scene& s, const mesh::Mesh& m);

/// Builds the DG model, its stitching and the scene's loads: area forces and pressures as
/// exact face tractions, point and uniform forces through the stitching's adjoint. With `old`
/// (the model before a cut edited `m`), the model re-integrates only the cells not flagged in
/// `unchanged` (source: old id of each cell) and their faces (dg::DgModel's update constructor).
std::unique_ptr<DgPart> make_dg_part(const scene::Scene& s, const mesh::Mesh& m,
    const dg::DgModel* old = nullptr, const std::vector<Index>& source = {},
    const std::vector<std::uint8_t>& unchanged = {});

/// After a cut edited the mesh `m` (core/cut's cell splitting, report `report`): a new DG part
/// on it, and the state carried over. Every cell takes the polynomial of the cell it came from
/// (itself, or the parent it was split from): a polynomial of degree p restricted to a piece is
/// in the piece's space, so the transfer is exact (a least-squares fit through the piece's
/// vertices, their midpoints and its centroid, which are unisolvent for p <= 2); cells the cut
/// did not change copy their rows. The cut faces are boundary faces of both lips: no penalty
/// couples them, so the two sides separate (003 sec. 10).
std::unique_ptr<DgPart> dg_after_cut(const DgPart& old, const scene::Scene& s, const mesh::Mesh& m,
    const cut::CutReport& report, MatX3& x, MatX3& v);

/// Stress-based refinement after a step (scene dg.refine_stress, 003 sec. 10): splits the hex
/// cells over the threshold whose level is below dg.refine_levels, 1-to-8, into `m`, and
/// returns the new part with the state carried over exactly (children start from the parent's
/// polynomial); null when no cell qualifies (nothing changed).
std::unique_ptr<DgPart> dg_refine(
    const DgPart& old, const scene::Scene& s, mesh::Mesh& m, MatX3& x, MatX3& v);

/// Displacement [m] at a rest point: the stitched value at a node (003 eq. 17), the MLS
/// embedding elsewhere (003 eq. 18-19); zero when the point is not near the tissue.
Vec3 dg_point_displacement(const DgPart& dg, const MatX3& x, const Vec3& X);

} // namespace polycut::sim
