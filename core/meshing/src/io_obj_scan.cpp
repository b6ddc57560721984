// The structural scan of Wavefront OBJ surfaces, line by line as CGAL's read_OBJ reads them:
// "v x y z", "f i j k ..." (1-based ids, "i/t/n" forms), statements CGAL skips, and comments.
#include "io_scan.hpp"

#include <array>

namespace polycut::meshing::detail {

namespace {

/// Statements CGAL's OBJ reader accepts and ignores (besides v, vt, vn, f and '#').
constexpr std::array<std::string_view, 42> kIgnored { "vp", "bevel", "lod", "ctech", "c_interp",
    "usemap", "usemtl", "stech", "d_interp", "mtllib", "shadow_obj", "trace_obj", "o", "g", "s",
    "p", "cstype", "deg", "step", "bmat", "con", "curv", "curv2", "surf", "parm", "trim", "hole",
    "scrv", "sp", "end", "surf_1", "q0_1", "q1_1", "curv2d_1", "surf_2", "q0_2", "q1_2", "curv2d_2",
    "bsp", "bzp", "cdc", "cdp" };

bool ignored(std::string_view keyword) {
    if (keyword == "res" || keyword == "vt" || keyword == "vn" || keyword.front() == '#')
        return true;
    for (std::string_view k : kIgnored)
        if (k == keyword)
            return true;
    return false;
}

} // namespace

SurfaceScan scan_obj(const std::string& path, std::string_view bytes) {
    SurfaceScan scan;
    scan.vertices = 0;
    TextCursor text(bytes);
    std::string_view line;
    // Face ids are checked once all vertices are known (CGAL resolves them at the end).
    long long max_id = 0;
    long max_id_line = 0;
    while (text.next_line(line)) {
        const std::vector<std::string_view> tokens = split_tokens(line);
        if (tokens.empty())
            continue;
        const std::string_view keyword = tokens[0];
        if (keyword == "v") {
            double x = 0;
            for (std::size_t k = 1; k <= 3; ++k)
                if (k >= tokens.size() || !parse_finite(tokens[k], x))
                    throw FileError(path, text.line(),
                        "vertex " + std::to_string(scan.vertices + 1) + ": "
                            + (k >= tokens.size() ? "fewer than 3 coordinates"
                                                  : "coordinate " + quote(tokens[k])
                                        + " is not a finite number"));
            ++scan.vertices;
        } else if (keyword == "f") {
            const long n = long(tokens.size()) - 1;
            if (n < 3 || n > kMaxPolygonVertices)
                throw FileError(path, text.line(),
                    "face " + std::to_string(scan.polygons + 1) + " has " + std::to_string(n)
                        + " vertices (3 to " + std::to_string(kMaxPolygonVertices) + ")");
            for (std::size_t k = 1; k < tokens.size(); ++k) {
                // "i", "i/t", "i//n" or "i/t/n": the vertex id is the part before the slash.
                const std::string_view id_text = tokens[k].substr(0, tokens[k].find('/'));
                long long id = 0;
                if (!parse_integer(id_text, id) || id == 0 || id > (1LL << 31) - 1)
                    throw FileError(path, text.line(),
                        "face " + std::to_string(scan.polygons + 1) + ": vertex id "
                            + quote(tokens[k]) + " is not a positive integer (OBJ ids start at 1)");
                if (id < 0)
                    throw FileError(path, text.line(),
                        "face " + std::to_string(scan.polygons + 1)
                            + ": relative (negative) vertex ids are not supported");
                if (id > max_id) {
                    max_id = id;
                    max_id_line = text.line();
                }
            }
            scan.polygon_at.push_back(text.line());
            scan.corners += n;
            ++scan.polygons;
        } else if (!ignored(keyword)) {
            throw FileError(path, text.line(), "unknown OBJ statement " + quote(keyword));
        }
    }
    if (scan.polygons == 0)
        throw FileError(path, text.line(), "no faces ('f' lines)");
    if (max_id > scan.vertices)
        throw FileError(path, max_id_line,
            "vertex id " + std::to_string(max_id) + " is out of range [1, "
                + std::to_string(scan.vertices) + "]");
    return scan;
}

} // namespace polycut::meshing::detail
