// Private: the scene-file name of every enum value, one table per enum. The parser reads names
// through these tables (ObjectReader::choice) and to_string() writes them back, so a name is
// spelled in exactly one place.
#pragma once

#include "polycut/scene/scene.hpp"

namespace polycut::scene::detail {

template <class E> struct Name {
    const char* text;
    E value;
};

inline constexpr Name<Geometry::Kind> kGeometryKind[] = { { "box", Geometry::Kind::Box },
    { "implicit", Geometry::Kind::Implicit }, { "surface_file", Geometry::Kind::SurfaceFile },
    { "mesh_file", Geometry::Kind::MeshFile }, { "random_planes", Geometry::Kind::RandomPlanes },
    { "convex_hull", Geometry::Kind::ConvexHull }, { "hex_slice", Geometry::Kind::HexSlice },
    { "octree", Geometry::Kind::Octree } };
inline constexpr Name<Obstacle::Kind> kObstacleKind[] = { { "plane", Obstacle::Kind::Plane },
    { "box", Obstacle::Kind::Box }, { "sphere", Obstacle::Kind::Sphere },
    { "capsule", Obstacle::Kind::Capsule }, { "mesh", Obstacle::Kind::Mesh } };
inline constexpr Name<Method> kMethod[] = { { "tet", Method::Tet }, { "hex", Method::Hex },
    { "mvc", Method::Mvc }, { "harmonic", Method::Harmonic }, { "dg", Method::Dg } };
inline constexpr Name<Elements> kElements[]
    = { { "tet", Elements::Tet }, { "hex", Elements::Hex } };
inline constexpr Name<TetSplit> kTetSplit[]
    = { { "kuhn6", TetSplit::Kuhn6 }, { "five", TetSplit::Five } };
/// Shapes of "implicit", "octree" and a hex_slice's implicit surface.
inline constexpr Name<Shape> kImplicitShape[] = { { "sphere", Shape::Sphere },
    { "hollow_sphere", Shape::HollowSphere }, { "ellipsoid", Shape::Ellipsoid },
    { "capsule", Shape::Capsule }, { "blob", Shape::Blob } };
/// Shapes of "convex_hull".
inline constexpr Name<Shape> kHullShape[]
    = { { "truncated_octahedron", Shape::TruncatedOctahedron } };
inline constexpr Name<NodeOrder> kNodeOrder[]
    = { { "rcm", NodeOrder::Rcm }, { "mesher", NodeOrder::Mesher } };
inline constexpr Name<Repair> kRepair[] = { { "auto", Repair::Auto }, { "none", Repair::None },
    { "pmp", Repair::Pmp }, { "wrap", Repair::Wrap } };
inline constexpr Name<Components> kComponents[] = { { "union", Components::Union },
    { "largest", Components::Largest }, { "refuse", Components::Refuse } };
inline constexpr Name<OctreeObject> kOctreeObject[] = { { "box", OctreeObject::Box },
    { "implicit", OctreeObject::Implicit }, { "surface_file", OctreeObject::SurfaceFile } };
inline constexpr Name<OctreeKeep> kOctreeKeep[]
    = { { "centre", OctreeKeep::Centre }, { "cover", OctreeKeep::Cover } };
inline constexpr Name<SolverType> kSolverType[] = { { "cholmod", SolverType::Cholmod },
    { "pcg", SolverType::Pcg }, { "cg_relaxation", SolverType::CgRelaxation } };
inline constexpr Name<Preconditioner> kPreconditioner[]
    = { { "jacobi", Preconditioner::Jacobi }, { "block_jacobi", Preconditioner::BlockJacobi },
          { "cell_block_jacobi", Preconditioner::CellBlockJacobi },
          { "lagged_cholesky", Preconditioner::LaggedCholesky }, { "amg", Preconditioner::Amg },
          { "two_level", Preconditioner::TwoLevel } };
inline constexpr Name<WarmStart> kWarmStart[] = { { "previous", WarmStart::Previous },
    { "extrapolated", WarmStart::Extrapolated }, { "projected", WarmStart::Projected } };
inline constexpr Name<Distribution> kDistribution[]
    = { { "area", Distribution::Area }, { "uniform", Distribution::Uniform } };
inline constexpr Name<CutMethod> kCutMethod[]
    = { { "split", CutMethod::Split }, { "snap", CutMethod::Snap } };
inline constexpr Name<ToolShape> kToolShape[] = { { "sphere", ToolShape::Sphere },
    { "capsule", ToolShape::Capsule }, { "blade", ToolShape::Blade } };
inline constexpr Name<basis::PolyRule> kPolyRule[] = { { "heuristic", basis::PolyRule::Heuristic },
    { "reference", basis::PolyRule::Reference }, { "monte_carlo", basis::PolyRule::MonteCarlo } };
inline constexpr Name<basis::VolumetricRule> kVolumetric[]
    = { { "full", basis::VolumetricRule::Full },
          { "mean_dilatation", basis::VolumetricRule::MeanDilatation },
          { "nodal_average", basis::VolumetricRule::NodalAverage } };
inline constexpr Name<dg::Flux> kFlux[]
    = { { "ip", dg::Flux::InteriorPenalty }, { "bz", dg::Flux::BabuskaZlamal } };
inline constexpr Name<dg::LambdaPenalty> kLambdaPenalty[]
    = { { "full", dg::LambdaPenalty::Full }, { "normal", dg::LambdaPenalty::Normal } };
inline constexpr Name<integrate::IntegratorKind> kIntegrator[]
    = { { "static", integrate::IntegratorKind::Static },
          { "implicit_euler", integrate::IntegratorKind::ImplicitEuler },
          { "semi_implicit_euler", integrate::IntegratorKind::SemiImplicitEuler } };
inline constexpr Name<integrate::StaticMode> kStaticMode[]
    = { { "newton", integrate::StaticMode::CorotatedNewton },
          { "fixed_point", integrate::StaticMode::CorotatedFixedPoint } };

/// The name of `value` in `table`, or "?" (a value no table lists).
template <class E, std::size_t N> const char* name_of(const Name<E> (&table)[N], E value) {
    for (const auto& n : table)
        if (n.value == value)
            return n.text;
    return "?";
}

} // namespace polycut::scene::detail
