// Splitting the embedded surface along a cut (issue 15 item 2, decision 0033): a sphere embedded
// in a hex or polyhedral box that the cutter splits along a plane. After the split the surface
// is closed and consistently oriented (every directed edge once, its reverse once), encloses the
// sphere's volume, its lips (tag 2) lie in the cut plane, a vertex on the cut is embedded on its
// own side, and affine motions of the nodes still move every vertex exactly.
#include "polycut/common/error.hpp"
#include "polycut/contact/triangle_mesh_distance.hpp"
#include "polycut/cut/cutter.hpp"
#include "polycut/embed/split.hpp"
#include "polycut/mesh/builders.hpp"
#include "uv_sphere.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <map>
#include <numeric>
#include <random>
#include <string>

using namespace polycut;
using test::uv_sphere;

namespace {
/// How often each directed edge of the triangles appears.
std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_counts(
    const std::vector<std::uint32_t>& tri) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> count;
    for (std::size_t t = 0; t < tri.size(); t += 3)
        for (int k = 0; k < 3; ++k)
            ++count[{ tri[t + std::size_t(k)], tri[t + std::size_t((k + 1) % 3)] }];
    return count;
}

/// Directed edges that do not appear exactly once with their reverse exactly once.
int open_edges(const std::vector<std::uint32_t>& tri) {
    const auto count = edge_counts(tri);
    int bad = 0;
    for (const auto& [e, n] : count) {
        const auto it = count.find({ e.second, e.first });
        bad += n != 1 || it == count.end() || it->second != 1;
    }
    return bad;
}

/// Directed edges used a different number of times than their reverse: holes (a closed surface
/// may still have edges that four triangles share, two each way, where the material on two
/// sides of a crack front touches along that edge).
int unbalanced_edges(const std::vector<std::uint32_t>& tri) {
    const auto count = edge_counts(tri);
    int bad = 0;
    for (const auto& [e, n] : count) {
        const auto it = count.find({ e.second, e.first });
        bad += it == count.end() || it->second != n;
    }
    return bad;
}

/// Enclosed volume (divergence theorem) of triangles over points.
double volume(const std::vector<Vec3>& p, const std::vector<std::uint32_t>& tri) {
    double v = 0;
    for (std::size_t t = 0; t < tri.size(); t += 3)
        v += p[tri[t]].dot(p[tri[t + 1]].cross(p[tri[t + 2]])) / 6.0;
    return v;
}

/// Area of polygon `subject` clipped to the convex, counter-clockwise polygon `clip`
/// (Sutherland-Hodgman; right for any simple subject, as far as the area goes), in 2D.
double clipped_area(
    std::vector<Eigen::Vector2d> subject, const std::vector<Eigen::Vector2d>& clip) {
    for (std::size_t i = 0; i < clip.size() && !subject.empty(); ++i) {
        const Eigen::Vector2d a = clip[i], b = clip[(i + 1) % clip.size()];
        auto side = [&](const Eigen::Vector2d& p) {
            const Eigen::Vector2d d = b - a, q = p - a;
            return d.x() * q.y() - d.y() * q.x();
        };
        std::vector<Eigen::Vector2d> out;
        for (std::size_t j = 0; j < subject.size(); ++j) {
            const Eigen::Vector2d p = subject[j], q = subject[(j + 1) % subject.size()];
            const double sp = side(p), sq = side(q);
            if (sp >= 0)
                out.push_back(p);
            if ((sp >= 0) != (sq >= 0))
                out.push_back(p + (q - p) * (sp / (sp - sq)));
        }
        subject = std::move(out);
    }
    double area = 0;
    for (std::size_t j = 0; j < subject.size(); ++j) {
        const Eigen::Vector2d& p = subject[j];
        const Eigen::Vector2d& q = subject[(j + 1) % subject.size()];
        area += p.x() * q.y() - p.y() * q.x();
    }
    return 0.5 * std::abs(area);
}

/// The section of a convex triangulated surface by the plane y = y0, as a counter-clockwise
/// convex polygon in (x, z): the hull of where its edges cross the plane.
std::vector<Eigen::Vector2d> section_at_y(
    const std::vector<Vec3>& v, const std::vector<std::array<Index, 3>>& t, double y0) {
    std::vector<Eigen::Vector2d> pts;
    for (const auto& tri : t)
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = v[std::size_t(tri[std::size_t(k)])];
            const Vec3& q = v[std::size_t(tri[std::size_t((k + 1) % 3)])];
            if ((p.y() - y0) * (q.y() - y0) < 0) {
                const Vec3 x = p + (q - p) * ((y0 - p.y()) / (q.y() - p.y()));
                pts.emplace_back(x.x(), x.z());
            }
        }
    // Andrew's monotone chain.
    std::sort(pts.begin(), pts.end(), [](const auto& a, const auto& b) {
        return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
    });
    auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
        return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
    };
    std::vector<Eigen::Vector2d> hull(2 * pts.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0)
            --k;
        hull[k++] = pts[i];
    }
    for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0)
            --k;
        hull[k++] = pts[i];
    }
    hull.resize(k - 1);
    return hull;
}

/// The open or over-used edges of `e` with their ends' rest positions and lip flags, for a
/// failure message.
std::string describe_open_edges(const embed::Embedding& e) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> uses;
    for (std::size_t t = 0; t < e.triangles.size(); t += 3)
        for (int k = 0; k < 3; ++k)
            uses[{ e.triangles[t + std::size_t(k)], e.triangles[t + std::size_t((k + 1) % 3)] }]
                .push_back(t / 3);
    std::string out;
    for (const auto& [edge, ts] : uses) {
        const auto back = uses.find({ edge.second, edge.first });
        if (ts.size() == 1 && back != uses.end() && back->second.size() == 1)
            continue;
        const Vec3 &a = e.rest[edge.first], &b = e.rest[edge.second];
        char line[256];
        std::snprintf(line, sizeof line, "%u-%u (%.17g %.17g %.17g)-(%.17g %.17g %.17g) lip %d\n",
            edge.first, edge.second, a.x(), a.y(), a.z(), b.x(), b.y(), b.z(),
            int(e.lip[ts.front()]));
        out += line;
    }
    return out;
}

struct Fixture {
    mesh::Mesh mesh;
    std::vector<Vec3> sphere;
    std::vector<std::array<Index, 3>> triangles;
    std::unique_ptr<contact::TriangleMeshDistance> inside;
    double sphere_volume = 0;
    embed::Embedding e;
    embed::SplitState state;
    std::vector<Index> cut_faces;
    basis::PolyBasis poly = basis::PolyBasis::MeanValue;

    explicit Fixture(int kind) {
        mesh::BoxGrid g;
        g.lo = Vec3(-0.02, -0.02, 0);
        g.hi = Vec3(0.02, 0.02, 0.04);
        g.cells = Eigen::Vector3i(4, 4, 4);
        mesh = kind == 0 ? mesh::hex_grid(g) : mesh::merged_hex_grid(g, 0.6, 3);
        uv_sphere(Vec3(0, 0, 0.02), 0.019, 24, 48, sphere, triangles);
        inside = std::make_unique<contact::TriangleMeshDistance>(sphere, triangles);
        sphere_volume = inside->volume();
        e = embed::embed_surface(mesh, sphere, triangles, poly);
    }
    /// Cuts the mesh along the plane y = y0 from z = z0 up, then splits the surface.
    embed::SplitReport cut(double y0, double z0) {
        const std::vector<cut::Triangle> blade { { Vec3(-0.03, y0, 0.05), Vec3(0.03, y0, 0.05),
                                                     Vec3(-0.03, y0, z0) },
            { Vec3(0.03, y0, 0.05), Vec3(0.03, y0, z0), Vec3(-0.03, y0, z0) } };
        const cut::CutReport r = cut::cut_rest(mesh, blade);
        EXPECT_TRUE(r.topology_changed);
        return split_after(r);
    }
    /// Splits the surface after the mesh was cut as `r` says.
    embed::SplitReport split_after(const cut::CutReport& r) {
        cut_faces = r.cut_faces;
        // Vertices in the cells the cut changed, as the simulation passes them.
        std::vector<std::uint32_t> moved;
        for (std::size_t v = 0; v < e.cells.size(); ++v) {
            Index c = e.cells[v];
            if (!r.cell_map.empty())
                c = e.cells[v] = r.cell_map[std::size_t(c)];
            if (c == kNone || std::binary_search(r.changed_cells.begin(), r.changed_cells.end(), c))
                moved.push_back(std::uint32_t(v));
        }
        embed::SplitReport s = split({ r.cut_faces, r.duplicated, moved });
        if (s.overlaps_earlier_cut) {
            // Over skin an earlier cut split: anew, along all the Cut faces (as the sim does).
            e = embed::embed_surface(mesh, sphere, triangles, poly);
            state = {};
            cut_faces.clear();
            for (Index face = 0; face < mesh.num_faces(); ++face)
                if (mesh.faces[std::size_t(face)].boundary()
                    && mesh.faces[std::size_t(face)].tag == mesh::FaceTag::Cut)
                    cut_faces.push_back(face);
            s = split({ cut_faces, {}, {} });
            s.overlaps_earlier_cut = true;
        }
        return s;
    }
    embed::SplitReport split(const embed::CutChange& change) {
        return embed::split_along_cut(
            e, state, mesh, change,
            [&](const Vec3& X) {
                Vec3 n;
                return inside->signed_distance(X, n) < 0;
            },
            poly);
    }
    std::vector<Vec3> deformed(const std::vector<Vec3>& x) const {
        std::vector<Vec3> out;
        for (std::size_t v = 0; v < e.rest.size(); ++v)
            out.push_back(embed::deformed_vertex(e, x, v));
        return out;
    }
};

class Split : public ::testing::TestWithParam<int> { };
} // namespace

TEST_P(Split, LipsAreClosedFlatAndTaggedAndTheVolumeIsKept) {
    Fixture f(GetParam());
    const std::size_t skin_before = f.e.triangles.size() / 3;
    const embed::SplitReport r = f.cut(0.001, 0.021);
    EXPECT_GT(r.cut_triangles, 0u);
    EXPECT_GT(r.lip_triangles_added, 0u);
    // Local: only triangles near the cut were corefined.
    EXPECT_LT(r.patch_triangles, skin_before / 2);
    ASSERT_EQ(f.e.lip.size(), f.e.triangles.size() / 3);
    EXPECT_EQ(open_edges(f.e.triangles), 0);
    // Zero-thickness lips on both sides: the enclosed volume is the sphere's (rounding only).
    EXPECT_NEAR(volume(f.e.rest, f.e.triangles), f.sphere_volume, 1e-12 * f.sphere_volume);
    double lip_area = 0;
    for (std::size_t t = 0; t < f.e.lip.size(); ++t) {
        if (!f.e.lip[t])
            continue;
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(f.e.rest[f.e.triangles[3 * t + std::size_t(k)]].y(), 0.001, 1e-12);
        const Vec3 &a = f.e.rest[f.e.triangles[3 * t]], &b = f.e.rest[f.e.triangles[3 * t + 1]],
                   &c = f.e.rest[f.e.triangles[3 * t + 2]];
        lip_area += 0.5 * (b - a).cross(c - a).norm();
    }
    // Both lips: twice the sphere's section above the cut's front. The front lies within the
    // cell layer z in [0.02, 0.03] (where the cutter ends the crack), so the section lies
    // between the disc segment above z = 0.03 and the one above z = 0.02 (radius of the
    // section circle rho = sqrt(r^2 - y0^2)).
    const double rho = std::sqrt(0.019 * 0.019 - 0.001 * 0.001);
    auto segment = [&](double h) { // area of the disc of radius rho above a chord at height h
        return rho * rho * std::acos(h / rho) - h * std::sqrt(rho * rho - h * h);
    };
    EXPECT_GT(lip_area, 2 * segment(0.01) * 0.98);
    EXPECT_LT(lip_area, 2 * segment(0.0) * 1.001);
    // Exactly: the lips are the mesh's Cut faces (both sides) clipped to the detailed surface,
    // so their area is the sum over those faces of the face's overlap with the (convex) section
    // of the triangulated sphere by the cut plane, computed here independently in 2D.
    const std::vector<Eigen::Vector2d> section = section_at_y(f.sphere, f.triangles, 0.001);
    double expected = 0, cut_area = 0;
    for (const Index face : f.cut_faces) {
        std::vector<Eigen::Vector2d> loop;
        for (const Index n : f.mesh.faces[std::size_t(face)].nodes) {
            loop.emplace_back(f.mesh.rest[std::size_t(n)].x(), f.mesh.rest[std::size_t(n)].z());
        }
        expected += clipped_area(loop, section);
        cut_area += clipped_area(loop, { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } });
    }
    EXPECT_GT(cut_area, lip_area); // the cells reach past the skin
    EXPECT_NEAR(lip_area, expected, 1e-9 * expected);
}

TEST_P(Split, AVertexOnTheCutFollowsItsOwnSide) {
    Fixture f(GetParam());
    f.cut(0.001, 0.021);
    // Every vertex on the cut plane embedded in a cell that lies wholly on one side: that side
    // is its probe's side.
    int checked = 0;
    for (std::size_t v = 0; v < f.e.rest.size(); ++v) {
        if (std::abs(f.e.rest[v].y() - 0.001) > 1e-12 || f.e.probes[v] == f.e.rest[v])
            continue; // off the cut, or at the crack front (one copy, both sides' cells)
        double lo = 1, hi = -1;
        for (const Index n : f.mesh.cells[std::size_t(f.e.cells[v])].nodes) {
            lo = std::min(lo, f.mesh.rest[std::size_t(n)].y() - 0.001);
            hi = std::max(hi, f.mesh.rest[std::size_t(n)].y() - 0.001);
        }
        if (lo < -1e-12 && hi > 1e-12)
            continue; // a cell the cut did not reach
        const double side = f.e.probes[v].y() - 0.001;
        ASSERT_NE(side, 0.0) << v;
        EXPECT_EQ(side > 0, hi > 1e-12) << v;
        ++checked;
    }
    EXPECT_GT(checked, 50);
    // Pulling the +y side's nodes 2 mm away opens the cut: every vertex moves by 0 or 2 mm in y
    // as its cell's side says, so the skin does not stretch across the opening.
    std::vector<Vec3> x = f.mesh.rest;
    std::vector<char> plus(x.size(), 0), minus(x.size(), 0);
    for (const auto& cell : f.mesh.cells) {
        Vec3 c = Vec3::Zero();
        for (const Index n : cell.nodes)
            c += f.mesh.rest[std::size_t(n)] / double(cell.nodes.size());
        for (const Index n : cell.nodes)
            (c.y() > 0.001 ? plus : minus)[std::size_t(n)] = 1;
    }
    for (std::size_t n = 0; n < x.size(); ++n)
        if (plus[n] && !minus[n])
            x[n].y() += 0.002;
    const std::vector<Vec3> moved = f.deformed(x);
    int opened = 0;
    for (std::size_t v = 0; v < f.e.rest.size(); ++v) {
        if (std::abs(f.e.rest[v].y() - 0.001) > 1e-12 || f.e.rest[v].z() < 0.031)
            continue; // above z = 0.031 every cell is cut through: the two lips part
        const double dy = moved[v].y() - f.e.rest[v].y();
        EXPECT_NEAR(dy, f.e.probes[v].y() > 0.001 ? 0.002 : 0.0, 1e-9) << v;
        ++opened;
    }
    EXPECT_GT(opened, 20);
}

TEST_P(Split, AffineMotionsStayExactAfterTheSplit) {
    Fixture f(GetParam());
    f.cut(0.001, 0.021);
    Mat3 A;
    A << 1.1, 0.2, -0.1, 0.05, 0.9, 0.3, -0.2, 0.1, 1.2;
    const Vec3 b(0.01, -0.02, 0.03);
    std::vector<Vec3> x;
    for (const Vec3& X : f.mesh.rest)
        x.push_back(A * X + b);
    const std::vector<Vec3> moved = f.deformed(x);
    double worst = 0;
    for (std::size_t v = 0; v < f.e.rest.size(); ++v)
        worst = std::max(worst, (moved[v] - (A * f.e.rest[v] + b)).norm());
    EXPECT_LT(worst, 1e-12);
}

TEST_P(Split, ACutCarriedOnDeeperKeepsTheSurfaceClosed) {
    // A progressive stroke: the same plane again from z = 0.011 up (the blade went deeper), so
    // the new Cut faces adjoin the first cut's front and separate its nodes. The lips of both
    // cuts join, the surface stays closed and oriented, and affine motions stay exact.
    Fixture f(GetParam());
    f.cut(0.001, 0.021);
    const std::size_t lips_before = std::size_t(std::count(f.e.lip.begin(), f.e.lip.end(), 1));
    const embed::SplitReport s = f.cut(0.001, 0.011);
    EXPECT_GT(s.lip_triangles_added, 0u);
    EXPECT_GT(std::size_t(std::count(f.e.lip.begin(), f.e.lip.end(), 1)), lips_before);
    EXPECT_EQ(open_edges(f.e.triangles), 0) << describe_open_edges(f.e);
    EXPECT_NEAR(volume(f.e.rest, f.e.triangles), f.sphere_volume, 1e-12 * f.sphere_volume);
    std::vector<Vec3> x;
    for (const Vec3& X : f.mesh.rest)
        x.push_back(Vec3(0.9 * X.x() + 0.1 * X.z(), X.y() + 0.2 * X.x(), 1.1 * X.z()));
    const std::vector<Vec3> moved = f.deformed(x);
    for (std::size_t v = 0; v < f.e.rest.size(); ++v) {
        const Vec3& X = f.e.rest[v];
        ASSERT_LT(
            (moved[v] - Vec3(0.9 * X.x() + 0.1 * X.z(), X.y() + 0.2 * X.x(), 1.1 * X.z())).norm(),
            1e-12)
            << v;
    }
}

INSTANTIATE_TEST_SUITE_P(Embed, Split, ::testing::Values(0, 1),
    [](const ::testing::TestParamInfo<int>& i) { return i.param == 0 ? "Q1" : "MeanValue"; });

TEST(SplitRandom, PlanesAtRandomKeepTheSurfaceClosedAndExact) {
    // Blades in random planes through the sphere (seeded; a third of them in planes of grid
    // faces or 1 nm off one, the degenerate cases), each ending at a random depth, and half of
    // them carried on deeper by a second call: after every call the surface is closed and
    // oriented (every directed edge as often as its reverse), encloses the sphere's volume, and
    // moves exactly under an affine motion.
    std::mt19937 rng(20261203);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int cases = 0, carried = 0, refused = 0, non_manifold = 0;
    for (int trial = 0; trial < 24; ++trial) {
        Fixture f(trial % 2);
        Vec3 n(u(rng), u(rng), 0.3 * u(rng));
        double offset = 0.008 * u(rng);
        if (trial % 3 == 0) { // a plane of grid faces (x or y = a multiple of 1 cm), or just off
            n = trial % 2 ? Vec3::UnitX() : Vec3::UnitY();
            offset = 0.01 * std::round(1.5 * u(rng)) + (trial % 6 == 0 ? 0.0 : 1e-9);
        }
        n.normalize();
        const Vec3 up = (Vec3::UnitZ() - n.z() * n).normalized();
        const Vec3 along = up.cross(n);
        const Vec3 centre = Vec3(0, 0, 0.02) + offset * n;
        auto blade_down_to = [&](double depth) { // from above the sphere down to `depth`
            const Vec3 a = centre + 0.04 * up - 0.04 * along, b = centre + 0.04 * up + 0.04 * along;
            const Vec3 c = centre + depth * up - 0.04 * along,
                       d = centre + depth * up + 0.04 * along;
            return std::vector<cut::Triangle> { { a, b, c }, { b, d, c } };
        };
        const double first = 0.012 * u(rng), second = first - 0.006 - 0.004 * (u(rng) + 1);
        for (const double depth : { first, second }) {
            if (depth == second && trial % 2 == 1)
                break;
            cut::CutReport r;
            try {
                r = cut::cut_rest(f.mesh, blade_down_to(depth));
            } catch (const std::exception& e) {
                // The cutter refused this blade (the simulation undoes such a cut and says so;
                // its mesh is not this test's subject): the next trial.
                std::printf("trial %d: the cutter refused: %s\n", trial, e.what());
                ++refused;
                break;
            }
            if (!r.topology_changed)
                continue;
            f.split_after(r);
            ++cases;
            carried += depth == second;
            EXPECT_EQ(unbalanced_edges(f.e.triangles), 0)
                << "trial " << trial << " depth " << depth << "\n"
                << describe_open_edges(f.e);
            non_manifold += open_edges(f.e.triangles) > 0;
            EXPECT_NEAR(volume(f.e.rest, f.e.triangles), f.sphere_volume, 1e-9 * f.sphere_volume)
                << "trial " << trial;
            Mat3 A;
            A << 1.1, 0.2, -0.1, 0.05, 0.9, 0.3, -0.2, 0.1, 1.2;
            std::vector<Vec3> x;
            for (const Vec3& X : f.mesh.rest)
                x.push_back(A * X);
            const std::vector<Vec3> moved = f.deformed(x);
            double worst = 0;
            for (std::size_t v = 0; v < f.e.rest.size(); ++v)
                worst = std::max(worst, (moved[v] - A * f.e.rest[v]).norm());
            EXPECT_LT(worst, 1e-12) << "trial " << trial;
        }
    }
    std::printf("random planes: %d splits (%d carried on deeper), %d blades the cutter refused, "
                "%d closed surfaces with an edge that four triangles share\n",
        cases, carried, refused, non_manifold);
    EXPECT_GT(cases, 20);
    // The merged cells are not convex: a plane may cross one in several places (it falls into
    // more than two pieces; the cutter refused such blades before, 2 of these 24).
    EXPECT_EQ(refused, 0);
    // Measured: 1 of 36 (a blade 1 nm off a plane of merged cells' faces: two lips of each side
    // meet along a crack-front edge, decision 0033).
    EXPECT_LE(non_manifold, 2);
    EXPECT_GT(carried, 4);
}
