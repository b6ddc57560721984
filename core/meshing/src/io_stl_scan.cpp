// The structural scan of STL files. Binary: an 80-byte header, a little-endian uint32 triangle
// count and 50 bytes per triangle (normal, three corners as float32, a uint16), recognised by
// its size even when the header starts with "solid" (many exporters write that). ASCII:
// "solid ... facet ... vertex x y z (x3) ... endfacet ... endsolid", read word by word as CGAL
// does (words other than vertex and endfacet inside a facet, such as the normal, are skipped).
#include "io_scan.hpp"

namespace polycut::meshing::detail {

namespace {

SurfaceScan scan_binary(const std::string& path, std::string_view bytes, std::uint32_t count) {
    SurfaceScan scan;
    scan.binary = true;
    ByteCursor in(bytes, 84, false);
    for (std::uint32_t t = 0; t < count; ++t) {
        const std::size_t at = in.position();
        in.skip(12); // the normal: not used, and not checked
        for (int corner = 0; corner < 3; ++corner)
            for (int axis = 0; axis < 3; ++axis) {
                float x = 0;
                in.read(x);
                if (!std::isfinite(x))
                    throw byte_error(path, in.position() - 4,
                        "triangle " + std::to_string(t) + " has a non-finite coordinate");
            }
        in.skip(2);
        scan.polygon_at.push_back(long(at));
    }
    scan.polygons = long(count);
    scan.corners = 3 * scan.polygons;
    return scan;
}

SurfaceScan scan_ascii(const std::string& path, std::string_view bytes) {
    SurfaceScan scan;
    TextCursor text(bytes);
    std::string_view word;
    bool in_solid = false, solid_seen = false;
    while (text.next_token(word)) {
        if (word == "solid") {
            if (in_solid)
                throw FileError(path, text.token_line, "'solid' inside a solid");
            in_solid = true;
        } else if (word == "endsolid") {
            in_solid = false;
            solid_seen = true;
        } else if (word == "facet") {
            const long facet_line = text.token_line;
            int corners = 0;
            for (;;) {
                if (!text.next_token(word))
                    throw FileError(path, facet_line,
                        "facet " + std::to_string(scan.polygons) + " has no 'endfacet'");
                if (word == "endfacet")
                    break;
                if (word != "vertex")
                    continue;
                if (++corners > 3)
                    throw FileError(path, text.token_line,
                        "facet " + std::to_string(scan.polygons)
                            + " has more than 3 vertices (STL holds triangles)");
                for (int axis = 0; axis < 3; ++axis) {
                    double x = 0;
                    if (!text.next_token(word) || !parse_finite(word, x))
                        throw FileError(path, text.token_line,
                            "facet " + std::to_string(scan.polygons) + ": coordinate " + quote(word)
                                + " is not a finite number");
                }
            }
            if (corners != 3)
                throw FileError(path, text.token_line,
                    "facet " + std::to_string(scan.polygons) + " has " + std::to_string(corners)
                        + " vertices (STL holds triangles)");
            scan.polygon_at.push_back(facet_line);
            ++scan.polygons;
        }
    }
    if (in_solid || !solid_seen)
        throw FileError(path, text.token_line > 0 ? text.token_line : 1,
            in_solid ? "file ends inside a solid (no 'endsolid')" : "no 'solid' ... 'endsolid'");
    scan.corners = 3 * scan.polygons;
    return scan;
}

} // namespace

SurfaceScan scan_stl(const std::string& path, std::string_view bytes) {
    std::uint32_t count = 0;
    if (bytes.size() >= 84) {
        ByteCursor c(bytes, 80, false);
        c.read(count);
    }
    const bool binary_size = bytes.size() >= 84 && bytes.size() == 84 + 50 * std::size_t(count);
    std::size_t first = 0;
    while (first < bytes.size() && TextCursor::is_space(bytes[first]))
        ++first;
    const bool ascii = bytes.substr(first, 5) == "solid"
        && (first + 5 == bytes.size() || TextCursor::is_space(bytes[first + 5]));
    SurfaceScan scan;
    if (binary_size)
        scan = scan_binary(path, bytes, count);
    else if (ascii)
        scan = scan_ascii(path, bytes);
    else if (bytes.size() >= 84)
        throw byte_error(path, 80,
            "binary STL declares " + std::to_string(count) + " triangles, which take "
                + std::to_string(84 + 50 * std::size_t(count)) + " bytes, but the file has "
                + std::to_string(bytes.size()) + " (and it is not ASCII STL: no 'solid')");
    else
        throw byte_error(
            path, 0, "neither ASCII STL (no 'solid') nor binary STL (shorter than 84 bytes)");
    if (scan.polygons == 0)
        throw FileError(path, 0, "no triangles");
    return scan;
}

} // namespace polycut::meshing::detail
