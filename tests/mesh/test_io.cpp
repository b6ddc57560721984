// Mesh files (issue 2 items 4 and 7): the readers accept the valid samples in tests/mesh/data
// (malformed files are in test_io_reject.cpp); the VTU writer's output is read back by meshio
// (tests/mesh/meshio_check.py) and compared with the C++ values; the OBJ writer round-trips.
#include "io_test_util.hpp"
#include "polycut/common/error.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/mesh/io.hpp"
#include "polycut/mesh/validate.hpp"

#include <algorithm>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sstream>

using namespace polycut;
using namespace polycut::mesh;
namespace fs = std::filesystem;
using namespace polycut::test;

namespace {

void expect_same_mesh(const Mesh& a, const Mesh& b) {
    ASSERT_EQ(a.num_nodes(), b.num_nodes());
    ASSERT_EQ(a.num_cells(), b.num_cells());
    ASSERT_EQ(a.num_faces(), b.num_faces());
    for (Index n = 0; n < a.num_nodes(); ++n)
        EXPECT_EQ(a.rest[std::size_t(n)], b.rest[std::size_t(n)]) << "node " << n;
    for (Index c = 0; c < a.num_cells(); ++c) {
        EXPECT_EQ(a.cells[std::size_t(c)].nodes, b.cells[std::size_t(c)].nodes) << "cell " << c;
        EXPECT_EQ(a.cells[std::size_t(c)].faces, b.cells[std::size_t(c)].faces) << "cell " << c;
        EXPECT_EQ(a.cells[std::size_t(c)].shape, b.cells[std::size_t(c)].shape) << "cell " << c;
    }
    for (Index f = 0; f < a.num_faces(); ++f) {
        EXPECT_EQ(a.faces[std::size_t(f)].nodes, b.faces[std::size_t(f)].nodes);
        EXPECT_EQ(a.faces[std::size_t(f)].owner, b.faces[std::size_t(f)].owner);
        EXPECT_EQ(a.faces[std::size_t(f)].neighbour, b.faces[std::size_t(f)].neighbour);
    }
}

// ---- meshio ----

/// Runs tests/mesh/meshio_check.py on a .vtu file and parses its JSON.
/// Runs tests/mesh/meshio_check.py once on several .vtu files (Python and meshio start slowly)
/// and returns its JSON summary of each, in order.
std::vector<nlohmann::json> meshio_read(const std::vector<fs::path>& files) {
    if (files.empty())
        return {};
    const fs::path out = files.front().string() + ".json";
    const fs::path err = files.front().string() + ".stderr";
    std::string cmd = "/usr/bin/python3 " POLYCUT_SOURCE_DIR "/tests/mesh/meshio_check.py";
    for (const fs::path& f : files)
        cmd += " '" + f.string() + "'";
    cmd += " > '" + out.string() + "' 2> '" + err.string() + "'";
    const int status = std::system(cmd.c_str());
    if (status != 0) {
        ADD_FAILURE() << "meshio_check.py failed (status " << status << "):\n" << read_text(err);
        return std::vector<nlohmann::json>(files.size());
    }
    return nlohmann::json::parse(read_text(out)).get<std::vector<nlohmann::json>>();
}

double frobenius(const MatX& m) {
    return m.norm();
}

/// Compares meshio's view of a written file with the mesh, world positions and fields.
void expect_meshio_agrees(const nlohmann::json& j, const Mesh& mesh, const std::vector<Vec3>& world,
    const std::vector<Field>& point_fields, const std::vector<Field>& cell_fields) {
    ASSERT_FALSE(j.is_null());
    EXPECT_EQ(j["points"].get<Index>(), mesh.num_nodes());
    EXPECT_EQ(j["cells"].get<Index>(), mesh.num_cells());
    // Cell volumes from the file's points and cells: the same multiset as in C++ (to 1e-12
    // relative, the text round-trips doubles exactly; only the summation order differs).
    std::vector<double> volumes;
    for (Index c = 0; c < mesh.num_cells(); ++c)
        volumes.push_back(geometry::polyhedron_volume(world, mesh.cell_face_loops(c)));
    std::sort(volumes.begin(), volumes.end());
    const auto read_volumes = j["volumes"].get<std::vector<double>>();
    ASSERT_EQ(read_volumes.size(), volumes.size());
    for (std::size_t i = 0; i < volumes.size(); ++i)
        EXPECT_NEAR(read_volumes[i], volumes[i], 1e-12 * std::abs(volumes[i])) << i;
    // Polyhedral files say which mesh cell each file cell is: compare cell by cell.
    if (j.contains("volumes_by_cell")) {
        const auto by_cell = j["volumes_by_cell"].get<std::vector<double>>();
        ASSERT_EQ(by_cell.size(), std::size_t(mesh.num_cells()));
        for (Index c = 0; c < mesh.num_cells(); ++c) {
            const double v = geometry::polyhedron_volume(world, mesh.cell_face_loops(c));
            EXPECT_NEAR(by_cell[std::size_t(c)], v, 1e-12 * std::abs(v)) << "cell " << c;
        }
    }
    auto compare = [](const nlohmann::json& summary, const Field& f) {
        SCOPED_TRACE(f.name);
        ASSERT_TRUE(summary.is_object());
        EXPECT_EQ(summary["components"].get<Eigen::Index>(), f.values.cols());
        EXPECT_EQ(summary["rows"].get<Eigen::Index>(), f.values.rows());
        EXPECT_NEAR(
            summary["norm"].get<double>(), frobenius(f.values), 1e-12 * frobenius(f.values));
        const auto sums = summary["sums"].get<std::vector<double>>();
        for (Eigen::Index k = 0; k < f.values.cols(); ++k)
            EXPECT_NEAR(sums[std::size_t(k)], f.values.col(k).sum(),
                1e-12 * f.values.col(k).cwiseAbs().sum());
    };
    for (const Field& f : point_fields)
        compare(j["point_data"][f.name], f);
    for (const Field& f : cell_fields)
        compare(j["cell_data"][f.name], f);
}

/// World positions x = A X + t of an affine map with det A = 1.2 * 0.9 * 1.1 (rotated).
std::vector<Vec3> affine_world(const Mesh& m, Mat3& A) {
    A = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix()
        * Vec3(1.2, 0.9, 1.1).asDiagonal();
    std::vector<Vec3> x;
    for (const Vec3& X : m.rest)
        x.push_back(A * X + Vec3(0.01, -0.02, 0.03));
    return x;
}

/// Displacement (#N x 3) [m], and per-cell fields: von_mises (#C x 1) [Pa], stress (#C x 9) [Pa].
std::vector<Field> displacement_field(const Mesh& m, const std::vector<Vec3>& world) {
    Field u { "displacement", MatX(m.num_nodes(), 3) };
    for (Index n = 0; n < m.num_nodes(); ++n)
        u.values.row(n) = (world[std::size_t(n)] - m.rest[std::size_t(n)]).transpose();
    return { u };
}

std::vector<Field> stress_fields(const Mesh& m) {
    Field vm { "von_mises", MatX(m.num_cells(), 1) };
    Field s { "stress", MatX(m.num_cells(), 9) };
    for (Index c = 0; c < m.num_cells(); ++c) {
        vm.values(c, 0) = 1000.0 + 17.5 * c;
        for (int k = 0; k < 9; ++k)
            s.values(c, k) = std::sin(0.3 * c + k) * 1e4;
    }
    return { vm, s };
}

/// A unit cube whose top face is split into two coplanar quads (so its front and back faces are
/// pentagons), a triangular prism glued to its +x face, and, apart at x in [3, 4], a Kuhn-6 cube.
Mesh polyhedral_sample() {
    std::vector<Vec3> X { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
        { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 }, { 0.5, 0, 1 }, { 0.5, 1, 1 }, { 1.5, 0, 0.5 },
        { 1.5, 1, 0.5 } };
    std::vector<std::vector<std::vector<Index>>> cells {
        { { 0, 3, 2, 1 }, { 4, 8, 9, 7 }, { 8, 5, 6, 9 }, { 0, 1, 5, 8, 4 }, { 1, 2, 6, 5 },
            { 2, 3, 7, 9, 6 }, { 3, 0, 4, 7 } },
        { { 5, 6, 2, 1 }, { 1, 10, 5 }, { 2, 6, 11 }, { 1, 2, 11, 10 }, { 5, 10, 11, 6 } },
    };
    const Mesh tets = tet_grid({ Vec3(3, 0, 0), Vec3(4, 1, 1), { 1, 1, 1 } });
    const Index offset = Index(X.size());
    X.insert(X.end(), tets.rest.begin(), tets.rest.end());
    for (Index c = 0; c < tets.num_cells(); ++c) {
        auto loops = tets.cell_face_loops(c);
        for (auto& loop : loops)
            for (Index& n : loop)
                n += offset;
        cells.push_back(loops);
    }
    return Mesh::from_polyhedra(X, cells);
}
} // namespace

// ---- readers: valid files ----

TEST(ReadGmsh, V2AndV41GiveTheSameMesh) {
    const Mesh v2 = read_gmsh(kData + "blocks_v2.msh");
    const Mesh v4 = read_volume_mesh(kData + "blocks_v41.msh");
    // 12 hex nodes + 8 tet nodes; the node used only by a point element is dropped.
    EXPECT_EQ(v2.num_nodes(), 20);
    EXPECT_EQ(v2.num_cells(), 7);
    EXPECT_EQ(std::count_if(v2.cells.begin(), v2.cells.end(),
                  [](const Cell& c) { return c.shape == CellShape::Hex; }),
        2);
    EXPECT_EQ(std::count_if(v2.cells.begin(), v2.cells.end(),
                  [](const Cell& c) { return c.shape == CellShape::Tet; }),
        5);
    EXPECT_NEAR(v2.rest_volume(), 3.0, 1e-14); // two unit hexes and a unit cube of five tets
    for (Index c = 0; c < v2.num_cells(); ++c)
        EXPECT_GT(v2.cell_volume(c), 0) << c; // the inverted tet in the file was reordered
    EXPECT_NO_THROW(validate(v2));
    const SurfaceCheck s = check_boundary_surface(v2);
    EXPECT_TRUE(s.ok());
    EXPECT_EQ(s.components, 2);
    expect_same_mesh(v2, v4);
}

TEST(ReadTetgen, OneBasedWithAttributesMarkersAndComments) {
    for (const char* name : { "cube.node", "cube.ele" }) {
        const Mesh m = read_volume_mesh(kData + name);
        EXPECT_EQ(m.num_nodes(), 8);
        EXPECT_EQ(m.num_cells(), 6);
        EXPECT_NEAR(m.rest_volume(), 1e-3, 1e-18);
        EXPECT_NEAR(m.rest[6].x(), 0.1, 1e-17); // point 7 (1-based) is the far corner
        EXPECT_NO_THROW(validate(m));
    }
    const Mesh m = read_tetgen(kData + "cube"); // base name
    EXPECT_EQ(m.num_cells(), 6);
    EXPECT_TRUE(check_boundary_surface(m).ok());
}

TEST(ReadTetgen, ZeroBasedTenNodeTet) {
    const Mesh m = read_tetgen(kData + "tet10.ele");
    EXPECT_EQ(m.num_nodes(), 4); // mid-edge nodes dropped
    EXPECT_EQ(m.num_cells(), 1);
    EXPECT_NEAR(m.rest_volume(), 1.0 / 6.0, 1e-15);
    EXPECT_EQ(m.cells[0].shape, CellShape::Tet);
}
// ---- VTU writer, read back by meshio ----

TEST(WriteVtu, ReadBackByMeshio) {
    const fs::path dir = test_dir();
    // 1. A deformed tet grid with a displacement point field and two cell fields.
    const Mesh grid = tet_grid({ Vec3::Zero(), Vec3(0.1, 0.2, 0.1), { 2, 3, 2 } });
    Mat3 A;
    const auto grid_world = affine_world(grid, A);
    const auto grid_point_fields = displacement_field(grid, grid_world);
    const auto grid_cell_fields = stress_fields(grid);
    write_vtu((dir / "grid.vtu").string(), grid, &grid_world, grid_point_fields, grid_cell_fields);
    EXPECT_FALSE(fs::exists(dir / "grid.vtu.part"));

    // 2. Tets and hexes as VTK_TETRA / VTK_HEXAHEDRON (no polyhedra, so no `faces` arrays).
    const Mesh blocks = read_gmsh(kData + "blocks_v2.msh");
    const auto blocks_cell_fields = stress_fields(blocks);
    write_vtu((dir / "blocks.vtu").string(), blocks, &blocks.rest, {}, blocks_cell_fields);
    EXPECT_EQ(read_text(dir / "blocks.vtu").find("faceoffsets"), std::string::npos);

    // 3. Polyhedra (split-top cube, prism) and tets, deformed, with fields. Auto writes every cell
    // as VTK_POLYHEDRON, the only layout meshio 5 reads.
    const Mesh poly = polyhedral_sample();
    ASSERT_TRUE(check_mesh(poly).empty());
    ASSERT_EQ(poly.cells[0].shape, CellShape::Polyhedron);
    ASSERT_EQ(poly.cells[1].shape, CellShape::Polyhedron);
    EXPECT_NEAR(poly.cell_volume(0), 1.0, 1e-15);
    EXPECT_NEAR(poly.cell_volume(1), 0.25, 1e-15);
    Mat3 B;
    const auto poly_world = affine_world(poly, B);
    const auto poly_point_fields = displacement_field(poly, poly_world);
    const auto poly_cell_fields = stress_fields(poly);
    write_vtu((dir / "poly.vtu").string(), poly, &poly_world, poly_point_fields, poly_cell_fields);

    // 4. A pure tet grid forced to polyhedra.
    const Mesh cube = tet_grid({ Vec3::Zero(), Vec3::Ones(), { 1, 1, 1 } });
    write_vtu((dir / "allpoly.vtu").string(), cube, nullptr, {}, {}, VtuCellTypes::AllPolyhedra);

    const auto j = meshio_read(
        { dir / "grid.vtu", dir / "blocks.vtu", dir / "poly.vtu", dir / "allpoly.vtu" });
    ASSERT_EQ(j.size(), 4u);
    {
        SCOPED_TRACE("grid");
        expect_meshio_agrees(j[0], grid, grid_world, grid_point_fields, grid_cell_fields);
        EXPECT_EQ(j[0]["types"]["tetra"].get<Index>(), grid.num_cells());
        double total = 0; // deformed volume = det A * rest volume
        for (double v : j[0]["volumes"].get<std::vector<double>>())
            total += v;
        EXPECT_NEAR(total, A.determinant() * 0.1 * 0.2 * 0.1, 1e-15);
    }
    {
        SCOPED_TRACE("blocks");
        expect_meshio_agrees(j[1], blocks, blocks.rest, {}, blocks_cell_fields);
        EXPECT_EQ(j[1]["types"]["hexahedron"].get<Index>(), 2);
        EXPECT_EQ(j[1]["types"]["tetra"].get<Index>(), 5);
    }
    {
        SCOPED_TRACE("poly");
        expect_meshio_agrees(j[2], poly, poly_world, poly_point_fields, poly_cell_fields);
        EXPECT_EQ(j[2]["types"]["polyhedron10"].get<Index>(), 1); // split-top cube
        EXPECT_EQ(j[2]["types"]["polyhedron6"].get<Index>(), 1); // prism
        EXPECT_EQ(j[2]["types"]["polyhedron4"].get<Index>(), 6); // tets written as polyhedra
        EXPECT_TRUE(j[2].contains("volumes_by_cell"));
        double total = 0;
        for (double v : j[2]["volumes"].get<std::vector<double>>())
            total += v;
        EXPECT_NEAR(total, B.determinant() * 2.25, 1e-13);
    }
    {
        SCOPED_TRACE("allpoly");
        expect_meshio_agrees(j[3], cube, cube.rest, {}, {});
        EXPECT_EQ(j[3]["types"]["polyhedron4"].get<Index>(), 6);
    }
}

TEST(WriteVtu, NativeKeepsTetsNextToPolyhedra) {
    const fs::path dir = test_dir();
    const Mesh m = polyhedral_sample();
    write_vtu((dir / "native.vtu").string(), m, nullptr, {}, {}, VtuCellTypes::Native);
    const std::string text = read_text(dir / "native.vtu");
    EXPECT_NE(text.find("faceoffsets"), std::string::npos);
    EXPECT_NE(text.find(" 42 42 10 10 10 10 10 10\n"), std::string::npos) << "cell types";
    EXPECT_NE(text.find(" -1 -1 -1 -1 -1 -1\n"), std::string::npos) << "faceoffsets of the tets";
    EXPECT_EQ(text.find("polycut_cell"), std::string::npos);
}

TEST(WriteVtu, RejectsBadInput) {
    const fs::path dir = test_dir();
    const Mesh m = tet_grid({ Vec3::Zero(), Vec3::Ones(), { 1, 1, 1 } });
    try {
        write_vtu("/nonexistent-dir/x.vtu", m);
        FAIL() << "wrote into a missing directory";
    } catch (const FileError& e) {
        EXPECT_EQ(e.path(), "/nonexistent-dir/x.vtu");
        EXPECT_NE(std::string(e.what()).find("cannot open for writing"), std::string::npos);
    }
    const std::vector<Field> short_field { { "u", MatX::Zero(m.num_nodes() - 1, 3) } };
    EXPECT_THROW(write_vtu((dir / "a.vtu").string(), m, nullptr, short_field), InputError);
    const std::vector<Field> bad_name { { "a<b", MatX::Zero(m.num_cells(), 1) } };
    EXPECT_THROW(write_vtu((dir / "a.vtu").string(), m, nullptr, {}, bad_name), InputError);
    const std::vector<Vec3> few(3, Vec3::Zero());
    EXPECT_THROW(write_vtu((dir / "a.vtu").string(), m, &few), InputError);
    EXPECT_FALSE(fs::exists(dir / "a.vtu"));
}

// ---- OBJ writer ----

TEST(WriteObj, WritesOneBasedFaces) {
    const fs::path dir = test_dir();
    MatX3 V(4, 3);
    V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.25;
    MatX3i T(4, 3);
    T << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2;
    write_obj((dir / "tet.obj").string(), V, T);
    std::istringstream in(read_text(dir / "tet.obj"));
    std::string line;
    std::vector<std::string> v_lines, f_lines;
    while (std::getline(in, line)) {
        if (line.rfind("v ", 0) == 0)
            v_lines.push_back(line);
        if (line.rfind("f ", 0) == 0)
            f_lines.push_back(line);
    }
    ASSERT_EQ(v_lines.size(), 4u);
    ASSERT_EQ(f_lines.size(), 4u);
    EXPECT_EQ(v_lines[3], "v 0 0 0.25");
    EXPECT_EQ(f_lines[0], "f 1 3 2");
    EXPECT_EQ(f_lines[3], "f 1 4 3");

    const std::vector<Vec3> P { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } };
    write_obj((dir / "tri.obj").string(), P, { { 0, 1, 2 } });
    EXPECT_NE(read_text(dir / "tri.obj").find("f 1 2 3\n"), std::string::npos);
    EXPECT_THROW(write_obj((dir / "bad.obj").string(), P, { { 0, 1, 3 } }), InputError);
    EXPECT_FALSE(fs::exists(dir / "bad.obj"));
    EXPECT_THROW(write_obj("/nonexistent-dir/x.obj", P, { { 0, 1, 2 } }), FileError);
}
