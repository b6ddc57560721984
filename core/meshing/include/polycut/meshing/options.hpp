// Options shared by every CGAL Mesh_3 entry point (implicit shapes and closed surfaces), and the
// progress lines long meshing reports.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace polycut::meshing {

/// Sizing and quality criteria of a tetrahedral mesh (CGAL Mesh_3 criteria) and its seed.
struct MeshingOptions {
    /// Upper bound on the circumradius of the tetrahedra and on the radius of the surface
    /// Delaunay balls [m]. Edges of well-shaped tets come out at roughly 1-1.6 x cell_size.
    double cell_size = 0.01;
    /// Upper bound on the distance between a boundary facet's circumcentre and the true surface
    /// [m]; <= 0 means cell_size / 10.
    double facet_distance = 0;
    /// Lower bound on the smallest angle of boundary facets [deg] (CGAL allows at most 30).
    double facet_angle = 25;
    /// Upper bound on circumradius / shortest edge of the tetrahedra (>= 2 is safe).
    double cell_radius_edge_ratio = 3;
    /// Seed of every random choice CGAL makes; the same input and seed give the same mesh.
    unsigned seed = 0;
    /// Mesh_3 optimisers, run after refinement in this order (all deterministic: no time
    /// limits). Lloyd and ODT smoothing move the vertices towards a better size grading (each
    /// at most 20 iterations; slow); sliver perturbation moves the vertices of the worst tets
    /// and exudation re-weights them, both raising the smallest dihedral angle. Default: perturb
    /// and exude, which remove most slivers for ~1.5x the refinement time.
    bool lloyd = false;
    bool odt = false;
    bool perturb = true;
    bool exude = true;
    /// Perturbation and exudation stop once every tet's smallest dihedral angle is above this
    /// [deg]; 0 (CGAL's default) means as far as they can. Measured on the 4k-node organ
    /// (assets/meshes/liver_defects.off at 3 mm): 0 gives min 12.5 deg and 1st-percentile radius
    /// ratio 0.46 with exudation taking ~8x the refinement; 15 gives min 15 deg, p1 0.37 for
    /// ~1x; 25 takes 50x.
    double sliver_bound = 0;
    /// Surfaces only: edges whose dihedral angle deviates from flat by more than this are kept
    /// as sharp features [deg]; <= 0 disables feature detection.
    double feature_angle = 60;

    /// Wall time Mesh_3's refinement may take before it is stopped with an InputError [s]; <= 0:
    /// 10 s + 1 ms per expected vertex (0.4 x the bounding box volume / cell_size^3), about
    /// 100 x what a refinement that converges takes. Some surfaces much thinner than the cell
    /// size (the wrap of an open box at a quarter of its size) refine for ever otherwise.
    double refine_time_limit = 0;

    /// facet_distance with the default applied [m].
    double effective_facet_distance() const {
        return facet_distance > 0 ? facet_distance : cell_size / 10;
    }
};

/// Throws InputError (where "options.<field>") unless every option is finite and in range.
void check_options(const MeshingOptions& options);

/// Sets lloyd, odt, perturb and exude to whether their scene name ("lloyd", "odt", "perturb",
/// "exude") is in `names` (the scene's geometry.optimize). Throws InputError (where "optimize")
/// for another name.
void select_optimizers(MeshingOptions& options, const std::vector<std::string>& names);

/// Receives one line per meshing phase ("Mesh_3 exude: 21209 tets, 1298 ms").
using ProgressSink = std::function<void(const std::string& line)>;

/// Writes "polycut meshing: <line>" to stderr.
void print_progress(const std::string& line);

} // namespace polycut::meshing
