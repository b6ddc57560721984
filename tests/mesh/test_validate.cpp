// Validation catches each kind of defect (issue 2 item 7) on small hand-built meshes, and passes
// on the builders' grids; the boundary-surface check counts holes, non-manifold edges and
// components.
#include "polycut/common/error.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/mesh/validate.hpp"

#include <algorithm>
#include <gtest/gtest.h>

using namespace polycut;
using namespace polycut::mesh;
using Kind = ValidationIssue::Kind;

namespace {

std::vector<Vec3> unit_cube_points(const Vec3& offset = Vec3::Zero()) {
    std::vector<Vec3> X { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
        { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } };
    for (Vec3& p : X)
        p += offset;
    return X;
}

Mesh unit_cube() {
    return Mesh::from_hexes(unit_cube_points(), { { 0, 1, 2, 3, 4, 5, 6, 7 } });
}

/// Hex face loops as from_polyhedra input.
std::vector<std::vector<Index>> hex_loops(const std::array<Index, 8>& h) {
    std::vector<std::vector<Index>> loops;
    for (const auto& f : kHexFaces)
        loops.push_back({ h[std::size_t(f[0])], h[std::size_t(f[1])], h[std::size_t(f[2])],
            h[std::size_t(f[3])] });
    return loops;
}

/// Both meshes side by side in one (nodes, faces and cells renumbered).
Mesh merge(const Mesh& a, const Mesh& b) {
    Mesh m = a;
    const Index n0 = a.num_nodes(), f0 = a.num_faces(), c0 = a.num_cells();
    m.rest.insert(m.rest.end(), b.rest.begin(), b.rest.end());
    for (Face f : b.faces) {
        for (Index& n : f.nodes)
            n += n0;
        f.owner += c0;
        if (f.neighbour != kNone)
            f.neighbour += c0;
        m.faces.push_back(f);
    }
    for (Cell c : b.cells) {
        for (Index& n : c.nodes)
            n += n0;
        for (Index& f : c.faces)
            f += f0;
        m.cells.push_back(c);
    }
    return m;
}

/// Removes face f from the face table and from the cells that list it.
void remove_face(Mesh& m, Index f) {
    m.faces.erase(m.faces.begin() + f);
    for (Cell& c : m.cells) {
        c.faces.erase(std::remove(c.faces.begin(), c.faces.end(), f), c.faces.end());
        for (Index& g : c.faces)
            g -= g > f ? 1 : 0;
    }
}

bool has(const std::vector<ValidationIssue>& issues, Kind kind) {
    return std::any_of(
        issues.begin(), issues.end(), [&](const ValidationIssue& i) { return i.kind == kind; });
}

const ValidationIssue& first_of(const std::vector<ValidationIssue>& issues, Kind kind) {
    auto it = std::find_if(
        issues.begin(), issues.end(), [&](const ValidationIssue& i) { return i.kind == kind; });
    EXPECT_NE(it, issues.end()) << kind_name(kind);
    return *it;
}

std::string describe(const std::vector<ValidationIssue>& issues) {
    std::string s;
    for (const auto& i : issues)
        s += std::string(kind_name(i.kind)) + ": " + i.message + "\n";
    return s;
}

} // namespace

TEST(Validate, GridsAreValid) {
    const BoxGrid g { Vec3(-0.1, 0, 0.2), Vec3(0.2, 0.05, 0.3), { 3, 2, 4 } };
    for (const Mesh& m :
        { hex_grid(g), tet_grid(g, TetSplit::Kuhn6), tet_grid(g, TetSplit::Five) }) {
        const auto issues = check_mesh(m, { .require_convex = true });
        EXPECT_TRUE(issues.empty()) << describe(issues);
        EXPECT_NO_THROW(validate(m));
        const SurfaceCheck s = check_boundary_surface(m);
        EXPECT_TRUE(s.closed);
        EXPECT_TRUE(s.oriented);
        EXPECT_TRUE(s.ok());
        EXPECT_EQ(s.components, 1);
        EXPECT_EQ(s.boundary_edges, 0);
        EXPECT_EQ(s.nonmanifold_edges, 0);
        EXPECT_EQ(s.first_bad_face, kNone);
        EXPECT_EQ(s.faces, Index(m.boundary_faces().size()));
    }
}

TEST(Validate, LargerGridIsValid) {
    // A few tens of thousands of cells: exercises the hashing paths (and their speed).
    const Mesh m = tet_grid({ Vec3::Zero(), Vec3::Ones(), { 12, 12, 12 } });
    EXPECT_TRUE(check_mesh(m).empty());
    const SurfaceCheck s = check_boundary_surface(m);
    EXPECT_TRUE(s.ok());
    EXPECT_EQ(s.faces, 6 * 12 * 12 * 2);
}

TEST(Validate, NonFinitePosition) {
    Mesh m = unit_cube();
    m.rest[6].y() = std::numeric_limits<double>::quiet_NaN();
    const auto issues = check_mesh(m);
    const auto& i = first_of(issues, Kind::NonFinite);
    EXPECT_EQ(i.node, 6);
    EXPECT_EQ(i.cell, 0);
    EXPECT_EQ(issues.front().kind, Kind::NonFinite);
    EXPECT_THROW(validate(m), MeshError);
}

TEST(Validate, NonPlanarQuadFace) {
    Mesh m = unit_cube();
    m.rest[6] += Vec3(1, 1, 1) * 1e-3; // the three faces through node 6 bend
    const auto issues = check_mesh(m);
    const auto& i = first_of(issues, Kind::NonPlanarFace);
    EXPECT_EQ(i.cell, 0);
    ASSERT_NE(i.face, kNone);
    const auto& nodes = m.faces[std::size_t(i.face)].nodes;
    EXPECT_NE(std::find(nodes.begin(), nodes.end(), 6), nodes.end());
    // Exactly the three faces through node 6.
    EXPECT_EQ(std::count_if(issues.begin(), issues.end(),
                  [](const auto& x) { return x.kind == Kind::NonPlanarFace; }),
        3);
    // planarity_error of a bent face is about 1e-3 / 4 = 1.4e-4 * cell size (sqrt 3).
    EXPECT_FALSE(has(check_mesh(m, { .planarity_tol = 2e-4 }), Kind::NonPlanarFace));
    EXPECT_TRUE(has(check_mesh(m, { .planarity_tol = 1e-4 }), Kind::NonPlanarFace));
    try {
        validate(m);
        FAIL() << "validate accepted a non-planar face";
    } catch (const MeshError& e) {
        EXPECT_EQ(e.cell(), 0);
        EXPECT_EQ(e.face(), i.face);
        EXPECT_NE(std::string(e.what()).find("non-planar"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("cell 0 face"), std::string::npos) << e.what();
    }
}

TEST(Validate, InvertedHexAndTet) {
    // Top and bottom swapped: topologically consistent, volume -1.
    const Mesh hex = Mesh::from_hexes(unit_cube_points(), { { 4, 5, 6, 7, 0, 1, 2, 3 } });
    auto issues = check_mesh(hex);
    const auto& i = first_of(issues, Kind::InvertedCell);
    EXPECT_EQ(i.cell, 0);
    EXPECT_NE(i.message.find("-1"), std::string::npos) << i.message;
    EXPECT_FALSE(has(issues, Kind::OpenCell));

    // A tet with all loops inward (from_tets would reorder it, from_polyhedra does not).
    const std::vector<Vec3> X { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
    std::vector<std::vector<Index>> loops;
    for (const auto& f : kTetFaces)
        loops.push_back({ Index(f[0]), Index(f[2]), Index(f[1]) });
    const Mesh tet = Mesh::from_polyhedra(X, { loops });
    issues = check_mesh(tet);
    ASSERT_FALSE(issues.empty());
    EXPECT_EQ(issues.front().kind, Kind::InvertedCell) << describe(issues);
    EXPECT_THROW(validate(tet), MeshError);
}

TEST(Validate, ZeroVolumeCell) {
    // Four coplanar nodes.
    const std::vector<Vec3> X { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 } };
    const Mesh m = Mesh::from_tets(X, { { 0, 1, 2, 3 } });
    const auto issues = check_mesh(m);
    const auto& i = first_of(issues, Kind::ZeroVolumeCell);
    EXPECT_EQ(i.cell, 0);
    EXPECT_FALSE(has(issues, Kind::InvertedCell));
    // min_volume turns a small but valid cell into a reported one.
    const Mesh cube = unit_cube();
    EXPECT_TRUE(check_mesh(cube, { .min_volume = 0.5 }).empty());
    EXPECT_TRUE(has(check_mesh(cube, { .min_volume = 1.5 }), Kind::ZeroVolumeCell));
}

TEST(Validate, OpenCellWithMissingFace) {
    auto loops = hex_loops({ 0, 1, 2, 3, 4, 5, 6, 7 });
    loops.erase(loops.begin() + 1); // top face (4 5 6 7) gone
    const Mesh m = Mesh::from_polyhedra(unit_cube_points(), { loops });
    const auto issues = check_mesh(m);
    const auto& i = first_of(issues, Kind::OpenCell);
    EXPECT_EQ(i.cell, 0);
    ASSERT_NE(i.face, kNone);
    // The reported face borders the hole: it holds two top nodes.
    const auto& nodes = m.faces[std::size_t(i.face)].nodes;
    EXPECT_EQ(std::count_if(nodes.begin(), nodes.end(), [](Index n) { return n >= 4; }), 2);
    EXPECT_FALSE(has(issues, Kind::InvertedCell)); // no volume for an open cell
    EXPECT_TRUE(has(issues, Kind::NonManifoldBoundary));
    const SurfaceCheck s = check_boundary_surface(m);
    EXPECT_FALSE(s.closed);
    EXPECT_EQ(s.boundary_edges, 4);
}

TEST(Validate, FlippedFaceMakesCellOpen) {
    Mesh m = unit_cube();
    std::reverse(m.faces[0].nodes.begin(), m.faces[0].nodes.end());
    const auto issues = check_mesh(m);
    // The flip also breaks the Hex tag's VTK order (reported first) and the boundary.
    EXPECT_EQ(issues.front().kind, Kind::BadShape) << describe(issues);
    EXPECT_NE(first_of(issues, Kind::OpenCell).message.find("same direction"), std::string::npos);
    const SurfaceCheck s = check_boundary_surface(m);
    EXPECT_TRUE(s.closed);
    EXPECT_FALSE(s.oriented);
    EXPECT_EQ(s.misoriented_edges, 4);
}

TEST(Validate, DuplicateNodes) {
    // Two cubes touching along x = 1 with their own copies of the four shared nodes: a crack.
    const Mesh a = unit_cube();
    const Mesh b
        = Mesh::from_hexes(unit_cube_points(Vec3(1, 0, 0)), { { 0, 1, 2, 3, 4, 5, 6, 7 } });
    Mesh m = merge(a, b);
    auto issues = check_mesh(m);
    EXPECT_EQ(std::count_if(issues.begin(), issues.end(),
                  [](const auto& x) { return x.kind == Kind::DuplicateNodes; }),
        4)
        << describe(issues);
    const auto& i = first_of(issues, Kind::DuplicateNodes);
    EXPECT_GE(i.node, 8);
    EXPECT_EQ(i.cell, 1);
    // Moved 1e-3 apart, a pair is a duplicate only under a tolerance larger than that.
    auto count_duplicates = [](const std::vector<ValidationIssue>& list) {
        return std::count_if(
            list.begin(), list.end(), [](const auto& x) { return x.kind == Kind::DuplicateNodes; });
    };
    m.rest[8].x() += 1e-3;
    EXPECT_EQ(count_duplicates(check_mesh(m)), 3);
    EXPECT_EQ(count_duplicates(check_mesh(m, { .duplicate_tol = 1e-2 })), 4);
    m.rest[8].x() -= 1e-3;
    // Tagged as a cut, the coincident nodes are what a cut makes: the mesh is valid.
    for (Face& f : m.faces) {
        const Vec3 c = (m.rest[std::size_t(f.nodes[0])] + m.rest[std::size_t(f.nodes[2])]) / 2;
        if (std::abs(c.x() - 1) < 1e-12)
            f.tag = FaceTag::Cut;
    }
    issues = check_mesh(m);
    EXPECT_TRUE(issues.empty()) << describe(issues);
    const SurfaceCheck s = check_boundary_surface(m);
    EXPECT_TRUE(s.ok());
    EXPECT_EQ(s.components, 2);
}

TEST(Validate, NonManifoldBoundaryEdge) {
    // Two cubes sharing only the edge (1,1,0)-(1,1,1).
    std::vector<Vec3> X = unit_cube_points();
    const auto Y = unit_cube_points(Vec3(1, 1, 0));
    X.insert(X.end(), Y.begin(), Y.end());
    // Reuse nodes 2 and 6 for the second cube's nodes 0 and 4.
    const Mesh m
        = Mesh::from_hexes(X, { { 0, 1, 2, 3, 4, 5, 6, 7 }, { 2, 9, 10, 11, 6, 13, 14, 15 } });
    auto opts = ValidationOptions {};
    opts.allow_unused_nodes = true; // nodes 8 and 12 are left over ...
    opts.check_duplicates = false; // ... and coincide with nodes 2 and 6
    const auto issues = check_mesh(m, opts);
    ASSERT_EQ(issues.size(), 1u) << describe(issues);
    EXPECT_EQ(issues[0].kind, Kind::NonManifoldBoundary);
    const bool names_edge = issues[0].message.find("(2, 6)") != std::string::npos
        || issues[0].message.find("(6, 2)") != std::string::npos;
    EXPECT_TRUE(names_edge) << issues[0].message;
    EXPECT_TRUE(has(check_mesh(m), Kind::UnusedNode));
    const SurfaceCheck s = check_boundary_surface(m);
    EXPECT_FALSE(s.closed);
    EXPECT_TRUE(s.oriented);
    EXPECT_EQ(s.nonmanifold_edges, 1);
    EXPECT_EQ(s.boundary_edges, 0);
    EXPECT_EQ(s.components, 1);
    EXPECT_THROW(validate(m, opts), MeshError);
}

TEST(Validate, BadAdjacency) {
    const Mesh grid = hex_grid({ Vec3::Zero(), Vec3::Ones(), { 2, 1, 1 } });
    Index interior = kNone;
    for (Index f = 0; f < grid.num_faces(); ++f)
        if (!grid.faces[std::size_t(f)].boundary())
            interior = f;
    ASSERT_NE(interior, kNone);
    {
        Mesh m = grid;
        m.faces[std::size_t(interior)].tag = FaceTag::Skin;
        const auto issues = check_mesh(m);
        ASSERT_FALSE(issues.empty());
        EXPECT_EQ(issues.front().kind, Kind::BadAdjacency);
        EXPECT_EQ(issues.front().face, interior);
    }
    {
        Mesh m = grid;
        const Index nb = m.faces[std::size_t(interior)].neighbour;
        auto& fs = m.cells[std::size_t(nb)].faces;
        fs.erase(std::find(fs.begin(), fs.end(), interior));
        const auto issues = check_mesh(m);
        const auto& i = first_of(issues, Kind::BadAdjacency);
        EXPECT_EQ(i.cell, nb);
        EXPECT_EQ(i.face, interior);
        EXPECT_NE(i.message.find("does not list"), std::string::npos) << i.message;
    }
    {
        Mesh m = grid;
        m.faces[0].nodes[1] = 99;
        EXPECT_EQ(check_mesh(m).front().kind, Kind::BadAdjacency);
    }
}

TEST(Validate, BadShapeTag) {
    Mesh m = tet_grid({ Vec3::Zero(), Vec3::Ones(), { 1, 1, 1 } });
    std::swap(m.cells[2].nodes[0], m.cells[2].nodes[1]);
    const auto issues = check_mesh(m);
    ASSERT_EQ(issues.size(), 1u) << describe(issues);
    EXPECT_EQ(issues[0].kind, Kind::BadShape);
    EXPECT_EQ(issues[0].cell, 2);
}

TEST(Validate, NonConvexCellOnlyWhenAsked) {
    // A prism over the concave quadrilateral (0,0) (2,1) (0,2) (0.5,1): planar faces, volume 1.5.
    std::vector<Vec3> X;
    for (double z : { 0.0, 1.0 })
        for (const auto& [x, y] :
            { std::pair { 0.0, 0.0 }, { 2.0, 1.0 }, { 0.0, 2.0 }, { 0.5, 1.0 } })
            X.emplace_back(x, y, z);
    const Mesh m = Mesh::from_hexes(X, { { 0, 1, 2, 3, 4, 5, 6, 7 } });
    EXPECT_NEAR(m.cell_volume(0), 1.5, 1e-14);
    EXPECT_TRUE(check_mesh(m).empty());
    const auto issues = check_mesh(m, { .require_convex = true });
    ASSERT_EQ(issues.size(), 1u);
    EXPECT_EQ(issues[0].kind, Kind::NonConvexCell);
}

TEST(BoundarySurface, TwoDisjointBlocks) {
    const Mesh a = hex_grid({ Vec3::Zero(), Vec3::Ones(), { 2, 2, 2 } });
    const Mesh b = tet_grid({ Vec3(3, 0, 0), Vec3(4, 1, 1), { 1, 2, 1 } });
    const Mesh m = merge(a, b);
    EXPECT_TRUE(check_mesh(m).empty());
    const SurfaceCheck s = check_boundary_surface(m);
    EXPECT_TRUE(s.ok());
    EXPECT_EQ(s.components, 2);
    EXPECT_EQ(m.count_components(), 2);
}

TEST(BoundarySurface, RemovedBoundaryFaceOpensIt) {
    Mesh m = hex_grid({ Vec3::Zero(), Vec3::Ones(), { 2, 2, 2 } });
    const Index f = m.boundary_faces()[3];
    const Index owner = m.faces[std::size_t(f)].owner;
    remove_face(m, f);
    const SurfaceCheck s = check_boundary_surface(m);
    EXPECT_FALSE(s.closed);
    EXPECT_TRUE(s.oriented);
    EXPECT_EQ(s.boundary_edges, 4);
    EXPECT_EQ(s.components, 1);
    EXPECT_NE(s.first_bad_face, kNone);
    const auto issues = check_mesh(m);
    EXPECT_EQ(first_of(issues, Kind::OpenCell).cell, owner);
    EXPECT_EQ(std::count_if(issues.begin(), issues.end(),
                  [](const auto& x) { return x.kind == Kind::NonManifoldBoundary; }),
        4);
}
