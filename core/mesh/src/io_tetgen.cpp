// TetGen .node/.ele reader (file formats as in the TetGen 1.6 manual, sec. 5.2.1 and 5.2.4).
#include "polycut/mesh/io_tetgen.hpp"

#include "io_build.hpp"
#include "io_text.hpp"

#include <filesystem>

namespace polycut::mesh {
namespace {
constexpr long kMaxCount = std::numeric_limits<Index>::max() / 8;

/// Fails if the file holds anything after the records its header announced.
void expect_end(io::LineReader& in, long count, const char* what) {
    if (in.next())
        in.fail("extra data after " + std::to_string(count) + " " + what
            + " (the header count is too small?)");
}
} // namespace

Mesh read_tetgen(const std::string& path) {
    std::filesystem::path base(path);
    if (base.extension() == ".node" || base.extension() == ".ele")
        base.replace_extension();
    io::RawMesh raw;
    raw.node_path = base.string() + ".node";
    raw.element_path = base.string() + ".ele";

    // .node: <#points> <dimension = 3> <#attributes> <boundary markers 0|1>, then
    // <point #> <x> <y> <z> [attributes] [marker].
    io::LineReader nodes(raw.node_path, '#');
    nodes.next_or_fail("(empty .node file)");
    nodes.expect_tokens(4, ".node header (#points, dimension, #attributes, #markers)");
    const long num_points = nodes.integer(0, "number of points", 0, kMaxCount);
    if (num_points == 0)
        nodes.fail("no points (points in a .poly file are not supported)");
    const long dim = nodes.integer(1, "dimension", 0, 1000);
    if (dim != 3)
        nodes.fail("dimension " + std::to_string(dim) + " is not supported (only 3)");
    const long num_attributes = nodes.integer(2, "number of attributes", 0, 10000);
    const long markers = nodes.integer(3, "boundary marker flag", 0, 1);
    const std::size_t point_tokens = std::size_t(1 + 3 + num_attributes + markers);
    long first = 0;
    raw.nodes.reserve(std::size_t(std::min(num_points, 1L << 20)));
    for (long i = 0; i < num_points; ++i) {
        nodes.next_or_fail("after " + std::to_string(i) + " of " + std::to_string(num_points)
            + " points (truncated file or wrong count)");
        nodes.expect_tokens(point_tokens, "point");
        const long id = nodes.integer(0, "point number");
        if (i == 0) {
            if (id != 0 && id != 1)
                nodes.fail("first point number is " + std::to_string(id) + " (must be 0 or 1)");
            first = id;
        } else if (id != first + i) {
            nodes.fail("point number " + std::to_string(id) + " out of sequence (expected "
                + std::to_string(first + i) + ")");
        }
        raw.nodes.emplace_back(nodes.real(1, "x coordinate"), nodes.real(2, "y coordinate"),
            nodes.real(3, "z coordinate"));
        for (long a = 0; a < num_attributes; ++a)
            nodes.real(std::size_t(4 + a), "point attribute");
        if (markers)
            nodes.integer(std::size_t(4 + num_attributes), "boundary marker");
        raw.node_lines.push_back(nodes.line());
    }
    expect_end(nodes, num_points, "points");

    // .ele: <#tets> <nodes per tet 4|10> <#attributes>, then <tet #> <n1> ... [attributes].
    io::LineReader ele(raw.element_path, '#');
    ele.next_or_fail("(empty .ele file)");
    ele.expect_tokens(3, ".ele header (#tetrahedra, nodes per tetrahedron, #attributes)");
    const long num_tets = ele.integer(0, "number of tetrahedra", 0, kMaxCount);
    if (num_tets == 0)
        ele.fail("no tetrahedra");
    const long per_tet = ele.integer(1, "nodes per tetrahedron", 4, 10);
    if (per_tet != 4 && per_tet != 10)
        ele.fail("nodes per tetrahedron must be 4 or 10, not " + std::to_string(per_tet));
    const long tet_attributes = ele.integer(2, "number of attributes", 0, 10000);
    raw.elements.reserve(std::size_t(std::min(num_tets, 1L << 20)));
    for (long i = 0; i < num_tets; ++i) {
        ele.next_or_fail("after " + std::to_string(i) + " of " + std::to_string(num_tets)
            + " tetrahedra (truncated file or wrong count)");
        ele.expect_tokens(std::size_t(1 + per_tet + tet_attributes), "tetrahedron");
        ele.integer(0, "tetrahedron number");
        io::RawElement e;
        e.count = 4;
        e.line = ele.line();
        for (long k = 0; k < per_tet; ++k) {
            const long n = ele.integer(std::size_t(1 + k), "node", first, first + num_points - 1);
            if (k < 4)
                e.nodes[std::size_t(k)] = Index(n - first);
        }
        for (long a = 0; a < tet_attributes; ++a)
            ele.real(std::size_t(1 + per_tet + a), "region attribute");
        raw.elements.push_back(e);
    }
    expect_end(ele, num_tets, "tetrahedra");
    return io::build_mesh(raw);
}

} // namespace polycut::mesh
