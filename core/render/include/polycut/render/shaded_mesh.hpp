// Per-vertex normals for shading a triangle surface: area-weighted, split at sharp creases and
// at tag boundaries so a cut face keeps a crisp edge against the skin around it.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace polycut::render {

/// Triangle tags, as polycut::FaceTag.
enum class SurfaceTag : std::uint8_t { Interior = 0, Skin = 1, Cut = 2 };

/// A triangle surface as plain arrays (non-owning views).
struct SurfaceArrays {
    std::span<const float> positions; ///< (#V x 3) [m]
    std::span<const std::uint32_t> triangles; ///< (#T x 3) vertex indices
    std::span<const std::uint8_t> tags; ///< (#T) SurfaceTag values; empty = all skin

    /// Throws InputError naming the first bad entry: a size that is not a multiple of 3, a
    /// tags array of the wrong length, an unknown tag, a non-finite position or an index >= #V.
    void validate() const;
};

/// A surface ready to draw: vertices duplicated where the shading normal changes.
struct ShadedMesh {
    std::vector<float> positions; ///< (#R x 3) [m]
    std::vector<float> normals; ///< (#R x 3) unit normals
    std::vector<std::uint8_t> tags; ///< (#R) tag of the triangles sharing the vertex
    std::vector<std::uint32_t> source; ///< (#R) input vertex each render vertex copies
    std::vector<std::uint32_t> triangles; ///< (#T x 3) indices into the render vertices
};

/// Builds shading normals. Two triangles that share an edge (with no third triangle on it) are
/// shaded smoothly across it if they have the same tag and their normals differ by at most
/// `crease_angle_deg` [deg]: 0 gives flat shading, 180 smooth shading except at tag boundaries.
/// A vertex normal is the area-weighted mean of the face normals in its smooth group.
/// Degenerate triangles get the normal of a neighbour-free group, (0, 0, 1) if it has zero area.
/// Deterministic; reuses the capacity of `out`. Input is assumed valid (SurfaceArrays::validate).
void build_shaded_mesh(const SurfaceArrays& surface, double crease_angle_deg, ShadedMesh& out);

} // namespace polycut::render
