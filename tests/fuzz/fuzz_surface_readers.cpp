// libFuzzer target: the surface readers, OFF / STL / PLY / OBJ in every encoding (issue 14 item
// 6). Byte 0 picks the extension (bits 0-1: .off .stl .ply .obj; bit 2: upper case, which the
// readers must accept too); the rest is the file. read_surface() runs with and without
// require_closed and must return a surface that keeps its documented promises or throw a
// FileError naming the file; anything else (another exception, a crash, a sanitizer report)
// is a finding. A small surface read without require_closed also goes through the PMP repair,
// whose result must be closed or an InputError. A tiny one (at most kMaxWrapTriangles) also
// goes through the Alpha_wrap_3 wrap at a coarse alpha (a quarter of its bounding box), whose
// result must be closed or an InputError, and that wrap through Mesh_3 at a coarse size without
// optimisers, which must give tets of positive volume or throw InputError / MeshError: both stay
// in milliseconds at that size, where the organ-sized runs of the scenes take seconds.
#include "polycut/common/error.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polycut/meshing/options.hpp"
#include "polycut/meshing/repair.hpp"
#include "polycut/meshing/surface.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

using polycut::meshing::SurfaceMesh;

// Inputs larger than this are skipped: the scans are linear, and bigger files only slow the
// fuzzer down without reaching new code.
constexpr std::size_t kMaxInputBytes = 64 * 1024;
// PMP repair (hole filling, self-intersection removal) stays in milliseconds up to here.
constexpr std::size_t kMaxRepairTriangles = 300;
// The wrap and Mesh_3 of a surface this small, at a quarter of its bounding box, too.
constexpr std::size_t kMaxWrapTriangles = 40;

[[noreturn]] void finding(const std::string& what) {
    std::fprintf(stderr, "fuzz_surface_readers: %s\n", what.c_str());
    std::abort();
}

/// What every surface read_surface() returns promises: triangles, finite positions, ids in
/// range; with require_closed also a clean closed surface.
void check_surface(const SurfaceMesh& s, bool closed, const char* who) {
    if (s.triangles.empty())
        finding(std::string(who) + " returned no triangles");
    for (const auto& p : s.positions)
        if (!p.allFinite())
            finding(std::string(who) + " returned a non-finite position");
    for (const auto& t : s.triangles)
        for (polycut::Index v : t)
            if (v < 0 || std::size_t(v) >= s.positions.size())
                finding(std::string(who) + " returned a vertex id out of range: "
                    + std::to_string(v) + " of " + std::to_string(s.positions.size()));
    // The orientation is not checked through enclosed_volume(): its double sum loses the sign
    // for tiny or far-off surfaces that exact predicates orient correctly.
    if (closed) {
        if (const std::string problem = polycut::meshing::closed_surface_problem(s);
            !problem.empty())
            finding(std::string(who) + " returned a surface that is not clean: " + problem);
    }
}

/// The PMP repair of a surface read without require_closed: a clean surface or InputError.
void check_repair(const SurfaceMesh& s) {
    polycut::meshing::RepairOptions options;
    options.mode = polycut::meshing::RepairMode::Pmp;
    try {
        const SurfaceMesh repaired = polycut::meshing::repair_surface(s, options, 1.0);
        check_surface(repaired, true, "repair_surface");
    } catch (const polycut::InputError&) {
        // PMP could not make it clean: the documented outcome
    } catch (const std::exception& e) {
        finding(std::string("repair_surface threw something else than InputError: ") + e.what());
    }
}

/// The wrap of a tiny surface at a quarter of its bounding box (a clean surface or InputError),
/// and that wrap's tets (positive volumes, or InputError / MeshError).
void check_wrap_and_mesh(const SurfaceMesh& s) {
    polycut::geometry::Aabb box;
    for (const auto& p : s.positions)
        box.extend(p);
    const double cell = box.diagonal() / 4;
    polycut::meshing::RepairOptions options;
    options.mode = polycut::meshing::RepairMode::Wrap;
    SurfaceMesh wrapped;
    try {
        wrapped = polycut::meshing::repair_surface(s, options, cell);
        check_surface(wrapped, true, "repair_surface (wrap)");
    } catch (const polycut::InputError&) {
        return; // refused (a flat or degenerate input, a size out of range): documented
    } catch (const std::exception& e) {
        finding(std::string("the wrap threw something else than InputError: ") + e.what());
    }
    polycut::meshing::MeshingOptions mo;
    mo.cell_size = cell;
    mo.perturb = false;
    mo.exude = false;
    mo.refine_time_limit = 2; // under libFuzzer's -timeout: a refinement that does not finish
                              // must end in the documented InputError, not a hang
    try {
        const polycut::mesh::Mesh m = polycut::meshing::mesh_surface(wrapped, mo);
        if (m.num_cells() == 0)
            finding("mesh_surface returned no cell");
        for (polycut::Index c = 0; c < m.num_cells(); ++c)
            if (!(m.cell_volume(c) > 0)) {
                char text[96];
                std::snprintf(text, sizeof text, "mesh_surface returned a tet of volume %.3g",
                    m.cell_volume(c));
                finding(text);
            }
    } catch (const polycut::InputError&) {
    } catch (const polycut::MeshError&) {
    } catch (const std::exception& e) {
        finding(std::string("mesh_surface threw something else than InputError or MeshError: ")
            + e.what());
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0 || size > kMaxInputBytes) {
        return 0;
    }
    static const char* const kExtensions[] = { ".off", ".stl", ".ply", ".obj" };
    static const char* const kUpper[] = { ".OFF", ".STL", ".PLY", ".OBJ" };
    const int format = data[0] & 3;
    const bool upper = (data[0] & 4) != 0;
    const std::string path = (std::filesystem::temp_directory_path()
                                 / ("polycut_fuzz_surface_" + std::to_string(::getpid())))
                                 .string()
        + (upper ? kUpper[format] : kExtensions[format]);
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));

    // With the replay driver's POLYCUT_REPLAY_VERBOSE, each outcome is printed (seed review).
    const bool verbose = std::getenv("POLYCUT_REPLAY_VERBOSE") != nullptr;
    for (const bool require_closed : { false, true }) {
        try {
            const SurfaceMesh s = polycut::meshing::read_surface(path, require_closed);
            check_surface(s, require_closed, "read_surface");
            if (verbose)
                std::fprintf(stderr, "  require_closed=%d: %zu triangles\n", int(require_closed),
                    s.triangles.size());
            if (!require_closed && s.triangles.size() <= kMaxRepairTriangles)
                check_repair(s);
            if (!require_closed && s.triangles.size() <= kMaxWrapTriangles)
                check_wrap_and_mesh(s);
        } catch (const polycut::FileError& e) {
            if (e.path() != path)
                finding("FileError names '" + e.path() + "', not the file read: " + e.what());
            if (verbose)
                std::fprintf(stderr, "  require_closed=%d: %s\n", int(require_closed), e.what());
        } catch (const std::exception& e) {
            finding(std::string("read_surface threw something else than FileError: ") + e.what());
        } catch (...) {
            finding("read_surface threw a non-exception");
        }
    }
    return 0;
}
