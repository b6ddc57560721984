// OFF / OBJ / STL / PLY surface files: each file is read into memory, scanned (io_scan.hpp:
// counts bounded, numbers and ids checked, errors with line or byte offset), parsed by CGAL's
// stream readers (binary OFF by the scan itself) and cross-checked; then fanned into triangles.
#include "io_scan.hpp"
#include "polycut/common/error.hpp"
#include "polycut/meshing/surface.hpp"
#include "surface_prepare.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <algorithm>
#include <bit>
#include <cctype>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

namespace polycut::meshing {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using detail::SurfaceFormat;

constexpr const char* kFormats = "expected .off, .obj, .stl or .ply";

std::optional<SurfaceFormat> format_of(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(
        ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".off")
        return SurfaceFormat::Off;
    if (ext == ".obj")
        return SurfaceFormat::Obj;
    if (ext == ".stl")
        return SurfaceFormat::Stl;
    if (ext == ".ply")
        return SurfaceFormat::Ply;
    return std::nullopt;
}

const char* name_of(SurfaceFormat f) {
    switch (f) {
    case SurfaceFormat::Off:
        return "OFF";
    case SurfaceFormat::Obj:
        return "OBJ";
    case SurfaceFormat::Stl:
        return "STL";
    case SurfaceFormat::Ply:
        return "PLY";
    }
    return "?";
}

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw FileError(path, 0, "cannot open file");
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0)
        throw FileError(path, 0, "cannot read file");
    if (size == 0)
        throw FileError(path, 0, "empty file");
    if (std::size_t(size) > detail::kMaxSurfaceFileBytes)
        throw FileError(path, 0,
            "file of " + std::to_string(size) + " bytes is larger than the "
                + std::to_string(detail::kMaxSurfaceFileBytes) + " bytes read");
    std::string bytes(std::size_t(size), '\0');
    in.seekg(0);
    if (!in.read(bytes.data(), size))
        throw FileError(path, 0, "cannot read file");
    return bytes;
}

/// CGAL's stream reader for the format on the scanned bytes; false if it fails.
bool parse_with_cgal(SurfaceFormat format, const std::string& bytes, std::vector<Point>& points,
    std::vector<std::vector<std::size_t>>& polygons) {
    std::istringstream in(bytes, std::ios::in | std::ios::binary);
    switch (format) {
    case SurfaceFormat::Off:
        return CGAL::IO::read_OFF(in, points, polygons);
    case SurfaceFormat::Obj:
        return CGAL::IO::read_OBJ(in, points, polygons);
    case SurfaceFormat::Stl:
        CGAL::IO::set_mode(in, CGAL::IO::BINARY);
        return CGAL::IO::read_STL(in, points, polygons);
    case SurfaceFormat::Ply:
        CGAL::IO::set_mode(in, CGAL::IO::BINARY);
        return CGAL::IO::read_PLY(in, points, polygons);
    }
    return false;
}

std::string located(const detail::SurfaceScan& scan, std::size_t polygon) {
    if (polygon >= scan.polygon_at.size())
        return "polygon " + std::to_string(polygon);
    return (scan.binary ? "byte " : "line ") + std::to_string(scan.polygon_at[polygon])
        + ": polygon " + std::to_string(polygon);
}

/// Binary OFF (Geomview): "OFF BINARY", big-endian int32 counts, float32 coordinates, faces as
/// int32 3, three int32 ids and an int32 colour count 0.
void write_off_binary(const std::string& path, const SurfaceMesh& s) {
    std::ofstream out(path, std::ios::binary);
    auto put = [&](auto value) {
        unsigned char buf[sizeof value];
        std::memcpy(buf, &value, sizeof value);
        if constexpr (std::endian::native == std::endian::little)
            std::reverse(buf, buf + sizeof value);
        out.write(reinterpret_cast<const char*>(buf), sizeof value);
    };
    out << "OFF BINARY\n";
    put(std::int32_t(s.positions.size()));
    put(std::int32_t(s.triangles.size()));
    put(std::int32_t(0));
    for (const Vec3& p : s.positions)
        for (int k = 0; k < 3; ++k)
            put(float(p[k]));
    for (const auto& t : s.triangles) {
        put(std::int32_t(3));
        for (Index v : t)
            put(std::int32_t(v));
        put(std::int32_t(0));
    }
    if (!out)
        throw FileError(path, 0, "cannot write file");
}

} // namespace

SurfaceMesh read_surface(const std::string& path, bool require_closed) {
    const std::optional<SurfaceFormat> format = format_of(path);
    if (!format)
        throw FileError(path, 0, std::string("unsupported surface format (") + kFormats + ")");
    const std::string bytes = read_bytes(path);
    detail::SurfaceScan scan;
    switch (*format) {
    case SurfaceFormat::Off:
        scan = detail::scan_off(path, bytes);
        break;
    case SurfaceFormat::Obj:
        scan = detail::scan_obj(path, bytes);
        break;
    case SurfaceFormat::Stl:
        scan = detail::scan_stl(path, bytes);
        break;
    case SurfaceFormat::Ply:
        scan = detail::scan_ply(path, bytes);
        break;
    }

    std::vector<Vec3> positions;
    std::vector<std::vector<std::size_t>> polygons;
    if (scan.has_soup) {
        positions = std::move(scan.points);
        polygons = std::move(scan.soup);
    } else {
        std::vector<Point> points;
        bool ok = false;
        try {
            ok = parse_with_cgal(*format, bytes, points, polygons);
        } catch (const std::exception& e) {
            throw FileError(
                path, 0, std::string("CGAL's ") + name_of(*format) + " reader failed: " + e.what());
        }
        long corners = 0;
        for (const auto& p : polygons)
            corners += long(p.size());
        if (!ok || long(polygons.size()) != scan.polygons || corners != scan.corners
            || (scan.vertices >= 0 && long(points.size()) != scan.vertices))
            throw FileError(path, 0,
                std::string("CGAL's ") + name_of(*format) + " reader "
                    + (ok ? "read " + std::to_string(points.size()) + " vertices and "
                                + std::to_string(polygons.size()) + " polygons"
                          : "failed")
                    + " where the file has " + std::to_string(scan.vertices) + " and "
                    + std::to_string(scan.polygons) + " (an unusual layout?)");
        positions.reserve(points.size());
        for (const Point& p : points)
            positions.emplace_back(p.x(), p.y(), p.z());
    }

    SurfaceMesh surface;
    surface.positions = std::move(positions);
    for (std::size_t f = 0; f < polygons.size(); ++f) {
        const auto& poly = polygons[f];
        // The scan checked sizes and ids; this guards the conversion all the same.
        if (poly.size() < 3)
            throw FileError(path, 0, located(scan, f) + " has fewer than 3 vertices");
        for (std::size_t v : poly)
            if (v >= surface.positions.size())
                throw FileError(path, 0, located(scan, f) + " uses a vertex out of range");
        // Fan triangulation: exact for planar convex polygons (the usual OBJ/OFF quads); a
        // non-convex polygon that folds shows up as a self-intersection.
        for (std::size_t k = 1; k + 1 < poly.size(); ++k)
            surface.triangles.push_back({ Index(poly[0]), Index(poly[k]), Index(poly[k + 1]) });
    }
    std::string problem
        = require_closed ? detail::prepare_closed_surface(surface) : detail::soup_problem(surface);
    if (!problem.empty())
        throw FileError(path, 0, problem);
    return surface;
}

void write_surface(const std::string& path, const SurfaceMesh& surface, SurfaceEncoding encoding) {
    const std::optional<SurfaceFormat> format = format_of(path);
    if (!format)
        throw FileError(path, 0, std::string("unsupported surface format (") + kFormats + ")");
    if (std::string problem = detail::soup_problem(surface); !problem.empty())
        throw InputError("surface", problem);
    const bool binary = encoding == SurfaceEncoding::Binary;
    if (binary && *format == SurfaceFormat::Obj)
        throw FileError(path, 0, "OBJ has no binary encoding");
    if (binary && *format == SurfaceFormat::Off) {
        write_off_binary(path, surface);
        return;
    }
    std::vector<Point> points;
    points.reserve(surface.positions.size());
    for (const Vec3& p : surface.positions)
        points.emplace_back(p.x(), p.y(), p.z());
    std::vector<std::vector<std::size_t>> polygons;
    polygons.reserve(surface.triangles.size());
    for (const auto& t : surface.triangles)
        polygons.push_back({ std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2]) });
    if (!CGAL::IO::write_polygon_soup(
            path, points, polygons, CGAL::parameters::stream_precision(17).use_binary_mode(binary)))
        throw FileError(path, 0, "cannot write file");
}

} // namespace polycut::meshing
