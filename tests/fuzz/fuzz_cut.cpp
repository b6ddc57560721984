// libFuzzer target: geometric fuzz of the cutters (issue 14 item 6). One input is one cut
// sequence on a fresh (reset) tissue, with either cutter, on one of three meshes:
//
//   byte 0: bit 0 cutter (0 face snapping, 1 cell splitting); bits 1-2 mesh (0 tet grid
//           3 x 3 x 2, 1 hex grid 3 x 3 x 2 (always split: snapping needs tets), 2 CGAL
//           Mesh_3 sphere (tets)); bits 3-4 steps between the cut calls (0-3).
//   then records of 19 bytes: a mode byte and nine 16-bit values w[0..8]. Mode % 5:
//     0 random: corners from w, in a box 1.5x the tissue's;
//     1 in a face plane: the plane of face w0 (its first three nodes), corners around the
//       face's centre, scaled by 0.5-4.5 (w1..w3), so the blade lies exactly in a face plane;
//     2 through nodes: corners at nodes w0, w1, w2 (exactly, or nudged by 1e-12..1e-6 of the
//       tissue size when w8 is odd);
//     3 along an edge: corners 0 and 1 the two ends of edge w1 of cell w0 extended past them
//       by w2/65536 of the edge, corner 2 random;
//     4 a fan: the previous record's last corner, its centre and a random point.
//   Mode / 5 % 2 == 1 ends the current cut call after this triangle (up to 8 triangles).
//
// After each cut call, on the rest mesh (world = rest: the tissue is cut right after reset):
//   Applied / Deferred: the cut invariants (rest volume within 1e-6 plus what re-cutting
//   the not quite planar lips of earlier calls may change (split, lip_slack), or 1e-3 (snap,
//   whose skin may move by its budget)), positive cells, convex cells (split), closed oriented
//   surface, finite, consistent face table);
//   Rejected / Failed: nothing changed (state hash, cells, topology version).
// After the steps: every position finite and within 3 rest diagonals of the rest centre (plus
// the free fall since the reset: cut-free pieces fall under gravity), the energy finite. Any
// violation aborts with the input's description on stderr.
#include "impl.hpp"
#include "polycut/cut/invariants.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/simulation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

namespace polycut::sim {

struct SimulationTestPeer {
    static Simulation::Impl& impl(Simulation& s) { return *s.m_impl; }
};

} // namespace polycut::sim

namespace {

using polycut::Index;
using polycut::Vec3;
using Triangle = std::array<Vec3, 3>;

constexpr std::size_t kRecord = 19;
constexpr int kMaxTriangles = 8;

std::string scene_text(int mesh, bool split) {
    std::string geometry;
    std::string fixed;
    switch (mesh) {
    case 0:
    case 1:
        geometry = std::string(R"({"type": "box", "origin": [0, 0, 0], "size": [0.03, 0.03, 0.02],
                   "cells": [3, 3, 2], "elements": ")")
            + (mesh == 0 ? "tet" : "hex") + "\"}";
        fixed = R"({"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}})";
        break;
    default:
        geometry = R"({"type": "implicit", "shape": "sphere", "radius": 0.015,
                   "center": [0.015, 0.015, 0.015], "cell_size": 0.008, "seed": 0})";
        fixed = R"({"box": {"min": [0, 0, -0.01], "max": [0.03, 0.03, 0.004]}})";
        break;
    }
    // Cell splitting makes polyhedra: the polyhedral (MVC) basis. Snapping keeps tets: P1.
    const std::string method = split ? "mvc" : "tet";
    return std::string(R"({"name": "fuzz_cut", "geometry": )") + geometry + R"(,
      "method": ")"
        + method + R"(",
      "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.45, "density": 1000,
                   "rayleigh_stiffness": 0.02},
      "integrator": {"type": "implicit_euler", "dt": 0.0166667, "corotated": true},
      "solver": {"type": "pcg", "preconditioner": "jacobi", "tolerance": 1e-8},
      "loads": {"gravity": [0, 0, -9.81]},
      "fixed": [)"
        + fixed + R"(],
      "cutting": {"method": ")"
        + (split ? "split" : "snap") + R"("}})";
}

struct Tissue {
    std::unique_ptr<polycut::sim::Simulation> sim;
    double volume = 0; ///< rest volume of the uncut mesh [m^3]
    Vec3 lo, hi; ///< rest bounding box [m]
};

Tissue& tissue(int mesh, bool split) {
    static Tissue tissues[3][2];
    Tissue& t = tissues[mesh][split ? 1 : 0];
    if (!t.sim) {
        t.sim = std::make_unique<polycut::sim::Simulation>(
            polycut::scene::parse_scene(scene_text(mesh, split)));
        const auto& m = polycut::sim::SimulationTestPeer::impl(*t.sim).initial_mesh;
        t.volume = m.rest_volume();
        t.lo = t.hi = m.rest.front();
        for (const Vec3& p : m.rest) {
            t.lo = t.lo.cwiseMin(p);
            t.hi = t.hi.cwiseMax(p);
        }
    }
    return t;
}

/// How much a cut call may change the rest volume through the snapping rule [m^3]: the lips of
/// earlier cuts (tag 2) are planar only to within the nodes snapped onto the sweep plane but not
/// moved onto it (`cutting.snap_distance` x the cell thickness; decision 0057 moves them where
/// it can). Splitting such a face along a chord replaces its surface by one within the same
/// slab, so the enclosed volume changes by at most 2 x (distance from its plane) x its area.
/// The original skin stays planar (skin nodes move only within it; edge splits are on edges).
double lip_slack(const polycut::mesh::Mesh& m) {
    double slack = 0;
    for (const polycut::mesh::Face& f : m.faces) {
        if (f.tag != polycut::mesh::FaceTag::Cut || f.nodes.size() < 4) {
            continue; // a triangle is planar
        }
        const auto loop = polycut::geometry::gather(m.rest, f.nodes);
        Vec3 centre = Vec3::Zero();
        for (const Vec3& p : loop) {
            centre += p;
        }
        centre /= double(loop.size());
        const Vec3 normal = polycut::geometry::polygon_normal(loop).normalized();
        double off = 0;
        for (const Vec3& p : loop) {
            off = std::max(off, std::abs((p - centre).dot(normal)));
        }
        slack += 2 * off * polycut::geometry::polygon_area(loop);
    }
    return slack;
}

[[noreturn]] void fail(const char* what, const std::string& detail) {
    std::fprintf(stderr, "fuzz_cut: %s: %s\n", what, detail.c_str());
    std::abort();
}

/// Reads the records into cut calls of at most kMaxTriangles triangles each.
std::vector<std::vector<Triangle>> read_calls(
    const std::uint8_t* data, std::size_t size, const polycut::mesh::Mesh& m, const Tissue& t) {
    std::vector<std::vector<Triangle>> calls(1);
    const Vec3 extent = t.hi - t.lo;
    const double scale = extent.norm();
    Triangle previous { t.lo, t.hi, t.lo };
    int total = 0;
    for (std::size_t off = 1; off + kRecord <= size && total < 4 * kMaxTriangles; off += kRecord) {
        const int mode = data[off];
        std::uint16_t w[9];
        std::memcpy(w, data + off + 1, sizeof w);
        auto unit = [&](int k) { return double(w[k]) / 65535.0; };
        auto random_point = [&](int k) {
            Vec3 p;
            for (int a = 0; a < 3; ++a) {
                p[a] = t.lo[a] + (-0.25 + 1.5 * unit((k + a) % 9)) * extent[a];
            }
            return p;
        };
        auto node = [&](int k) { return m.rest[std::size_t(w[k] % m.rest.size())]; };
        Triangle tri;
        switch (mode % 5) {
        case 0:
            tri = { random_point(0), random_point(3), random_point(6) };
            break;
        case 1: {
            const auto& f = m.faces[std::size_t(w[0] % m.faces.size())];
            const Vec3 a = m.rest[std::size_t(f.nodes[0])], b = m.rest[std::size_t(f.nodes[1])],
                       c = m.rest[std::size_t(f.nodes[2])];
            const Vec3 centre = (a + b + c) / 3.0;
            tri = { centre + (0.5 + 4.0 * unit(1)) * (a - centre),
                centre + (0.5 + 4.0 * unit(2)) * (b - centre),
                centre + (0.5 + 4.0 * unit(3)) * (c - centre) };
            break;
        }
        case 2: {
            tri = { node(0), node(1), node(2) };
            if (w[8] % 2 == 1) {
                const double nudge = scale * std::pow(10.0, -12.0 + 6.0 * unit(7));
                tri[0].z() += nudge;
                tri[1].x() -= nudge;
            }
            break;
        }
        case 3: {
            const auto& cell = m.cells[std::size_t(w[0] % m.cells.size())];
            const std::size_t n = cell.nodes.size();
            const Vec3 a = m.rest[std::size_t(cell.nodes[w[1] % n])];
            const Vec3 b = m.rest[std::size_t(cell.nodes[(w[1] / n + 1 + w[1]) % n])];
            const double past = unit(2);
            tri = { a - past * (b - a), b + past * (b - a), random_point(3) };
            break;
        }
        default:
            tri = { previous[2], (previous[0] + previous[1] + previous[2]) / 3.0, random_point(0) };
            break;
        }
        previous = tri;
        calls.back().push_back(tri);
        ++total;
        if ((mode / 5) % 2 == 1 || int(calls.back().size()) == kMaxTriangles) {
            calls.emplace_back();
        }
    }
    if (calls.back().empty()) {
        calls.pop_back();
    }
    return calls;
}

std::string describe(const Triangle& t) {
    char text[256];
    std::snprintf(text, sizeof text,
        "[[%.17g,%.17g,%.17g],[%.17g,%.17g,%.17g],[%.17g,%.17g,%.17g]]", t[0].x(), t[0].y(),
        t[0].z(), t[1].x(), t[1].y(), t[1].z(), t[2].x(), t[2].y(), t[2].z());
    return text;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using Status = polycut::sim::CutSummary::Status;
    if (size < 1 + kRecord) {
        return 0;
    }
    const bool split = (data[0] & 1) != 0;
    const int mesh = ((data[0] >> 1) & 3) % 3;
    const int steps = (data[0] >> 3) & 3;
    Tissue& t = tissue(mesh, split || mesh == 1);
    polycut::sim::Simulation& sim = *t.sim;
    sim.reset();
    auto& impl = polycut::sim::SimulationTestPeer::impl(sim);
    const auto calls = read_calls(data, size, impl.initial_mesh, t);
    polycut::cut::InvariantOptions io;
    const bool snapping = !(split || mesh == 1);
    io.require_convex = !snapping;
    double slack = 0; // [m^3] the volume the snapping rule allows to drift so far (lip_slack)
    const Vec3 centre = 0.5 * (t.lo + t.hi);
    const double diagonal = (t.hi - t.lo).norm();
    for (std::size_t k = 0; k < calls.size(); ++k) {
        const auto hash = sim.state_hash();
        const auto cells = sim.cell_count();
        const auto topology = sim.topology_version();
        // Blades are in rest space only before the first step (world = rest at tick 0).
        const double lips_before = snapping ? 0.0 : lip_slack(impl.mesh);
        const polycut::sim::CutSummary r = sim.cut(calls[k]);
        const std::string where = "call " + std::to_string(k) + " first triangle "
            + describe(calls[k].front()) + " status " + std::to_string(int(r.status)) + " "
            + r.reason;
        if (r.status == Status::Rejected || r.status == Status::Failed) {
            if (std::getenv("FUZZ_CUT_VERBOSE") != nullptr) {
                std::fprintf(
                    stderr, "call %zu: refused (%d): %s\n", k, int(r.status), r.reason.c_str());
            }
            if (sim.state_hash() != hash || sim.cell_count() != cells
                || sim.topology_version() != topology) {
                fail("a refused cut changed the state", where);
            }
        } else {
            // the lips this call made may have been split by its later triangles: their pieces
            // are as far from planar and cover the same area
            slack += std::max(lips_before, snapping ? 0.0 : lip_slack(impl.mesh));
            io.volume_tol = snapping ? 1e-3 : 1e-6 + slack / t.volume;
            const auto inv = polycut::cut::check_cut_invariants(impl.mesh, t.volume, io);
            if (std::getenv("FUZZ_CUT_VERBOSE") != nullptr) {
                std::fprintf(stderr, "call %zu: rest volume error %.3g, allowed %.3g (relative)\n",
                    k, inv.volume_error, io.volume_tol);
            }
            if (!inv.ok()) {
                fail("cut invariants", where + ": " + inv.first_problem);
            }
        }
        for (int s = 0; s < steps; ++s) {
            // A step that fails after a cut undoes it: the undo itself must not fail (with
            // POLYCUT_CHECK_UNDO=1 that includes the model's pattern against a full build).
            for (const std::string& w : sim.step().warnings) {
                if (w.find("could not be undone") != std::string::npos) {
                    fail("undo after a failed step", where + ": " + w);
                }
            }
        }
        // A piece the cuts freed falls under gravity: allow the free fall since the reset.
        const double fall = 0.5 * 9.81 * sim.time() * sim.time();
        for (const Vec3& p : sim.positions()) {
            if (!p.allFinite() || (p - centre).norm() > 3 * diagonal + fall) {
                fail("a position went non-finite or far away", where);
            }
        }
        if (!std::isfinite(sim.energy().total())) {
            fail("non-finite energy", where);
        }
    }
    return 0;
}
