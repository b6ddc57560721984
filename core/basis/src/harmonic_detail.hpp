// Internals of the harmonic basis (harmonic.hpp): the per-face 2D problems and the cell data.
#pragma once

#include "polycut/basis/harmonic.hpp"

#include <Eigen/Core>
#include <array>
#include <vector>

namespace polycut::basis::detail {

using Vec2 = Eigen::Vector2d;

/// Least-squares MFS system  min |A c - B| with A = [psi(|c_i - k_j|) | polynomial] (001 eq.
/// 14), solved by `solver` (Householder QR as a fallback when the normal equations are not
/// positive definite), then corrected so that the nodal combination sum_i x~_i N_i reproduces
/// linear functions exactly (the solution of the exact problem, up to round-off).
/// A: (m x (n + d + 1)), B: (m x g), X: (g x (d + 1)) nodal [x, 1]. Returns (n + d + 1) x g.
MatX solve_mfs(MatX A, const MatX& B, const MatX& X, Index num_kernels, HarmonicSolver solver);

/// 2D harmonic coordinates of one planar polygon face (001 sec. 4: the boundary values of the
/// 3D functions), by 2D MFS with the log kernel and a linear term.
class HarmonicFace {
public:
    /// loop: the face's distinct vertices in order (#k >= 3) [m].
    HarmonicFace(const std::vector<Vec3>& loop, const HarmonicOptions& options);
    /// Values (#k) of the k vertex functions at the projection of x onto the face plane.
    void evaluate(const Vec3& x, Eigen::Ref<VecX> out) const;
    /// 2D coordinates in the face frame, scaled by the face size.
    Vec2 to_2d(const Vec3& x) const;
    Vec3 to_3d(const Vec2& q) const;
    const std::vector<Vec2>& polygon() const { return m_poly; }
    double scale() const { return m_scale; }
    const Vec3& normal() const { return m_normal; }

private:
    Vec3 m_origin, m_e1, m_e2, m_normal;
    double m_scale = 1;
    std::vector<Vec2> m_poly; ///< scaled 2D vertices (#k), counter-clockwise
    std::vector<Vec2> m_kernel; ///< kernel centres (#n)
    MatX m_coef; ///< (n + 3) x k
};

/// Polygon helpers in 2D (counter-clockwise loops).
bool inside_polygon(const std::vector<Vec2>& poly, const Vec2& p);
double distance_to_polygon(const std::vector<Vec2>& poly, const Vec2& p);
/// Points of a square grid of spacing h inside the polygon, at least margin from its boundary.
std::vector<Vec2> polygon_grid(const std::vector<Vec2>& poly, double h, double margin);

} // namespace polycut::basis::detail

namespace polycut::basis {

/// The data of a harmonic cell (harmonic.cpp builds it, harmonic_integration.cpp integrates).
struct HarmonicCell::Impl {
    HarmonicOptions options;
    std::vector<Vec3> nodes;
    std::vector<Index> group; ///< node -> joint basis function (coincident nodes merged)
    std::vector<double> share; ///< node's share of its group's function (1 / group size)
    std::vector<Vec3> group_pos; ///< (#g) [m]
    std::vector<std::vector<Index>> loops; ///< group loops, consecutive duplicates removed
    std::vector<Index> face_of_loop; ///< input loop -> faces index, kNone if degenerate
    std::vector<detail::HarmonicFace> faces;
    std::vector<std::vector<Index>> face_groups; ///< group ids of each kept face's vertices
    std::vector<SurfaceTriangle> triangles; ///< fan of the group loops (group ids)
    std::vector<Vec3> tri_normal; ///< unit outward normals
    bool convex = true;
    double volume = 0, size = 0;
    Vec3 centroid = Vec3::Zero();
    std::vector<Vec3> kernels; ///< kernel centres in scaled coordinates (x - centroid) / size
    MatX coef; ///< (n + 4) x g
    Index num_collocation = 0;

    Vec3 scaled(const Vec3& x) const { return (x - centroid) / size; }
    double winding(const Vec3& p) const;
    double surface_distance(const Vec3& p) const;
    double max_plane_distance(const Vec3& p) const;
    void evaluate_groups(const Vec3& x, VecX& phi, MatX3* grad) const;
    void to_nodes(const VecX& g, VecX& phi) const;
};

} // namespace polycut::basis
