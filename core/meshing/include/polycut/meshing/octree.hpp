// An adaptive octree of hexahedral cells that embeds an object (001 sec. 7, Fig. 4 and 7): coarse
// cells inside, fine cells where the object's surface crosses and in regions of interest, 2:1
// balanced across faces, edges and corners. The leaves become the cells of a polyhedral mesh
// whose faces match between neighbours: where a coarse cell meets four finer ones its face is
// split into their four faces, and the nodes finer cells put on its edges enter its face loops.
// So there are no hanging nodes ("the center one is not a hanging node, but instead is part (and
// DOF) of all three elements", 001 Fig. 4): a leaf with no finer neighbour stays a Hex (Q1), the
// others are Polyhedra for the `harmonic` or `mvc` basis. Cells outside the object are dropped,
// cells the surface crosses are kept whole (an embedded surface gives the detailed skin).
// Leaves can be split 1-to-8 later (stress-based refinement, 001 sec. 8): the domain never
// changes, only its partition.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/mesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace polycut::meshing {

/// A box refined to a finer cell size.
struct OctreeRegion {
    Vec3 lo = Vec3::Zero(); ///< min corner [m]
    Vec3 hi = Vec3::Zero(); ///< max corner [m]
    double cell_size = 0; ///< largest cell edge inside the box [m] (> 0)
};

/// Options of an Octree. Lengths in metres.
struct OctreeOptions {
    Vec3 lo = Vec3::Zero(); ///< domain min corner [m]
    Vec3 hi = Vec3::Ones(); ///< domain max corner [m]
    /// Edge of the base (coarsest) cells [m]; the domain is divided into round(size / cell_size)
    /// blocks per axis (at least 1), so base cells are cubes when the size is a multiple.
    double cell_size = 0.1;
    /// Largest edge of a cell the object's surface may cross [m]; 0: cell_size.
    double surface_cell_size = 0;
    std::vector<OctreeRegion> regions; ///< boxes refined further
    /// Most levels below the base cells (each halves the edge); at most kMaxDepth.
    int max_depth = 6;
    /// Which leaves the surface crosses are kept: those that may overlap the object (`cover`:
    /// value(centre) < half-diagonal; the cells contain the whole object, their volume exceeds
    /// it by up to a shell of one cell) or those whose centre is inside (`centre`; about the
    /// object's volume, the surface up to a half-diagonal outside the cells).
    enum class Keep { Cover, Centre };
    Keep keep = Keep::Centre;
};

/// Signed value of the object at a point [m]: negative inside, and |value| never more than the
/// distance to the surface (1-Lipschitz), so a cell whose centre value exceeds its half-diagonal
/// is wholly inside or outside. An empty function: the whole domain is the object.
using SignedValue = std::function<double(const Vec3&)>;

/// The octree: a forest over the base grid, leaves kept (in the object) or dropped.
class Octree {
public:
    static constexpr int kMaxDepth = 10; ///< levels below the base cells

    /// Builds the tree: splits to the surface and region sizes, balances 2:1, keeps the leaves
    /// the object may overlap. Throws InputError naming the option ("cell_size",
    /// "surface_cell_size", "regions/i", "max_depth", "lo") for bad options.
    Octree(const OctreeOptions& options, SignedValue value = {});

    /// The kept leaves as cells (see the file comment). Cell c is leaf cell_leaves()[c]. Kept
    /// leaves are added where the boundary would not be a 2-manifold (cells touching along an
    /// edge or at a corner only). Validated (mesh::validate) before it is returned.
    mesh::Mesh build_mesh();
    /// Leaf of each cell of the last build_mesh().
    const std::vector<int>& cell_leaves() const { return m_cell_leaves; }

    /// Splits these leaves 1-to-8 (children keep the parent's kept flag, so the domain does not
    /// change) and balances again; returns how many leaves were split in all. Leaves at
    /// max_depth are left alone.
    int refine(const std::vector<int>& leaves);

    /// Level of a leaf below its base cell (0: base).
    int level(int leaf) const { return m_nodes[std::size_t(leaf)].level; }
    /// Edge lengths of a leaf [m].
    Vec3 leaf_size(int leaf) const;
    int max_depth() const { return m_max_depth; }
    /// Number of kept leaves.
    int num_kept() const;
    /// Leaves per level among the kept ones (index: level).
    std::vector<int> kept_per_level() const;

private:
    struct Node {
        std::array<int, 3> lo {}; ///< min corner in units of the finest level
        int size = 0; ///< edge in units
        int level = 0;
        int first_child = -1; ///< 8 children from here, -1 for a leaf
        bool kept = true;
    };
    int split(int node);
    void split_to(int node);
    void balance();
    int leaf_at(const std::array<int, 3>& p) const; ///< -1 outside the domain
    int target_level(const Node& n) const;
    bool may_overlap(const Node& n) const;
    Vec3 position(const std::array<int, 3>& p) const;
    bool in_domain(const std::array<int, 3>& p) const;

    OctreeOptions m_options;
    SignedValue m_value;
    Eigen::Vector3i m_blocks { 1, 1, 1 };
    Vec3 m_unit = Vec3::Ones(); ///< edge of a unit [m] per axis
    int m_max_depth = 0;
    int m_surface_level = 0;
    std::vector<int> m_region_levels;
    std::vector<Node> m_nodes; ///< roots first (base grid, x fastest)
    std::vector<int> m_cell_leaves;

    friend struct OctreeMeshBuilder; // octree_mesh.cpp
};

} // namespace polycut::meshing
