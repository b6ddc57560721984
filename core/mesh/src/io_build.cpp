// From parsed file contents to a validated Mesh; every problem is reported at its file line.
#include "io_build.hpp"

#include "polycut/common/error.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/validate.hpp"

#include <algorithm>
#include <sstream>

namespace polycut::mesh::io {
namespace {
std::string fmt(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

/// Signed volume of a raw element [m^3] and the cube of its longest edge-ish size.
std::pair<double, double> element_volume(const RawMesh& raw, const RawElement& e) {
    geometry::Aabb box;
    for (int i = 0; i < e.count; ++i)
        box.extend(raw.nodes[std::size_t(e.nodes[std::size_t(i)])]);
    const double size = box.diagonal();
    double volume = 0;
    if (e.count == 4) {
        const Vec3& a = raw.nodes[std::size_t(e.nodes[0])];
        volume = (raw.nodes[std::size_t(e.nodes[1])] - a)
                     .dot((raw.nodes[std::size_t(e.nodes[2])] - a)
                              .cross(raw.nodes[std::size_t(e.nodes[3])] - a))
            / 6.0;
    } else {
        std::vector<std::vector<Index>> loops;
        for (const auto& f : kHexFaces) {
            std::vector<Index> loop;
            for (int i : f)
                loop.push_back(e.nodes[std::size_t(i)]);
            loops.push_back(std::move(loop));
        }
        volume = geometry::polyhedron_volume(raw.nodes, loops);
    }
    return { volume, size * size * size };
}
} // namespace

Mesh build_mesh(const RawMesh& raw) {
    const std::string& path = raw.element_path;
    if (raw.elements.empty())
        throw FileError(path, 0, "no tetrahedra or hexahedra in the file");

    // Each element on its own: distinct nodes, a volume that is not zero, hexes not inverted.
    std::vector<std::vector<std::vector<Index>>> loops(raw.elements.size());
    for (std::size_t c = 0; c < raw.elements.size(); ++c) {
        RawElement e = raw.elements[c];
        const char* name = e.count == 4 ? "tetrahedron" : "hexahedron";
        std::array<Index, 8> sorted = e.nodes;
        std::sort(sorted.begin(), sorted.begin() + e.count);
        if (std::adjacent_find(sorted.begin(), sorted.begin() + e.count)
            != sorted.begin() + e.count)
            throw FileError(path, e.line, std::string(name) + " repeats a node");
        const auto [volume, size3] = element_volume(raw, e);
        if (std::abs(volume) <= 1e-12 * size3)
            throw FileError(path, e.line,
                std::string("zero-volume ") + name + " (volume " + fmt(volume) + " m^3)");
        if (e.count == 4 && volume < 0)
            std::swap(e.nodes[1], e.nodes[2]);
        if (e.count == 8 && volume < 0)
            throw FileError(path, e.line,
                "inverted hexahedron (volume " + fmt(volume)
                    + " m^3): nodes must be in gmsh/VTK order, bottom face counter-clockwise seen "
                      "from the top face");
        if (e.count == 4)
            for (const auto& f : kTetFaces)
                loops[c].push_back({ e.nodes[std::size_t(f[0])], e.nodes[std::size_t(f[1])],
                    e.nodes[std::size_t(f[2])] });
        else
            for (const auto& f : kHexFaces)
                loops[c].push_back({ e.nodes[std::size_t(f[0])], e.nodes[std::size_t(f[1])],
                    e.nodes[std::size_t(f[2])], e.nodes[std::size_t(f[3])] });
    }

    // The same element twice (same node set).
    {
        std::vector<std::pair<std::array<Index, 8>, std::size_t>> keys;
        keys.reserve(raw.elements.size());
        for (std::size_t c = 0; c < raw.elements.size(); ++c) {
            std::array<Index, 8> k;
            k.fill(kNone);
            const RawElement& e = raw.elements[c];
            std::copy(e.nodes.begin(), e.nodes.begin() + e.count, k.begin());
            std::sort(k.begin(), k.begin() + e.count);
            keys.push_back({ k, c });
        }
        std::sort(keys.begin(), keys.end());
        for (std::size_t i = 1; i < keys.size(); ++i)
            if (keys[i].first == keys[i - 1].first)
                throw FileError(path, raw.elements[keys[i].second].line,
                    "element repeats the element on line "
                        + std::to_string(raw.elements[keys[i - 1].second].line));
    }

    // Drop nodes no element uses (they would carry no mass), keeping the file order.
    std::vector<Index> new_id(raw.nodes.size(), kNone);
    for (const auto& cell : loops)
        for (const auto& loop : cell)
            for (Index n : loop)
                new_id[std::size_t(n)] = 0;
    std::vector<Vec3> rest;
    std::vector<long> node_lines;
    for (std::size_t n = 0; n < raw.nodes.size(); ++n)
        if (new_id[n] == 0) {
            new_id[n] = Index(rest.size());
            rest.push_back(raw.nodes[n]);
            node_lines.push_back(raw.node_lines[n]);
        }
    for (auto& cell : loops)
        for (auto& loop : cell)
            for (Index& n : loop)
                n = new_id[std::size_t(n)];

    Mesh mesh;
    try {
        mesh = Mesh::from_polyhedra(std::move(rest), loops);
    } catch (const MeshError& e) {
        const long line = e.cell() >= 0 ? raw.elements[std::size_t(e.cell())].line : 0;
        throw FileError(path, line, e.problem());
    }

    ValidationOptions options;
    options.planarity_tol = 1e-6;
    options.check_boundary = false;
    const auto issues = check_mesh(mesh, options);
    if (!issues.empty()) {
        const ValidationIssue& i = issues.front();
        if (i.kind == ValidationIssue::Kind::DuplicateNodes)
            throw FileError(raw.node_path, node_lines[std::size_t(i.node)],
                "node coincides with the node on line "
                    + std::to_string(node_lines[std::size_t(i.other)]));
        const long line = i.cell != kNone ? raw.elements[std::size_t(i.cell)].line : 0;
        throw FileError(path, line, std::string(kind_name(i.kind)) + ": " + i.message);
    }
    return mesh;
}

} // namespace polycut::mesh::io
