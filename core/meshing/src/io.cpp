// OFF / OBJ / STL surface files through CGAL's polygon soup IO, with the checks meshing needs.
#include "polycut/common/error.hpp"
#include "polycut/meshing/surface.hpp"
#include "surface_prepare.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <algorithm>
#include <cctype>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <vector>

namespace polycut::meshing {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

/// Lower-case extension with the dot ("off"), or "" if the format is not supported.
std::string supported_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(
        ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".off" || ext == ".obj" || ext == ".stl")
        return ext;
    return {};
}

} // namespace

SurfaceMesh read_surface(const std::string& path, bool require_closed) {
    const std::string ext = supported_extension(path);
    if (ext.empty())
        throw FileError(path, 0, "unsupported surface format (expected .off, .obj or .stl)");
    {
        std::ifstream probe(path, std::ios::binary);
        if (!probe)
            throw FileError(path, 0, "cannot open file");
        if (probe.peek() == std::ifstream::traits_type::eof())
            throw FileError(path, 0, "empty file");
    }
    std::vector<Point> points;
    std::vector<std::vector<std::size_t>> polygons;
    bool ok = false;
    try {
        ok = CGAL::IO::read_polygon_soup(path, points, polygons);
    } catch (const std::exception& e) {
        throw FileError(path, 0, std::string("cannot parse: ") + e.what());
    }
    if (!ok)
        throw FileError(path, 0, "cannot parse as " + ext.substr(1) + " surface");
    if (polygons.empty())
        throw FileError(path, 0, "no polygons");

    SurfaceMesh surface;
    surface.positions.reserve(points.size());
    for (const Point& p : points)
        surface.positions.emplace_back(p.x(), p.y(), p.z());
    for (std::size_t f = 0; f < polygons.size(); ++f) {
        const auto& poly = polygons[f];
        if (poly.size() < 3)
            throw FileError(path, 0,
                "polygon " + std::to_string(f) + " has " + std::to_string(poly.size())
                    + " vertices");
        for (std::size_t v : poly)
            if (v >= points.size())
                throw FileError(path, 0,
                    "polygon " + std::to_string(f) + " uses vertex " + std::to_string(v)
                        + ", out of range [0, " + std::to_string(points.size()) + ")");
        // Fan triangulation: exact for planar convex polygons (the usual OBJ/OFF quads); a
        // non-convex polygon that folds shows up as a self-intersection below.
        for (std::size_t k = 1; k + 1 < poly.size(); ++k)
            surface.triangles.push_back({ Index(poly[0]), Index(poly[k]), Index(poly[k + 1]) });
    }
    std::string problem
        = require_closed ? detail::prepare_closed_surface(surface) : detail::soup_problem(surface);
    if (!problem.empty())
        throw FileError(path, 0, problem);
    return surface;
}

void write_surface(const std::string& path, const SurfaceMesh& surface) {
    if (supported_extension(path).empty())
        throw FileError(path, 0, "unsupported surface format (expected .off, .obj or .stl)");
    if (std::string problem = detail::soup_problem(surface); !problem.empty())
        throw InputError("surface", problem);
    std::vector<Point> points;
    points.reserve(surface.positions.size());
    for (const Vec3& p : surface.positions)
        points.emplace_back(p.x(), p.y(), p.z());
    std::vector<std::vector<std::size_t>> polygons;
    polygons.reserve(surface.triangles.size());
    for (const auto& t : surface.triangles)
        polygons.push_back({ std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2]) });
    if (!CGAL::IO::write_polygon_soup(
            path, points, polygons, CGAL::parameters::stream_precision(17)))
        throw FileError(path, 0, "cannot write file");
}

} // namespace polycut::meshing
