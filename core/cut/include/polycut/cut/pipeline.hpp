// The one cut pipeline (issue 12 item 6, docs/decisions/0010): world-space sweep triangles and
// the current node positions in, a typed result out. It validates each triangle once (finite,
// near the tissue, a triangle at the tissue's scale), maps it to rest space (DESIGN.md sec. 3:
// the blade traces material points), applies the snapping rules of docs/decisions/0005 and 0007
// there, and hands the rest triangles to the cutter of the scene (cell splitting, 000 sec. 5, or
// face snapping, 002 sec. 3.2) within a budget of changed cells; the triangles past the budget
// are deferred to the next call.
//
// The pipeline changes only the mesh; the caller (sim::Simulation) owns the state
// that must follow the mesh (displacements, the model, the undo snapshot).
#pragma once
#include "polycut/cut/cut_options.hpp"
#include "polycut/cut/cut_report.hpp"
#include "polycut/cut/snap_cutter.hpp"
#include "polycut/mesh/mesh.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace polycut::cut {

/// Which cutter a pipeline drives.
enum class CutMethod {
    Split, ///< cell splitting (000 sec. 4-5), any convex cells
    Snap, ///< face snapping (002 sec. 3.2), tet meshes
};

/// Settings of a CutPipeline.
struct PipelineOptions {
    CutMethod method = CutMethod::Split;
    CutOptions split; ///< the cell-splitting cutter's tolerances
    SnapOptions snap; ///< the face-snapping cutter's tolerances
    /// Cell splitting: a strip of sweep triangles in the scalpel's order whose samples are
    /// closer than this [m] is swept through fewer, wider quads (the blade resolution the
    /// server's `scalpel` samples get, Simulation::blade_min_advance); 0: as given.
    double strip_min_advance = 0;
};

/// A mapped sweep triangle whose rest image is longer (longest edge) or larger (area) than this
/// many times its world self went through tissue that is folded or crushed beyond what the map
/// can follow: it is skipped and reported (CutResult::stretched). A sagging, grabbed or cut
/// organ maps its sweep within 0.82-1.22 (area) and 1.05 (edge); on an organ pressed into folds
/// the joint fit of successive samples jumped, rest triangles came out up to 33x longer and
/// 1,900x larger, the face-snapped cut covered 3.3x the swept area and single calls took up to
/// 0.5 s searching the cells under them (docs/decisions/0067).
inline constexpr double kMaxRestStretch = 4.0;

/// Outcome of a pipeline call.
enum class CutStatus {
    Applied, ///< every triangle was cut, skipped or missed the tissue
    Deferred, ///< the budget was reached: `deferred` trailing triangles wait for the next call
    Rejected, ///< the input was refused before anything changed (see `rejected_triangle`)
    Failed, ///< the cutter failed part-way: the caller must restore the mesh (see `reason`)
};

/// What a pipeline call did, with the cutter's report.
struct CutResult {
    CutStatus status = CutStatus::Applied;
    CutReport report; ///< the cutter's report (empty unless something was cut)
    /// Input triangles consumed: cut, missed or skipped (the first `consumed` of the input).
    std::size_t consumed = 0;
    std::size_t deferred = 0; ///< trailing input triangles not consumed (Deferred)
    std::size_t cut = 0; ///< triangles handed to the cutter
    std::size_t skipped = 0; ///< too small at the tissue's scale, or outside it: no change
    /// Rest area of the cut triangles inside the uncut tissue [m^2]; for Failed, of the
    /// triangles the failed call was given.
    double swept_area = 0;
    /// Tets around the mapped triangles whose deformed volume is negative (the body folded
    /// there: the world-to-rest map is not one-to-one, so the cut follows the fold only
    /// approximately; docs/scenes.md "Completeness"). 0 for a body that did not invert.
    std::size_t inverted_cells = 0;
    /// Skipped triangles (counted in `skipped` too) whose rest image came out more than
    /// kMaxRestStretch times longer or larger than the triangle: mapped through folded or
    /// crushed tissue.
    std::size_t stretched = 0;
    /// Rejected: index of the offending input triangle, and its corner (-1 for the whole
    /// triangle); the server turns them into a JSON pointer.
    std::ptrdiff_t rejected_triangle = -1;
    int rejected_corner = -1;
    std::string reason; ///< Rejected and Failed: what is wrong
    bool ok() const { return status == CutStatus::Applied || status == CutStatus::Deferred; }
};

/// World-space sweep triangles to a cut of `mesh`. Holds the cutter, the stroke's mapped corners
/// and two uniform grids (deformed cells, uncut cells at rest).
class CutPipeline {
public:
    /// Binds to `mesh` (cut in place) and `uncut` (the mesh before any cut, for the swept area
    /// and the blade-edge snapping); both must outlive the pipeline.
    CutPipeline(mesh::Mesh& mesh, const mesh::Mesh& uncut, PipelineOptions options);
    ~CutPipeline();
    CutPipeline(const CutPipeline&) = delete;
    CutPipeline& operator=(const CutPipeline&) = delete;

    /// Validates and maps `world` triangles [m] through the current node positions `positions`
    /// (#N) [m], then cuts the mesh along them in order. With `max_changed_cells` > 0 the cut
    /// stops after the triangle that brings the cells it changed (split or rewritten) to that
    /// many, and the rest is Deferred; at least one triangle is cut, so a stroke advances. The
    /// budget is a count, not a time, so a replayed command log cuts the same. Rejected leaves
    /// everything as it was. Failed leaves the mesh half cut: call undo().
    /// `before_change` runs once right before the mesh is first changed (to snapshot what the
    /// caller must undo), and not at all when nothing is to be cut. Never throws for bad input or a
    /// failing cutter. With `max_triangles` > 0 at most that many mapped triangles are cut and
    /// the rest is Deferred the same way (every triangle is still validated first).
    CutResult cut(std::span<const Triangle> world, std::span<const Vec3> positions,
        Index max_changed_cells = 0, const std::function<void()>& before_change = {},
        std::size_t max_triangles = 0);
    /// Ends the current stroke: forgets its corners; face snapping cuts the faces it held back
    /// (their pinched edges split), so a stroke ends complete. Same contract as cut().
    CutResult end_stroke(const std::function<void()>& before_change = {});
    /// Puts the mesh back as it was before the last call that changed it (after a Failed call,
    /// or when the caller finds the cut unsound) and forgets what was derived from the cut mesh.
    /// The pipeline keeps a mirror of the mesh for this, brought up to date at the start of each
    /// call from what the previous call reported it changed (issue 12 item 5: no copy of the
    /// mesh per cut); the undo itself copies the mirror back.
    void undo();
    /// The cuts so far are sound (the step after them succeeded): undo_all() comes back to here.
    void accept();
    /// Puts the mesh back as it was at the last accept() (or when the pipeline was made): every
    /// call since is undone, when the step after them failed.
    void undo_all();
    /// How many calls were mirrored by a whole copy of the mesh (calls that renumbered cells,
    /// faces or nodes); the others copied only what they changed.
    std::uint64_t whole_mesh_copies() const;
    /// How many mirror syncs moved the mirror's faces along merged cut faces' compactions
    /// (CutReport::face_map) instead of copying the whole mesh.
    std::uint64_t mirror_face_moves() const;
    /// Builds the cutter (its adjacency and caches) and the grid of the uncut mesh now, so the
    /// first call does not pay for them.
    void prepare();
    /// Forgets everything derived from the mesh (after the caller restored it).
    void forget();
    /// Mean cell size of the uncut mesh [m]: the cube root of its mean cell volume.
    double cell_size() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace polycut::cut
