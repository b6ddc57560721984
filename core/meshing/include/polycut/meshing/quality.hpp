// Shape quality of the tetrahedra of a mesh: dihedral angles and radius ratios, the figures that
// say whether a meshed organ has slivers (flat tets whose stiffness blows up the condition number
// of the step's system).
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/mesh/mesh.hpp"

#include <string>

namespace polycut::meshing {

/// Below this smallest dihedral angle a tet counts as a sliver [deg].
inline constexpr double kSliverDihedralDeg = 5.0;

/// Quality of the tetrahedra of a mesh. Cells that are not tets are not counted.
struct TetQuality {
    Index tets = 0; ///< tets measured
    double min_dihedral_deg = 0; ///< smallest dihedral angle over all tets [deg] (70.53 regular)
    double max_dihedral_deg = 0; ///< largest dihedral angle over all tets [deg]
    /// Radius ratio rho = 3 r_in / r_circ of each tet (1 for the regular tet, 0 for a flat one):
    /// minimum, 1st percentile and median over the tets.
    double radius_ratio_min = 0;
    double radius_ratio_p1 = 0;
    double radius_ratio_p50 = 0;
    Index slivers = 0; ///< tets whose smallest dihedral angle is below kSliverDihedralDeg
    /// True when the mesh has slivers (slivers > 0): the scene should be remeshed (smaller
    /// cell_size, or perturb/exude if they were turned off).
    bool has_slivers() const { return slivers > 0; }
};

/// Dihedral angles and radius ratios of every tet cell of `mesh` (rest positions). A degenerate
/// tet (zero volume or coincident nodes) counts with angle 0 and ratio 0.
TetQuality tet_quality(const mesh::Mesh& mesh);

/// One line for logs: "27745 tets, dihedral 9.8-160.2 deg, radius ratio min 0.21 p1 0.43 p50
/// 0.80, 0 slivers (< 5 deg)".
std::string to_string(const TetQuality& quality);

} // namespace polycut::meshing
